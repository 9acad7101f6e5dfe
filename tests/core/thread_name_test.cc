#include "ocg/core/thread_name.h"

#include <gtest/gtest.h>

#include <string>
#include <thread>

namespace ocg {
namespace {

#if defined(__linux__)
TEST(ThreadName, NamesTheCallingThreadOnly) {
  const std::string before = ThisThreadName();
  std::string inside;
  std::thread worker([&inside] {
    NameThisThread("local_mapping");
    inside = ThisThreadName();
  });
  worker.join();
  EXPECT_EQ(inside, "local_mapping");
  EXPECT_EQ(ThisThreadName(), before);
}

TEST(ThreadName, ALongNameIsCutToWhatLinuxKeeps) {
  std::string inside;
  std::thread worker([&inside] {
    NameThisThread("a_name_longer_than_fifteen_characters");
    inside = ThisThreadName();
  });
  worker.join();
  EXPECT_EQ(inside, "a_name_longer_t");
}
#endif

}  // namespace
}  // namespace ocg
