#include <gtest/gtest.h>

#include "ocg/core/file_io.h"
#include "ocg/io/text_lines.h"
#include "ocg/io/trajectory.h"
#include "test_support.h"

namespace ocg {
namespace {

std::string WriteFixture(const std::string& text) {
  const std::string path = testing::MakeTempDir("trajectory") + "/traj.txt";
  WriteFileAtomically(path, text);
  return path;
}

TEST(TumTrajectory, RoundTripKeepsTimestampTextAndPose) {
  std::vector<StampedPose> poses(2);
  poses[0].timestamp = 1341847980.722988;
  poses[0].timestamp_text = "1341847980.722988";
  poses[0].T_wc = SE3::Exp((Vector6d() << 1, 2, 3, 0.1, 0.2, 0.3).finished());
  poses[1].timestamp = 1341847982.5;  // no text: written with 6 decimals
  const std::string path = WriteFixture("");
  WriteTumTrajectory(path, poses);
  const auto read = ReadTumTrajectory(path);
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[0].timestamp_text, "1341847980.722988");
  EXPECT_EQ(read[1].timestamp_text, "1341847982.500000");
  EXPECT_TRUE(read[0].T_wc.Matrix().isApprox(poses[0].T_wc.Matrix(), 1e-8));
}

TEST(TumTrajectory, CommentsBlankLinesAndCrlfAreAccepted) {
  const auto poses =
      ReadTumTrajectory(WriteFixture("# header\n\n1.0 0 0 0 0 0 0 1\r\n2.0 1 0 0 0 0 0 1"));
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_DOUBLE_EQ(poses[1].T_wc.translation().x(), 1.0);
}

TEST(TumTrajectory, MalformedLinesNameFileAndLine) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"# c\n1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n", ":3: expected 8 fields"},
      {"1 0 0 zero 0 0 0 1\n", ":1: tz must be a number"},
      {"1 0 0 0 0 0 0 2\n", ":1: quaternion"}};
  for (const auto& [text, expected] : cases) {
    const std::string path = WriteFixture(text);
    try {
      ReadTumTrajectory(path);
      FAIL() << "accepted: " << text;
    } catch (const ParseError& error) {
      EXPECT_NE(std::string(error.what()).find(path + expected), std::string::npos) << error.what();
    }
  }
  EXPECT_THROW(ReadTumTrajectory("/nonexistent/traj.txt"), FileError);
}

}  // namespace
}  // namespace ocg

namespace ocg {
namespace {

TEST(PoseAtTime, InterpolatesBetweenPosesAndFallsBackToTheNearest) {
  std::vector<StampedPose> poses(3);
  poses[0].timestamp = 1.0;
  poses[0].T_wc = SE3(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, 0));
  poses[1].timestamp = 1.05;
  poses[1].T_wc = SE3(Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ())),
                      Eigen::Vector3d(1, 0, 0));
  poses[2].timestamp = 2.0;  // 0.95 s after the previous one: too far to interpolate
  poses[2].T_wc = SE3(Eigen::Quaterniond::Identity(), Eigen::Vector3d(5, 0, 0));
  const std::optional<SE3> middle = PoseAtTime(poses, 1.025);
  ASSERT_TRUE(middle.has_value());
  const SE3 T_wc = middle->Inverse();
  EXPECT_TRUE(T_wc.translation().isApprox(Eigen::Vector3d(0.5, 0, 0)));
  EXPECT_NEAR(Eigen::AngleAxisd(T_wc.quaternion()).angle(), 0.1, 1e-9);
  EXPECT_TRUE(PoseAtTime(poses, 1.99)->Inverse().translation().isApprox(Eigen::Vector3d(5, 0, 0)));
  EXPECT_FALSE(PoseAtTime(poses, 1.5).has_value());  // in the gap
  EXPECT_FALSE(PoseAtTime(poses, 0.9).has_value());  // before the first
  EXPECT_TRUE(PoseAtTime(poses, 0.99).has_value());  // within 20 ms of the first
  EXPECT_FALSE(PoseAtTime({}, 1.0).has_value());
}

}  // namespace
}  // namespace ocg
