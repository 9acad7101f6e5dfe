// TextSpool: a run's growing log kept out of memory and read back whole (issue 33).

#include "ocg/core/text_spool.h"

#include <gtest/gtest.h>

namespace ocg {
namespace {

TEST(TextSpool, ReadsBackEverythingAppendedAndKeepsAppendingAfterARead) {
  TextSpool spool;
  std::string expected;
  for (int i = 0; i < 2000; ++i) {
    const std::string line = "{\"keyframe\": " + std::to_string(i) + "}\n";
    spool.Append(line);
    expected += line;
    if (i == 1000) {
      EXPECT_EQ(spool.Text(), expected);  // a read in between
    }
  }
  EXPECT_EQ(spool.size(), expected.size());
  EXPECT_EQ(spool.Text(), expected);
  spool.Clear();
  EXPECT_TRUE(spool.empty());
  spool.Append("again\n");
  EXPECT_EQ(spool.Text(), "again\n");
}

}  // namespace
}  // namespace ocg
