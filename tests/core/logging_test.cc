#include <gtest/gtest.h>

#include "ocg/core/logging.h"

namespace ocg {
namespace {

TEST(Logging, RejectsUnknownLevel) {
  EXPECT_NO_THROW(ConfigureLogging("warn"));
  EXPECT_NO_THROW(ConfigureLogging("off"));
  EXPECT_THROW(ConfigureLogging("loud"), std::invalid_argument);
  ConfigureLogging("info");
}

TEST(Progress, FormatsCountRateAndEta) {
  const ProgressLine progress("frames", 200, false);
  // 50 frames in 10 s: 5 fps, 150 left, 30 s to go.
  EXPECT_EQ(progress.Format(50, 10.0), "frames 50/200 (25.0%)  5.0 fps  ETA 30s");
  EXPECT_EQ(ProgressLine("kf", 0, false).Format(7, 2.0), "kf 7  3.5 fps");
  EXPECT_NE(ProgressLine("f", 10000, false).Format(100, 10.0).find("ETA 16m30s"),
            std::string::npos);
}

TEST(Progress, DisabledWhenStdoutIsNotATerminal) {
  // Test runners capture stdout, so the automatic choice must be "off".
  ProgressLine progress("frames", 10);
  EXPECT_FALSE(progress.enabled());
}

}  // namespace
}  // namespace ocg
