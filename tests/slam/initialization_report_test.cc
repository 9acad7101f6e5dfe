// A run that never initializes says why: the reasons the initializer gave, counted, and a
// message naming the cause, on a constructed still camera (the same view, fresh sensor
// noise every frame) against the same scene with the camera moving.

#include "ocg/slam/initialization_report.h"

#include <gtest/gtest.h>

#include "ocg/features/vocabulary.h"
#include "ocg/sim/generator.h"
#include "ocg/sim/presets.h"
#include "ocg/slam/system.h"
#include "test_support.h"

namespace ocg {
namespace {

TEST(InitializationReport, CountsFailuresByReasonWithoutTheirFigures) {
  EXPECT_EQ(FailureReason("too little parallax (0.12 degrees)"), "too little parallax");
  EXPECT_EQ(FailureReason("weak initial map: 12 points after bundle adjustment"),
            "weak initial map");
  EXPECT_EQ(FailureReason("neither a homography nor a fundamental matrix fits the matches"),
            "neither a homography nor a fundamental matrix fits the matches");
  InitializationAttempts attempts;
  attempts.frames = 6;
  EXPECT_EQ(attempts.MostFrequentReason(), "");
  attempts.Record("too little parallax (0.12 degrees)");
  attempts.Record("too few features (40, Tracking.minInitFeatures = 100)");
  attempts.Record("too little parallax (0.31 degrees)");
  EXPECT_EQ(attempts.reasons.at("too little parallax"), 2);
  EXPECT_EQ(attempts.MostFrequentReason(), "too little parallax");
  const std::string message = NeverInitializedMessage(attempts);
  EXPECT_EQ(message.rfind("never initialized in 6 frames: too little parallax", 0), 0u) << message;
  EXPECT_NE(message.find("for 2 of the 3 failed attempts"), std::string::npos) << message;
  EXPECT_NE(message.find("(last: 'too little parallax (0.31 degrees)')"), std::string::npos);
  attempts.Record("too few features (30, Tracking.minInitFeatures = 100)");
  attempts.Record("too few features (20, Tracking.minInitFeatures = 100)");
  EXPECT_NE(NeverInitializedMessage(attempts).find("too few ORB features"), std::string::npos);
}

TEST(InitializationReport, NoSecondFrameIsSaidSo) {
  InitializationAttempts attempts;
  attempts.frames = 1;
  EXPECT_NE(
      NeverInitializedMessage(attempts).find("never initialized in 1 frames: no second frame"),
      std::string::npos);
}

// frames of the smoke preset seen from the pose at time 0 (still) or along its path.
const System& RunSmoke(System& system, const sim::Scene& scene, int frames, bool still) {
  sim::SceneRenderer renderer(scene);
  for (int frame = 0; frame < frames; ++frame) {
    const double t = frame / scene.fps;
    const cv::Mat image = renderer.Colour(t, sim::CameraPoseAt(scene, still ? 0.0 : t),
                                          static_cast<std::uint64_t>(frame) + 1);
    system.TrackImage(image, t, std::to_string(t));
  }
  system.Shutdown();
  return system;
}

TEST(InitializationReport, AStillCameraNeverInitializesForLackOfParallax) {
  const Vocabulary vocabulary =
      Vocabulary::Load(testing::SourceDir() + "/thirdparty/vocabulary/ocg_orb_vocabulary.ocgvoc");
  const sim::Scene scene = sim::MakePreset("smoke", 1);
  SystemConfig config;
  config.camera = scene.camera;
  config.fps = scene.fps;
  System still(config, vocabulary);
  RunSmoke(still, scene, 12, true);
  EXPECT_EQ(still.KeyFrameCount(), 0u);
  const InitializationAttempts& attempts = still.Initialization();
  EXPECT_EQ(attempts.frames, 12);
  int failed = 0;
  for (const auto& entry : attempts.reasons) failed += entry.second;
  EXPECT_EQ(failed, 11);  // the first frame is the first view, nothing to fail yet
  const std::string message = NeverInitializedMessage(attempts);
  EXPECT_EQ(message.rfind("never initialized in 12 frames: too little parallax", 0), 0u) << message;

  // The same scene with the camera moving initializes, and its attempts stop there.
  System moving(config, vocabulary);
  RunSmoke(moving, scene, 30, false);
  EXPECT_GT(moving.KeyFrameCount(), 0u);
  EXPECT_LT(moving.Initialization().frames, 30);
}

}  // namespace
}  // namespace ocg
