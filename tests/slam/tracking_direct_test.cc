// Tracking on its own (no System): frames of the smoke preset rendered in-process, a
// keyframe sink that maps each keyframe at once (as sequential mode does). It must
// initialize, follow the true camera up to the monocular map's similarity, hand keyframes
// over, report the map points it tracked, and relocalize in its map after losing itself.

#include "ocg/slam/tracking.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <optional>

#include "ocg/core/alignment.h"
#include "ocg/features/vocabulary.h"
#include "ocg/sim/generator.h"
#include "ocg/sim/presets.h"
#include "ocg/slam/local_mapping.h"
#include "test_support.h"

namespace ocg {
namespace {

constexpr int kFrames = 40;

const Vocabulary& DefaultVocabulary() {
  static const Vocabulary vocabulary =
      Vocabulary::Load(testing::SourceDir() + "/thirdparty/vocabulary/ocg_orb_vocabulary.ocgvoc");
  return vocabulary;
}

class TrackingDirect : public ::testing::Test {
 protected:
  TrackingDirect()
      : scene_(sim::MakePreset("smoke", 1)),
        renderer_(scene_),
        database_(DefaultVocabulary().WordCount()),
        tracking_(
            scene_.camera, scene_.fps, OrbExtractorOptions{}, MatcherOptions{}, InitialMapOptions{},
            TrackingOptions{}, TrackingDependencies{&DefaultVocabulary(), &database_, &map_},
            [this](const KeyFramePtr& keyframe) {
              ++keyframes_handed_;
              mapping_->ProcessKeyFrame(keyframe);
              return false;
            },
            [] { return true; }) {
    mapping_ = std::make_unique<LocalMapping>(scene_.camera, tracking_.pyramid(), MatcherOptions{},
                                              LocalMappingOptions{}, &map_, &database_);
  }

  cv::Mat Image(int frame) {
    const double t = frame / scene_.fps;
    return renderer_.Colour(t, sim::CameraPoseAt(scene_, t), frame);
  }
  TrackingResult Track(int frame, const cv::Mat& image) {
    const double t = frame / scene_.fps;
    return tracking_.Track(image, t, std::to_string(t));
  }

  sim::Scene scene_;
  sim::SceneRenderer renderer_;
  Map map_;
  BowDatabase database_;
  std::unique_ptr<LocalMapping> mapping_;
  int keyframes_handed_ = 0;
  Tracking tracking_;
};

TEST_F(TrackingDirect, FollowsTheTrueCameraUpToTheMapsSimilarity) {
  std::vector<Eigen::Vector3d> estimated, truth;
  std::optional<int> first_tracked;
  int keyframe_results = 0;
  for (int frame = 0; frame < kFrames; ++frame) {
    const TrackingResult result = Track(frame, Image(frame));
    if (result.state != TrackingState::kOk) {
      EXPECT_FALSE(first_tracked.has_value()) << "lost at frame " << frame;
      continue;
    }
    const bool initializing = !first_tracked;
    if (!first_tracked) first_tracked = frame;
    ASSERT_TRUE(result.T_cw.has_value());
    keyframe_results += result.new_keyframe ? 1 : 0;
    // Tracked frames report the map points they matched (the inliers; the initializing
    // frame the initial map's points), each in the map: local mapping, run on a new
    // keyframe before the result is made, may have culled a few of the inliers.
    if (!initializing) {
      EXPECT_GE(result.inliers, TrackingOptions{}.min_local_map_inliers) << "frame " << frame;
      EXPECT_LE(static_cast<int>(result.points.size()), result.inliers) << "frame " << frame;
    }
    EXPECT_GE(static_cast<int>(result.points.size()), TrackingOptions{}.min_local_map_inliers)
        << "frame " << frame;
    for (const TrackedPoint& point : result.points)
      ASSERT_EQ(map_.points().count(point.id), 1u) << "frame " << frame << " point " << point.id;
    estimated.push_back(result.T_cw->Inverse().translation());
    truth.push_back(sim::CameraPoseAt(scene_, frame / scene_.fps).Inverse().translation());
  }
  ASSERT_TRUE(first_tracked.has_value());
  EXPECT_LE(*first_tracked, 10);
  EXPECT_EQ(tracking_.state(), TrackingState::kOk);
  // Every keyframe reported went to the sink, and the initial map's first one too (its
  // second is the initializing frame's).
  EXPECT_GE(keyframe_results, 2);
  EXPECT_EQ(keyframes_handed_, keyframe_results + 1);
  EXPECT_GE(map_.keyframes().size(), static_cast<std::size_t>(keyframe_results));
  const AlignmentResult fit = AlignPoints(estimated, truth, true);
  std::printf(
      "initialized at frame %d, %zu frames tracked, %d keyframes, camera centres within "
      "%.2f mm of the truth after Sim(3) alignment\n",
      *first_tracked, estimated.size(), keyframes_handed_, 1e3 * fit.rmse);
  EXPECT_LT(fit.rmse, 0.01);
}

TEST_F(TrackingDirect, ALostCameraRelocalizesWhereItHadBeen) {
  std::optional<SE3> pose_at_12;
  for (int frame = 0; frame < 30; ++frame) {
    const TrackingResult result = Track(frame, Image(frame));
    if (frame == 12) pose_at_12 = result.T_cw;
  }
  ASSERT_TRUE(pose_at_12.has_value());
  ASSERT_EQ(tracking_.state(), TrackingState::kOk);
  const std::size_t keyframes = map_.keyframes().size();
  // A blank image: nothing to track.
  const cv::Mat blank(scene_.camera.height, scene_.camera.width, CV_8UC3, cv::Scalar(90, 90, 90));
  const TrackingResult lost = Track(30, blank);
  EXPECT_EQ(lost.state, TrackingState::kLost);
  EXPECT_FALSE(lost.T_cw.has_value());
  EXPECT_FALSE(lost.reset);  // the map is large enough to keep
  // Frame 12's view again, well behind where the camera was lost: found by place
  // recognition in the keyframe database, placed where the map had it.
  const TrackingResult found = Track(31, Image(12));
  ASSERT_EQ(found.state, TrackingState::kOk);
  EXPECT_TRUE(found.relocalized);
  ASSERT_TRUE(found.T_cw.has_value());
  EXPECT_LT((found.T_cw->Inverse().translation() - pose_at_12->Inverse().translation()).norm(),
            0.02);
  EXPECT_GE(map_.keyframes().size(), keyframes);
}

TEST_F(TrackingDirect, ResetForgetsTheMapAndInitializesAgain) {
  for (int frame = 0; frame < 12; ++frame) Track(frame, Image(frame));
  ASSERT_EQ(tracking_.state(), TrackingState::kOk);
  tracking_.Reset();
  EXPECT_TRUE(map_.keyframes().empty());
  EXPECT_TRUE(map_.points().empty());
  EXPECT_EQ(database_.size(), 0u);
  std::optional<int> again;
  for (int frame = 12; frame < 30 && !again; ++frame) {
    if (Track(frame, Image(frame)).state == TrackingState::kOk) again = frame;
  }
  EXPECT_TRUE(again.has_value());
}

}  // namespace
}  // namespace ocg
