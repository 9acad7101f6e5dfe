// Features extracted ahead of tracking (System::MakeFeatureExtractor, given to TrackImage),
// as ocg_slam's reader thread does, on generated frames (smoke preset, rendered
// in-process), sequential mode.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <optional>

#include "ocg/features/vocabulary.h"
#include "ocg/sim/generator.h"
#include "ocg/sim/presets.h"
#include "ocg/slam/system.h"
#include "test_support.h"

namespace ocg {
namespace {

constexpr int kFrames = 40;

enum class Features { kExtractedByTracking, kMadeAhead, kOfABlankImage };

// T_cw of every frame (none when not tracked).
std::vector<std::optional<SE3>> TrackSmoke(const Vocabulary& vocabulary, Features features) {
  const sim::Scene scene = sim::MakePreset("smoke", 1);
  sim::SceneRenderer renderer(scene);
  SystemConfig config;
  config.camera = scene.camera;
  config.fps = scene.fps;
  System system(config, vocabulary);
  const std::function<ExtractedFeatures(const cv::Mat&)> extract = system.MakeFeatureExtractor();
  const cv::Mat blank(scene.camera.height, scene.camera.width, CV_8UC1, cv::Scalar(128));
  std::vector<std::optional<SE3>> poses;
  for (int frame = 0; frame < kFrames; ++frame) {
    const double t = frame / scene.fps;
    const cv::Mat image = renderer.Colour(t, sim::CameraPoseAt(scene, t), frame);
    ExtractedFeatures ahead;
    if (features == Features::kMadeAhead) ahead = extract(image);
    if (features == Features::kOfABlankImage) ahead = extract(blank);
    poses.push_back(system
                        .TrackImage(image, t, std::to_string(t),
                                    features == Features::kExtractedByTracking ? nullptr : &ahead)
                        .T_cw);
  }
  system.Shutdown();
  return poses;
}

Vocabulary DefaultVocabulary() {
  return Vocabulary::Load(testing::SourceDir() +
                          "/thirdparty/vocabulary/ocg_orb_vocabulary.ocgvoc");
}

// The reader thread's extractor has tracking's options and camera: the same features,
// so the same poses, bit for bit.
TEST(FeaturesAhead, TrackingWithFeaturesMadeAheadGivesTheSamePoses) {
  const Vocabulary vocabulary = DefaultVocabulary();
  const std::vector<std::optional<SE3>> own =
      TrackSmoke(vocabulary, Features::kExtractedByTracking);
  const std::vector<std::optional<SE3>> ahead = TrackSmoke(vocabulary, Features::kMadeAhead);
  ASSERT_EQ(own.size(), ahead.size());
  int tracked = 0;
  for (std::size_t i = 0; i < own.size(); ++i) {
    ASSERT_EQ(own[i].has_value(), ahead[i].has_value()) << "frame " << i;
    if (!own[i]) continue;
    ++tracked;
    EXPECT_EQ(own[i]->Matrix(), ahead[i]->Matrix()) << "frame " << i;
  }
  EXPECT_GE(tracked, kFrames - 5);
}

// The given features are what tracking uses once initialized: with those of a blank image
// every frame after an initialization is lost (and the small map is reset). They are not
// used while initializing, which extracts more features of its own: it initializes on
// the real images regardless, and again after each reset.
TEST(FeaturesAhead, GivenFeaturesAreUsedOnceInitializedAndNotBefore) {
  const std::vector<std::optional<SE3>> poses =
      TrackSmoke(DefaultVocabulary(), Features::kOfABlankImage);
  int initializations = 0;
  int tracked_after_a_tracked_frame = 0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (!poses[i]) continue;
    ++initializations;
    if (i > 0 && poses[i - 1]) ++tracked_after_a_tracked_frame;
  }
  EXPECT_GE(initializations, 2);
  EXPECT_EQ(tracked_after_a_tracked_frame, 0);
}

}  // namespace
}  // namespace ocg
