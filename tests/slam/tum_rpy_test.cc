// Monocular SLAM on real hand-held video: the first 330 frames of TUM RGB-D fr1_rpy (a
// desk turned about all three axes at 20-95 deg/s, blur, the fr1 lens distortion) from
// ../shared/data, sequential mode, ORB-SLAM2's TUM1 settings. Skips when the data is absent.

#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>
#include <opencv2/imgcodecs.hpp>

#include "ocg/app/settings.h"
#include "ocg/eval/trajectory_error.h"
#include "ocg/io/sequence.h"
#include "ocg/slam/system.h"
#include "test_support.h"

namespace ocg {
namespace {

TEST(TumRpySlam, InitializesEarlyTracksThroughTheTurnsAndStaysAccurate) {
  const std::optional<std::string> data = testing::SharedDataDir();
  if (!data) GTEST_SKIP() << testing::SharedDataSkipMessage();
  const std::string root = *data + "/tum_fr1_rpy_first330";
  if (!std::filesystem::is_directory(root)) GTEST_SKIP() << "no fr1_rpy frames at " << root;
  const Settings settings = LoadSettings(root + "/orbslam2_TUM1.yaml").settings;
  const Vocabulary vocabulary = Vocabulary::Load(settings.vocabulary.Resolve());
  const ImageSequence sequence = ReadTumSequence(root);
  SystemConfig config = MakeSystemConfig(settings);
  config.sequential = true;  // reproducible
  System system(config, vocabulary);
  for (const TimedImage& image : sequence.images) {
    const cv::Mat gray = cv::imread(image.path, cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(gray.empty()) << image.path;
    system.TrackImage(gray, image.timestamp, image.timestamp_text);
  }
  system.Shutdown();

  // The map the trajectory is written from: where it started and how much of the rest.
  const std::vector<StampedPose> trajectory = system.CameraTrajectory();
  int first = -1;
  for (std::size_t i = 0; i < system.Frames().size(); ++i) {
    if (system.Frames()[i].tracked && system.Frames()[i].map == system.MainMap()) {
      first = static_cast<int>(i);
      break;
    }
  }
  ASSERT_GE(first, 0) << "never initialized";
  EXPECT_LT(first, 60) << "initialized too late";
  const double after = static_cast<double>(sequence.images.size()) - first;
  EXPECT_GE(static_cast<double>(trajectory.size()), 0.9 * after)
      << "frames tracked after " << first;
  const AteResult ate = ComputeAte(sequence.groundtruth, trajectory, AteOptions());
  EXPECT_GE(ate.pairs.size(), trajectory.size() - 5);
  EXPECT_LE(ate.translation.rmse, 0.03) << "metres, Sim(3)-aligned";
  std::cout << "fr1_rpy: first tracked " << first << ", " << trajectory.size() << " of " << after
            << " frames after it, maps " << system.Maps().size() << ", ATE RMSE "
            << ate.translation.rmse << " m\n";
}

}  // namespace
}  // namespace ocg
