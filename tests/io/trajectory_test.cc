#include <gtest/gtest.h>

#include "error_of.h"
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

// The message of the ParseError read throws; fails the test when none is thrown.
template <typename Read>
std::string ParseErrorOf(Read read) {
  return testing::ErrorOf<ParseError>(read);
}

TEST(KittiTrajectory, RoundTripRowByRowWithTheRowIndexAsTime) {
  std::vector<StampedPose> poses(3);
  for (int i = 0; i < 3; ++i) {
    poses[i].timestamp = 10.0 + i;
    poses[i].T_wc = SE3::Exp((Vector6d() << i, 2, -3, 0.1 * i, 0.2, 0.3).finished());
  }
  const std::string path = WriteFixture("");
  WriteKittiTrajectory(path, poses);
  EXPECT_EQ(DetectTrajectoryFormat(path), TrajectoryFormat::kKitti);
  const std::vector<StampedPose> read = ReadKittiTrajectory(path);
  ASSERT_EQ(read.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(read[i].timestamp, i);
    EXPECT_EQ(read[i].timestamp_text, std::to_string(i));
    EXPECT_TRUE(read[i].T_wc.Matrix().isApprox(poses[i].T_wc.Matrix(), 1e-8)) << i;
  }
  // TUM lines are detected as such.
  WriteTumTrajectory(path, poses);
  EXPECT_EQ(DetectTrajectoryFormat(path), TrajectoryFormat::kTum);
  EXPECT_EQ(ReadTrajectory(path)[2].timestamp, 12.0);
}

TEST(KittiTrajectory, MalformedLinesAndTimesNameFileAndLine) {
  EXPECT_NE(ParseErrorOf([] {
              ReadKittiTrajectory(WriteFixture("1 0 0 0 0 1 0 0 0 0 1\n"));
            }).find(":1: expected the 12 numbers of a KITTI pose"),
            std::string::npos);
  EXPECT_NE(
      ParseErrorOf([] {
        ReadKittiTrajectory(WriteFixture("1 0 0 0 0 1 0 0 0 0 1 0\n2 0 0 0 0 1 0 0 0 0 1 0\n"));
      }).find(":2: the 3x3 part is not a rotation"),
      std::string::npos);
  const std::string dir = testing::MakeTempDir("kitti_times");
  WriteFileAtomically(dir + "/poses.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 1 0 1 0 0 0 0 1 0\n");
  WriteFileAtomically(dir + "/times.txt", "0.000000e+00\n1.038752e-01\n2.078941e-01\n");
  EXPECT_NE(ParseErrorOf([&] {
              ReadTrajectory(dir + "/poses.txt", dir + "/times.txt");
            }).find("2 KITTI poses, but '" + dir + "/times.txt' lists 3 times"),
            std::string::npos);
  WriteFileAtomically(dir + "/times.txt", "0.000000e+00\n1.038752e-01\n");
  const std::vector<StampedPose> timed = ReadTrajectory(dir + "/poses.txt", dir + "/times.txt");
  EXPECT_EQ(timed[1].timestamp_text, "0.103875");
  EXPECT_DOUBLE_EQ(timed[1].timestamp, 0.1038752);
  // times.txt is the frames' list: strict.
  WriteFileAtomically(dir + "/times.txt", "0.2\n0.1\n");
  EXPECT_NE(ParseErrorOf([&] {
              ReadKittiTimes(dir + "/times.txt");
            }).find("times.txt:2: frame time 0.1 is earlier than line 1"),
            std::string::npos);
  EXPECT_THROW(DetectTrajectoryFormat(WriteFixture("# nothing\n")), ParseError);
}

TEST(KittiTrajectory, RealGroundTruthEqualsItsTumConversion) {
  const auto data = testing::SharedDataDir();
  if (!data) GTEST_SKIP() << testing::SharedDataSkipMessage();
  const std::string root = *data + "/kitti_07_first160";
  const std::vector<StampedPose> kitti =
      ReadTrajectory(root + "/poses_kitti.txt", root + "/times.txt");
  const std::vector<StampedPose> tum = ReadTumTrajectory(root + "/groundtruth.txt");
  ASSERT_EQ(kitti.size(), 160u);
  ASSERT_EQ(tum.size(), 160u);
  for (std::size_t i = 0; i < kitti.size(); ++i) {
    EXPECT_EQ(kitti[i].timestamp_text, tum[i].timestamp_text) << i;
    EXPECT_LT((kitti[i].T_wc.translation() - tum[i].T_wc.translation()).norm(), 1e-5) << i;
    EXPECT_LT(kitti[i].T_wc.quaternion().angularDistance(tum[i].T_wc.quaternion()), 1e-5) << i;
  }
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
