// People walking through a generated scene (the `walkers` preset, bonn-style): how a walker
// moves, that the plan keeps people clear of the furniture and of the camera, that they
// hide what stands behind them, and that the SLAM tracks through them without mapping them.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <set>

#include "ocg/core/settings_file.h"
#include "ocg/eval/trajectory_error.h"
#include "ocg/features/vocabulary.h"
#include "ocg/sim/generator.h"
#include "ocg/sim/presets.h"
#include "ocg/sim/scene_io.h"
#include "ocg/slam/system.h"
#include "test_support.h"

namespace ocg::sim {
namespace {

Walker TwoLegWalker() {
  Walker walker;
  walker.id = 1;
  walker.waypoints = {{1.0, {0.0, 0.0}}, {2.0, {1.0, 0.0}}, {3.0, {1.0, 0.0}}, {4.0, {1.0, 1.0}}};
  return walker;
}

TEST(Walker, FollowsItsWaypointsFacingWhereItGoes) {
  const Walker walker = TwoLegWalker();
  EXPECT_FALSE(walker.PoseAt(0.5));
  EXPECT_FALSE(walker.PoseAt(4.1));
  const auto walking = walker.PoseAt(1.5);
  ASSERT_TRUE(walking);
  EXPECT_NEAR((walking->centre - Eigen::Vector3d(0.5, 0.0, 0.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(walking->yaw, 0.0, 1e-12);
  // Standing still between two waypoints at one place: it keeps facing where it came from.
  const auto standing = walker.PoseAt(2.5);
  ASSERT_TRUE(standing);
  EXPECT_NEAR((standing->centre - Eigen::Vector3d(1.0, 0.0, 0.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(standing->yaw, 0.0, 1e-12);
  const auto turned = walker.PoseAt(3.5);
  ASSERT_TRUE(turned);
  EXPECT_NEAR((turned->centre - Eigen::Vector3d(1.0, 0.5, 0.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(turned->yaw, M_PI / 2, 1e-12);
}

TEST(Walker, SceneFilesKeepWalkersAndRefuseBadOnes) {
  const Scene scene = MakePreset("walkers", 1);
  ASSERT_GE(scene.walkers.size(), 6u);
  const Scene back = ParseSceneYaml(SceneToYaml(scene), "walkers.yaml").scene;
  EXPECT_EQ(SceneToYaml(back), SceneToYaml(scene));
  ASSERT_EQ(back.walkers.size(), scene.walkers.size());
  for (std::size_t i = 0; i < scene.walkers.size(); ++i) {
    ASSERT_EQ(back.walkers[i].waypoints.size(), scene.walkers[i].waypoints.size());
    EXPECT_EQ(back.walkers[i].texture_seed, scene.walkers[i].texture_seed);
    for (std::size_t k = 0; k < scene.walkers[i].waypoints.size(); ++k) {
      EXPECT_NEAR(back.walkers[i].waypoints[k].time, scene.walkers[i].waypoints[k].time, 1e-8);
      EXPECT_NEAR(
          (back.walkers[i].waypoints[k].position - scene.walkers[i].waypoints[k].position).norm(),
          0.0, 1e-8);
    }
  }
  // Scenes without walkers write no key (their files stay as they were).
  EXPECT_EQ(SceneToYaml(MakePreset("desk_static", 1)).find("walkers"), std::string::npos);
  Scene bad = scene;
  bad.walkers[0].waypoints[1].time = bad.walkers[0].waypoints[0].time;
  EXPECT_THROW(bad.Check(), std::invalid_argument);
  EXPECT_THROW(ParseSceneYaml("walkers:\n  - id: 1\n    waypoints: [[0, 1, 2]]\n", "w.yaml"),
               SettingsError);
}

// Horizontal distance from p to the axis-aligned rectangle of a furniture item.
double DistanceToFootprint(const Eigen::Vector2d& p, const Furniture& item) {
  const Eigen::Vector2d half = 0.5 * item.size.head<2>();
  const Eigen::Vector2d outside =
      ((p - item.centre.head<2>()).cwiseAbs() - half).cwiseMax(Eigen::Vector2d::Zero());
  return outside.norm();
}

TEST(WalkersPreset, PeopleKeepClearOfFurnitureAndCameraAndComeNear) {
  const Scene scene = MakePreset("walkers", 1);
  double nearest = 1e9;
  for (const Walker& walker : scene.walkers) {
    for (double t = walker.StartTime(); t <= walker.EndTime(); t += 0.02) {
      const Eigen::Vector2d p = walker.PoseAt(t)->centre.head<2>();
      const Eigen::Vector2d eye = CameraPoseAt(scene, t).Inverse().translation().head<2>();
      nearest = std::min(nearest, (p - eye).norm());
      ASSERT_GE((p - eye).norm(), 1.0 - 1e-9) << "walker " << walker.id << " at " << t;
      ASSERT_LE(std::abs(p.x()) + walker.Radius(), scene.room_size.x() / 2);
      ASSERT_LE(std::abs(p.y()) + walker.Radius(), scene.room_size.y() / 2);
      for (const Furniture& item : scene.furniture) {
        if (item.name != "table_top" && item.name.rfind("cabinet", 0) != 0 &&
            item.name.rfind("shelf", 0) != 0) {
          continue;
        }
        ASSERT_GE(DistanceToFootprint(p, item), walker.Radius())
            << "walker " << walker.id << " walks into " << item.name << " at " << t;
      }
    }
  }
  EXPECT_LT(nearest, 1.2) << "no pass comes near the camera";
}

TEST(WalkersPreset, PeopleHideWhatStandsBehindThem) {
  const Scene scene = MakePreset("walkers", 1);
  SceneRenderer renderer(scene);
  Scene empty_scene = scene;
  empty_scene.walkers.clear();
  SceneRenderer empty(empty_scene);
  // The frame where people cover most of the image in the first 20 s.
  double best_t = 0.0, best = 0.0;
  for (double t = 0.0; t < 20.0; t += 0.5) {
    const double coverage = renderer.WalkerCoverage(t, CameraPoseAt(scene, t));
    if (coverage > best) {
      best = coverage;
      best_t = t;
    }
  }
  EXPECT_GT(best, 0.2) << "people cover at most " << best << " of the image";
  const SE3 T_cw = CameraPoseAt(scene, best_t);
  const cv::Mat with = renderer.Ids(best_t, T_cw), without = empty.Ids(best_t, T_cw);
  // Walker pixels are background (id 0) in the id pass: objects behind lose pixels.
  const int object_pixels_with = cv::countNonZero(with),
            object_pixels_without = cv::countNonZero(without);
  EXPECT_LT(object_pixels_with, object_pixels_without);
  EXPECT_EQ(cv::countNonZero((with != without) & (with != 0)), 0) << "a walker pixel got an id";
  EXPECT_EQ(empty.WalkerCoverage(best_t, T_cw), 0.0);
}

// The preset's first 5 s with people from the first second on, one crossing close in front
// of the camera: the SLAM initializes, tracks every frame after, stays accurate, and few map
// points are seen on people.
TEST(WalkersPreset, SlamTracksThroughPeopleAndKeepsThemOutOfTheMap) {
  const auto start = std::chrono::steady_clock::now();
  Scene scene = MakePreset("walkers", 1);
  scene.walkers = PlanWalkers(scene, 1, /*first_time=*/1.0);  // from the first second on
  scene.duration = 5.0;
  ASSERT_FALSE(scene.walkers.empty());
  SceneRenderer renderer(scene);
  const Vocabulary vocabulary =
      Vocabulary::Load(testing::SourceDir() + "/thirdparty/vocabulary/ocg_orb_vocabulary.ocgvoc");
  SystemConfig config;
  config.camera = scene.camera;
  config.fps = scene.fps;
  System system(config, vocabulary);
  std::vector<StampedPose> groundtruth;
  int first = -1, tracked = 0, tracked_behind_people = 0;
  double most_covered = 0.0;
  for (int frame = 0; frame < scene.FrameCount(); ++frame) {
    const double t = scene.TimeOfFrame(frame);
    const SE3 T_cw = CameraPoseAt(scene, t);
    const TrackingResult result = system.TrackImage(
        renderer.Colour(t, T_cw, static_cast<std::uint64_t>(frame)), t, std::to_string(t));
    const double coverage = renderer.WalkerCoverage(t, T_cw);
    most_covered = std::max(most_covered, coverage);
    if (result.T_cw) {
      if (first < 0) first = frame;
      ++tracked;
      tracked_behind_people += coverage >= 0.15 ? 1 : 0;
    }
    StampedPose pose;
    pose.timestamp = t;
    pose.T_wc = T_cw.Inverse();
    groundtruth.push_back(pose);
  }
  system.Shutdown();
  ASSERT_GE(first, 0) << "never initialized";
  EXPECT_LT(first, 30);
  EXPECT_GT(most_covered, 0.2) << "the clip has no large occluder";  // measured 0.22
  EXPECT_GT(tracked_behind_people, 10) << "frames tracked with people over 15 % of the image";
  EXPECT_GE(tracked, static_cast<int>(std::ceil(0.99 * (scene.FrameCount() - first))));
  const AteResult ate = ComputeAte(groundtruth, system.CameraTrajectory(), AteOptions());
  EXPECT_LT(ate.translation.rmse, 0.01) << "metres";
  // Map points a keyframe holds at a feature on a person (the true walker pixels of its
  // frame): points on movers, or static points matched to a person's feature.
  std::set<MapPointId> on_people;
  std::size_t observations = 0;
  for (const KeyFramePtr& keyframe : system.KeyFrames()) {
    if (keyframe->bad) continue;
    const cv::Mat mask =
        renderer.WalkerMask(keyframe->timestamp, CameraPoseAt(scene, keyframe->timestamp));
    for (std::size_t i = 0; i < keyframe->points.size(); ++i) {
      const MapPointPtr& point = keyframe->points[i];
      if (point == nullptr || point->bad) continue;
      ++observations;
      const cv::Point2f pixel = keyframe->features.keypoints[i].pt;
      if (mask.at<std::uint8_t>(cvRound(pixel.y), cvRound(pixel.x)) != 0)
        on_people.insert(point->id);
    }
  }
  const std::size_t points = system.MapPointCount();
  EXPECT_GT(observations, 0u);
  // Measured: 84 of 1,370 (6 %), 60 of them ghosts near the camera's height between the
  // camera and the person: local mapping triangulates a passing person's features between
  // consecutive keyframes (here 5 within half a second as the person passed), and a point
  // seen by 3-4 of them survives culling. A bound against more (docs/synthetic.md,
  // "Walkers"), not yet the target of none.
  EXPECT_LE(on_people.size(), points / 10)
      << on_people.size() << " of " << points << " map points seen on people";
  std::cout << "walkers: first tracked " << first << ", " << tracked << " of "
            << scene.FrameCount() - first << " after, " << tracked_behind_people
            << " with people over 15 %, people cover at most " << most_covered << ", ATE "
            << ate.translation.rmse << " m, map points seen on people " << on_people.size()
            << " of " << points << ", "
            << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()
            << " s\n";
}

}  // namespace
}  // namespace ocg::sim
