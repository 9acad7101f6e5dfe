// Loop closing's place recognition between two maps: a second map of the same place is
// recognized, a map of an unrelated scene never is. Maps come from the SLAM system run on
// generated frames (smoke preset, rendered in-process).

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>

#include "ocg/features/vocabulary.h"
#include "ocg/sim/generator.h"
#include "ocg/sim/presets.h"
#include "ocg/slam/system.h"
#include "test_support.h"

namespace ocg {
namespace {

// A SLAM map of frames first..first+count-1 of the smoke preset drawn with seed (layout,
// textures, camera wobble), with sensor noise seeded by noise_seed.
std::unique_ptr<System> MapOf(const Vocabulary& vocabulary, std::uint64_t seed, int first,
                              int count, std::uint64_t noise_seed) {
  const sim::Scene scene = sim::MakePreset("smoke", seed);
  sim::SceneRenderer renderer(scene);
  SystemConfig config;
  config.camera = scene.camera;
  config.fps = scene.fps;
  auto system = std::make_unique<System>(config, vocabulary);
  for (int frame = first; frame < first + count; ++frame) {
    const double t = frame / scene.fps;
    const cv::Mat image =
        renderer.Colour(t, sim::CameraPoseAt(scene, t), noise_seed * 100003 + frame);
    system->TrackImage(image, t, std::to_string(t));
  }
  system->Shutdown();
  return system;
}

TEST(LoopRecognition, ASecondMapOfThePlaceIsRecognizedAnUnrelatedSceneNever) {
  const Vocabulary vocabulary =
      Vocabulary::Load(testing::SourceDir() + "/thirdparty/vocabulary/ocg_orb_vocabulary.ocgvoc");
  const auto first = MapOf(vocabulary, 1, 0, 100, 1);
  ASSERT_GE(first->KeyFrames().size(), 10u);
  // The same stretch of the same scene, started 4 frames later, other sensor noise: its
  // own map, at its own scale and in its own frame.
  const auto again = MapOf(vocabulary, 1, 4, 100, 2);
  // Another layout with other textures on the walls, floor, table and objects.
  const auto unrelated = MapOf(vocabulary, 2, 0, 100, 3);

  const auto recognized = [&](const System& other) {
    int count = 0;
    for (const KeyFramePtr& keyframe : other.KeyFrames()) {
      if (first->RecognizePlace(keyframe, 5)) ++count;
    }
    return count;
  };
  const std::size_t again_keyframes = again->KeyFrames().size();
  const int again_recognized = recognized(*again);
  EXPECT_GE(again_recognized, static_cast<int>(again_keyframes) / 2);
  const int unrelated_recognized = recognized(*unrelated);
  EXPECT_EQ(unrelated_recognized, 0);
  std::printf("recognized: %d of %zu keyframes of the second map, %d of %zu of the unrelated one\n",
              again_recognized, again_keyframes, unrelated_recognized,
              unrelated->KeyFrames().size());
}

}  // namespace
}  // namespace ocg
