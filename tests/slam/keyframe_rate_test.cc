// How often tracking makes keyframes, on generated frames (smoke preset, rendered
// in-process) in sequential mode, where local mapping is always idle between frames.
#include <gtest/gtest.h>

#include "ocg/features/vocabulary.h"
#include "ocg/sim/generator.h"
#include "ocg/sim/presets.h"
#include "ocg/slam/system.h"
#include "test_support.h"

namespace ocg {
namespace {

// Indices of the frames that made a keyframe, over the first count frames.
std::vector<std::size_t> KeyFrameFrames(const Vocabulary& vocabulary, int min_frames, int count) {
  const sim::Scene scene = sim::MakePreset("smoke", 1);
  sim::SceneRenderer renderer(scene);
  SystemConfig config;
  config.camera = scene.camera;
  config.fps = scene.fps;
  config.tracking.min_frames_between_keyframes = min_frames;
  System system(config, vocabulary);
  for (int frame = 0; frame < count; ++frame) {
    const double t = frame / scene.fps;
    system.TrackImage(renderer.Colour(t, sim::CameraPoseAt(scene, t), frame), t, std::to_string(t));
  }
  system.Shutdown();
  std::vector<std::size_t> frames;
  for (std::size_t i = 0; i < system.Frames().size(); ++i) {
    if (system.Frames()[i].new_keyframe) frames.push_back(i);
  }
  return frames;
}

// The mapper finishes each keyframe before the next frame in sequential mode; the frame
// after a keyframe still counts it busy, so no two tracked frames in a row make
// keyframes, where ORB-SLAM2's rule alone (0 frames) lets them.
TEST(KeyFrameRate, SequentialModeLeavesAFrameBetweenKeyFrames) {
  const Vocabulary vocabulary =
      Vocabulary::Load(testing::SourceDir() + "/thirdparty/vocabulary/ocg_orb_vocabulary.ocgvoc");
  const std::vector<std::size_t> spaced = KeyFrameFrames(vocabulary, 2, 120);
  ASSERT_GE(spaced.size(), 5u);
  for (std::size_t k = 2; k < spaced.size(); ++k) {  // the first two: initialization
    EXPECT_GE(spaced[k] - spaced[k - 1], 2u)
        << "keyframes at frames " << spaced[k - 1] << " and " << spaced[k];
  }
  const std::vector<std::size_t> unspaced = KeyFrameFrames(vocabulary, 0, 120);
  int consecutive = 0;
  for (std::size_t k = 2; k < unspaced.size(); ++k) {
    consecutive += unspaced[k] - unspaced[k - 1] == 1 ? 1 : 0;
  }
  EXPECT_GT(consecutive, 0) << "the rule alone never made two keyframes in a row here";
  EXPECT_LT(spaced.size(), unspaced.size());
}

}  // namespace
}  // namespace ocg
