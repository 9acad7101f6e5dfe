// Loop closing on its own, on a map built from a synthetic scene with known poses: a camera
// circles a room, its estimated poses drift as a monocular map's do, and each point is
// mapped afresh every few keyframes (as tracking loses and re-triangulates points), so the
// end of the lap holds duplicates of the points the start mapped. Closing the loop must
// find the start again, pull the drifted end back to the truth and fuse the duplicates; a
// path that never comes back must close nothing.

#include "ocg/slam/loop_closing.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>

#include "ocg/features/vocabulary.h"
#include "synthetic_map.h"
#include "test_support.h"

namespace ocg {
namespace {

constexpr double kStepDeg = 9.0;  // the camera's step along the circle per keyframe
constexpr int kTrackLength = 6;   // keyframes a map point lasts before it is mapped again

const Vocabulary& DefaultVocabulary() {
  static const Vocabulary vocabulary =
      Vocabulary::Load(testing::SourceDir() + "/thirdparty/vocabulary/ocg_orb_vocabulary.ocgvoc");
  return vocabulary;
}

// The drift at keyframe k of n: the map's frame there is the world turned by up to 3
// degrees about z and shifted by up to 30 cm (estimated = drift * true).
SE3 Drift(int k, int n) {
  const double share = static_cast<double>(k) / n;
  const double yaw = 0.05 * share;
  Eigen::Matrix3d R;
  R << std::cos(yaw), -std::sin(yaw), 0, std::sin(yaw), std::cos(yaw), 0, 0, 0, 1;
  return SE3(R, Eigen::Vector3d(0.1 * share, 0.3 * share, 0.02 * share));
}

struct DriftedMap {
  testing::SyntheticScene scene;
  Map map;
  BowDatabase database{DefaultVocabulary().WordCount()};
  std::vector<KeyFramePtr> keyframes;  // one per frame
  ScalePyramid pyramid = MakeScalePyramid(8, 1.2);

  // Keyframe k's camera centre's distance from the truth.
  double Error(int k) const {
    return testing::CentreDistance(keyframes[static_cast<std::size_t>(k)]->T_cw,
                                   scene.T_cw[static_cast<std::size_t>(k)]);
  }
};

// A map of `frames` keyframes 9 degrees apart on the circle, the room's walls only (a
// table in the middle would be seen from everywhere by descriptors that, unlike real
// ones, never change with the view).
std::unique_ptr<DriftedMap> MakeDriftedMap(int frames) {
  auto drifted = std::make_unique<DriftedMap>();
  testing::SyntheticSceneOptions options;
  options.frames = frames;
  options.laps = frames * kStepDeg / 360.0;
  options.points = 900;
  options.points_on_table = 0;
  drifted->scene = testing::SynthesizeScene(options);
  const testing::SyntheticScene& scene = drifted->scene;
  Map& map = drifted->map;
  for (int k = 0; k < frames; ++k) {
    const SE3 estimated = scene.T_cw[static_cast<std::size_t>(k)] * Drift(k, frames).Inverse();
    drifted->keyframes.push_back(
        testing::SyntheticKeyFrame(scene, k, estimated, map.NextKeyFrameId(), DefaultVocabulary()));
    map.Add(drifted->keyframes.back());
  }
  // Each point's sightings, cut into tracks of kTrackLength keyframes (the cuts staggered
  // over the points, so consecutive keyframes share most points): one map point per
  // track, where the drifted map of its first keyframe puts it.
  for (int point = 0; point < options.points; ++point) {
    std::vector<int> seen_by;
    for (int k = 0; k < frames; ++k) {
      if (testing::FeatureOfPoint(scene, k, point) >= 0) seen_by.push_back(k);
    }
    std::vector<KeyFramePtr> track;
    int track_start = -1;
    const auto flush = [&] {
      if (track.size() >= 2) {
        testing::AddSyntheticPoint(
            scene, point,
            Drift(track_start, frames) * scene.points[static_cast<std::size_t>(point)], track,
            drifted->pyramid, &map);
      }
      track.clear();
    };
    for (const int k : seen_by) {
      const bool cut = !track.empty() && ((k + point) % kTrackLength == 0 ||
                                          k != static_cast<int>(track.back()->frame_id) + 1);
      if (cut) flush();
      if (track.empty()) track_start = k;
      track.push_back(drifted->keyframes[static_cast<std::size_t>(k)]);
    }
    flush();
  }
  testing::ConnectSyntheticMap(&map, &drifted->database);
  return drifted;
}

TEST(LoopClosing, TheEndOfALapFindsTheStartPullsTheDriftBackAndFusesTheDuplicates) {
  // 1.1 laps: keyframes 40-43 look where keyframes 0-3 looked.
  const int frames = 44;
  const auto drifted = MakeDriftedMap(frames);
  // No map point is shared between the two ends before the loop.
  const auto shares_points_with_start = [&](int k) {
    for (const MapPointPtr& point : drifted->keyframes[static_cast<std::size_t>(k)]->points) {
      if (!point || point->bad) continue;
      for (const auto& [id, feature] : point->observations) {
        if (id < 4) return true;
      }
    }
    return false;
  };
  ASSERT_FALSE(shares_points_with_start(frames - 2));
  const double error_before = drifted->Error(frames - 1);
  ASSERT_GT(error_before, 0.2);

  LoopClosing closing(drifted->scene.options.camera, drifted->pyramid, MatcherOptions{},
                      LoopClosingOptions{}, &drifted->map, &drifted->database, 1);
  std::vector<int> closed_at;
  for (int k = 0; k < frames; ++k) {
    if (closing.ProcessKeyFrame(drifted->keyframes[static_cast<std::size_t>(k)]))
      closed_at.push_back(k);
  }
  ASSERT_EQ(closed_at.size(), 1u);
  const LoopEvent& loop = closing.Stats().loops.front();
  std::printf(
      "loop at keyframe %llu onto %llu: %d Sim(3) inliers, %d matches, scale %.3f, %d "
      "points fused; error of the last keyframe %.3f -> %.3f m\n",
      static_cast<unsigned long long>(loop.keyframe), static_cast<unsigned long long>(loop.matched),
      loop.sim3_inliers, loop.loop_matches, loop.scale, loop.points_fused, error_before,
      drifted->Error(frames - 1));
  // Found where the views overlap: the end of the lap onto its start.
  EXPECT_GE(loop.keyframe, 38u);
  EXPECT_LE(loop.matched, 5u);
  // The drift is rigid: no scale to correct.
  EXPECT_NEAR(loop.scale, 1.0, 0.05);
  EXPECT_GT(loop.points_fused, 20);
  // The end of the lap is back where it belongs; the start did not move away.
  for (int k = frames - 6; k < frames; ++k) {
    EXPECT_LT(drifted->Error(k), 0.25 * drifted->Error(0) + 0.03) << "keyframe " << k;
  }
  EXPECT_LT(drifted->Error(frames - 1), 0.2 * error_before);
  for (int k = 0; k < 4; ++k) EXPECT_LT(drifted->Error(k), 0.03) << "keyframe " << k;
  // One point per place: the ends share points and are linked by a loop edge.
  EXPECT_TRUE(shares_points_with_start(frames - 2));
  EXPECT_FALSE(drifted->keyframes[static_cast<std::size_t>(loop.keyframe)]->loop_edges.empty());
}

TEST(LoopClosing, APathThatNeverComesBackClosesNothing) {
  // Three quarters of a lap: the last keyframes see walls the first ones never saw.
  const int frames = 30;
  const auto drifted = MakeDriftedMap(frames);
  LoopClosing closing(drifted->scene.options.camera, drifted->pyramid, MatcherOptions{},
                      LoopClosingOptions{}, &drifted->map, &drifted->database, 1);
  const double error_before = drifted->Error(frames - 1);
  for (int k = 0; k < frames; ++k) {
    EXPECT_FALSE(closing.ProcessKeyFrame(drifted->keyframes[static_cast<std::size_t>(k)]))
        << "keyframe " << k;
  }
  EXPECT_TRUE(closing.Stats().loops.empty());
  EXPECT_EQ(drifted->Error(frames - 1), error_before);  // the map was not touched
}

TEST(LoopClosing, DisabledClosesNoLoopEvenWhereOneIs) {
  const int frames = 44;
  const auto drifted = MakeDriftedMap(frames);
  LoopClosingOptions options;
  options.enabled = false;
  LoopClosing closing(drifted->scene.options.camera, drifted->pyramid, MatcherOptions{}, options,
                      &drifted->map, &drifted->database, 1);
  for (int k = 0; k < frames; ++k)
    EXPECT_FALSE(closing.ProcessKeyFrame(drifted->keyframes[static_cast<std::size_t>(k)]));
}

}  // namespace
}  // namespace ocg
