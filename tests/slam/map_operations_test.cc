// Bundle adjustment in three steps (prepare, solve, apply), as the global adjustment after
// a loop and local mapping run it: on a copy, while the map goes on growing.

#include "ocg/slam/map_operations.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <future>
#include <random>
#include <thread>

#include "ocg/slam/local_mapping.h"

#include "test_support.h"

namespace ocg {
namespace {

PinholeCamera Camera() { return testing::TestCamera(); }

// Cameras on the x axis looking along +z at points 3-5 m away; every keyframe sees every
// point, at its exact projection.
class GrowingMap : public ::testing::Test {
 protected:
  static constexpr int kPoints = 60;

  GrowingMap() : pyramid_(MakeScalePyramid(8, 1.2)) {
    for (int i = 0; i < kPoints; ++i) {
      truth_points_.emplace_back(-1.0 + 0.05 * i, 0.5 * std::sin(i), 3.0 + (i % 5) * 0.5);
    }
    for (int k = 0; k < 4; ++k) AddKeyFrame(TruePose(k));
    for (int i = 0; i < kPoints; ++i) {
      auto point = std::make_shared<MapPoint>();
      point->id = map_.NextMapPointId();
      point->position = truth_points_[static_cast<std::size_t>(i)];
      point->reference = 0;
      map_.Add(point);
      for (const auto& [id, keyframe] : map_.keyframes()) map_.AddObservation(keyframe, i, point);
    }
    for (const auto& [id, keyframe] : map_.keyframes()) map_.UpdateConnections(keyframe);
  }

  static SE3 TruePose(int k) {
    return SE3(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-0.3 * k, 0, 0));
  }

  KeyFramePtr AddKeyFrame(const SE3& T_cw) {
    KeyFramePtr keyframe = MakeKeyFrame(T_cw);
    map_.Add(keyframe);
    return keyframe;
  }

  // A keyframe as tracking hands it to local mapping: not in the map yet.
  KeyFramePtr MakeKeyFrame(const SE3& T_cw) {
    auto keyframe = std::make_shared<KeyFrame>();
    keyframe->id = map_.NextKeyFrameId();
    keyframe->T_cw = T_cw;
    for (const Eigen::Vector3d& point : truth_points_) {
      const Eigen::Vector2d pixel = Camera().ProjectUndistorted(TruePose(0) * point);
      keyframe->features.keypoints.emplace_back(static_cast<float>(pixel.x()),
                                                static_cast<float>(pixel.y()), 31.0f);
      keyframe->features.undistorted.push_back(
          Camera().ProjectUndistorted(TruePose(static_cast<int>(keyframe->id)) * point));
    }
    keyframe->features.descriptors.assign(truth_points_.size(), Descriptor{});
    keyframe->points.assign(truth_points_.size(), nullptr);
    return keyframe;
  }

  // Keyframe 4, 5 cm off its true place, seeing every point (tracking matched them), given
  // to local mapping; before_solve runs where the local adjustment is about to be solved.
  // Returns how far from its true centre keyframe 4 ends.
  double MapAFifthKeyFrame(const std::function<void()>& before_solve, LocalMappingStats* stats) {
    const KeyFramePtr keyframe = MakeKeyFrame(SE3());
    const SE3 truth = TruePose(static_cast<int>(keyframe->id));
    keyframe->T_cw = SE3(Eigen::Matrix3d::Identity(), truth.translation() + kOffset);
    for (const auto& [id, point] : map_.points()) {
      keyframe->points[static_cast<std::size_t>(point->observations.begin()->second)] = point;
    }
    BowDatabase database(16);
    LocalMapping mapping(Camera(), pyramid_, MatcherOptions{}, LocalMappingOptions{}, &map_,
                         &database);
    mapping.SetBeforeLocalSolve(before_solve);
    mapping.ProcessKeyFrame(keyframe);
    *stats = mapping.Stats();
    return (keyframe->Centre() - truth.Inverse().translation()).norm();
  }

  // A keyframe as tracking hands it over, at its true place, matched to every map point.
  KeyFramePtr TrackedKeyFrame() {
    const KeyFramePtr keyframe = MakeKeyFrame(SE3());
    keyframe->T_cw = TruePose(static_cast<int>(keyframe->id));
    for (const auto& [id, point] : map_.points()) {
      keyframe->points[static_cast<std::size_t>(point->observations.begin()->second)] = point;
    }
    return keyframe;
  }

  // New points that keyframes 3 and 4 both see but the map has none for: keyframe 3
  // holds features for them without points, keyframe 4 (at its true place, returned)
  // comes to local mapping with them, after the kPoints features of the map's points.
  // Every feature is under one vocabulary node and each new point has a descriptor of its
  // own, so triangulation pairs them one to one.
  KeyFramePtr KeyFrameFourSeeingNewPoints(std::vector<Eigen::Vector3d>* new_points) {
    std::vector<Eigen::Vector3d>& fresh = *new_points;
    for (int i = 0; i < 20; ++i)
      fresh.emplace_back(-0.6 + 0.06 * i, 0.3 * std::cos(i), 3.5 + (i % 4) * 0.4);
    std::mt19937_64 rng(7);
    std::vector<Descriptor> descriptors;
    for (std::size_t i = 0; i < fresh.size(); ++i)
      descriptors.push_back({rng(), rng(), rng(), rng()});
    const auto add_fresh_features = [&](const KeyFramePtr& keyframe) {
      for (std::size_t i = 0; i < fresh.size(); ++i) {
        const Eigen::Vector2d pixel = Camera().ProjectUndistorted(keyframe->T_cw * fresh[i]);
        keyframe->features.keypoints.emplace_back(static_cast<float>(pixel.x()),
                                                  static_cast<float>(pixel.y()), 31.0f);
        keyframe->features.undistorted.push_back(pixel);
        keyframe->features.descriptors.push_back(descriptors[i]);
        keyframe->points.push_back(nullptr);
      }
      std::vector<int>& node = keyframe->feature_vector[0];
      for (std::size_t f = 0; f < keyframe->points.size(); ++f) node.push_back(static_cast<int>(f));
    };
    add_fresh_features(map_.GetKeyFrame(3));
    const KeyFramePtr keyframe = TrackedKeyFrame();
    add_fresh_features(keyframe);
    return keyframe;
  }

  // The new points of KeyFrameFourSeeingNewPoints that keyframe holds now, with their true
  // positions.
  static std::vector<std::pair<MapPointPtr, Eigen::Vector3d>> NewPointsOf(
      const KeyFrame& keyframe, const std::vector<Eigen::Vector3d>& new_points) {
    std::vector<std::pair<MapPointPtr, Eigen::Vector3d>> created;
    for (std::size_t i = 0; i < new_points.size(); ++i) {
      const MapPointPtr& point = keyframe.points[static_cast<std::size_t>(kPoints) + i];
      if (point) created.emplace_back(point, new_points[i]);
    }
    return created;
  }

  // Maps keyframe 4 of KeyFrameFourSeeingNewPoints; before_triangulation runs where the
  // pairs are about to be found without the lock. Returns the points that local mapping
  // created, with the new points' true positions.
  std::vector<std::pair<MapPointPtr, Eigen::Vector3d>> TriangulateNewPointsOfKeyFrameFour(
      const std::function<void()>& before_triangulation) {
    std::vector<Eigen::Vector3d> fresh;
    const KeyFramePtr keyframe = KeyFrameFourSeeingNewPoints(&fresh);
    BowDatabase database(16);
    LocalMappingOptions options;
    options.triangulation_neighbours = 4;  // keyframe 3, the one holding the features, among them
    LocalMapping mapping(Camera(), pyramid_, MatcherOptions{}, options, &map_, &database);
    mapping.SetBeforeTriangulation(before_triangulation);
    mapping.ProcessKeyFrame(keyframe);
    return NewPointsOf(*keyframe, fresh);
  }

  const Eigen::Vector3d kOffset{0.05, 0.0, 0.0};

  Map map_;
  ScalePyramid pyramid_;
  std::vector<Eigen::Vector3d> truth_points_;
};

TEST_F(GrowingMap, WhatWasAddedDuringAnAdjustmentFollowsItsCorrection) {
  // Drift: the last two keyframes stand 5 cm off, the points 2 cm off.
  const Eigen::Vector3d drift(0.05, -0.02, 0.03);
  for (KeyFrameId id : {2, 3}) {
    const KeyFramePtr k = map_.GetKeyFrame(id);
    k->T_cw = SE3(Eigen::Matrix3d::Identity(), k->T_cw.translation() - drift);
  }
  for (const auto& [id, point] : map_.points()) point->position += Eigen::Vector3d(0, 0.02, 0);
  std::vector<KeyFramePtr> all;
  for (const auto& [id, keyframe] : map_.keyframes()) all.push_back(keyframe);
  KeyFrameAdjustment adjustment = PrepareAdjustment(map_, Camera(), pyramid_, all);

  // Meanwhile tracking adds a keyframe (a child of keyframe 3, 0.2 m further) and local
  // mapping a point it made.
  const KeyFramePtr k3 = map_.GetKeyFrame(3);
  const SE3 T_4_3(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-0.2, 0, 0));
  const KeyFramePtr k4 = AddKeyFrame(T_4_3 * k3->T_cw);
  k4->parent = 3;
  k4->has_parent = true;
  auto fresh = std::make_shared<MapPoint>();
  fresh->id = map_.NextMapPointId();
  fresh->position = k4->T_cw.Inverse() * Eigen::Vector3d(0.1, 0.2, 4.0);
  fresh->reference = k4->id;
  map_.Add(fresh);
  map_.AddObservation(k4, 0, fresh);
  const SE3 k3_before = k3->T_cw;

  ASSERT_TRUE(SolveAdjustment(&adjustment, 30));
  EXPECT_EQ(ApplyAdjustment(map_, pyramid_, adjustment), 2);  // k4 and the fresh point

  // Nothing was lost: five keyframes, every point.
  EXPECT_EQ(map_.keyframes().size(), 5u);
  EXPECT_EQ(map_.points().size(), static_cast<std::size_t>(kPoints + 1));
  EXPECT_FALSE(k4->bad);
  EXPECT_FALSE(fresh->bad);
  // The adjusted keyframes are back where they belong (the first holds the gauge).
  for (KeyFrameId id : {1, 2, 3}) {
    EXPECT_LT(
        (map_.GetKeyFrame(id)->Centre() - TruePose(static_cast<int>(id)).Inverse().translation())
            .norm(),
        0.01)
        << id;
  }
  EXPECT_GT((k3->T_cw.translation() - k3_before.translation()).norm(), 0.03);  // it did move
  // The new keyframe moved with its parent: same relative pose as when it was added.
  const SE3 relative = k4->T_cw * k3->T_cw.Inverse();
  EXPECT_LT((relative.translation() - T_4_3.translation()).norm(), 1e-9);
  // The fresh point moved with its reference keyframe: same place in its camera.
  EXPECT_LT((k4->T_cw * fresh->position - Eigen::Vector3d(0.1, 0.2, 4.0)).norm(), 1e-9);
}

// Tracking must not wait a whole local adjustment for the map: the solve runs without the
// map lock, and its result is written back.
TEST_F(GrowingMap, LocalMappingSolvesWithoutTheMapLock) {
  bool lock_was_free = false;
  LocalMappingStats stats;
  const double error = MapAFifthKeyFrame(
      [&] {
        std::thread tracker([&] {  // another thread, as tracking would be
          std::unique_lock<std::mutex> lock(map_.mutex(), std::try_to_lock);
          lock_was_free = lock.owns_lock();
        });
        tracker.join();
      },
      &stats);
  EXPECT_TRUE(lock_was_free);
  EXPECT_EQ(stats.ba_seconds.count(), 1u);
  EXPECT_EQ(stats.local_adjustments_dropped, 0);
  EXPECT_LT(error, 0.005) << "the adjustment was not applied";
}

// A loop correction merged while the local adjustment solved moved the whole map; writing
// the local solution over it would undo the correction, so it is dropped.
TEST_F(GrowingMap, LocalAdjustmentIsDroppedWhenALoopCorrectedTheMapMeanwhile) {
  LocalMappingStats stats;
  const double error = MapAFifthKeyFrame(
      [&] {
        std::lock_guard<std::mutex> lock(map_.mutex());
        map_.CountCorrection();
      },
      &stats);
  EXPECT_EQ(stats.local_adjustments_dropped, 1);
  EXPECT_EQ(stats.ba_seconds.count(), 0u);
  EXPECT_NEAR(error, kOffset.norm(), 1e-9) << "the stale adjustment was written";
}

// New points are matched and triangulated without the map lock, and created.
TEST_F(GrowingMap, TriangulationMatchesWithoutTheMapLock) {
  bool lock_was_free = false;
  const auto created = TriangulateNewPointsOfKeyFrameFour([&] {
    std::thread tracker([&] {
      std::unique_lock<std::mutex> lock(map_.mutex(), std::try_to_lock);
      lock_was_free = lock.owns_lock();
    });
    tracker.join();
  });
  EXPECT_TRUE(lock_was_free);
  ASSERT_GE(created.size(), 15u);
  for (const auto& [point, truth] : created) EXPECT_LT((point->position - truth).norm(), 1e-6);
}

// A correction merged while the pairs were found moved every keyframe and point: points
// triangulated from the poses copied before it would stand where the world was. They are
// triangulated again on the moved map.
TEST_F(GrowingMap, TriangulationFollowsACorrectionMadeMeanwhile) {
  const Eigen::Vector3d shift(0.2, -0.1, 0.05);  // a rigid move of the whole map
  const auto created = TriangulateNewPointsOfKeyFrameFour([&] {
    std::lock_guard<std::mutex> lock(map_.mutex());
    for (const auto& [id, keyframe] : map_.keyframes())
      keyframe->T_cw = keyframe->T_cw * SE3(Eigen::Matrix3d::Identity(), -shift);
    for (const auto& [id, point] : map_.points()) point->position += shift;
    map_.CountCorrection();
  });
  ASSERT_GE(created.size(), 15u);
  for (const auto& [point, truth] : created)
    EXPECT_LT((point->position - (truth + shift)).norm(), 1e-6) << "triangulated on stale poses";
}

// run.json's local_mapping_map_lock_held_per_keyframe must tell how long tracking could
// have been kept waiting: the time of the solve, made without the lock, is not in it.
TEST_F(GrowingMap, TimeHoldingTheMapLockLeavesOutTheSolve) {
  constexpr double kSolveDelay = 0.3;  // seconds spent "solving" without the lock
  LocalMappingStats stats;
  MapAFifthKeyFrame(
      [&] { std::this_thread::sleep_for(std::chrono::duration<double>(kSolveDelay)); }, &stats);
  ASSERT_EQ(stats.keyframe_seconds.count(), 1u);
  ASSERT_EQ(stats.map_lock_held_seconds.count(), 1u);
  // One keyframe: its time is the summary's maximum (kept exact).
  EXPECT_GE(stats.keyframe_seconds.max(), kSolveDelay);
  EXPECT_GE(stats.map_lock_held_seconds.max(), 0.0);
  EXPECT_LE(stats.map_lock_held_seconds.max(), stats.keyframe_seconds.max() - kSolveDelay + 1e-6);
}

// Threaded local mapping catches up as ORB-SLAM2's does: while more keyframes wait, a
// keyframe is linked and its new points triangulated, but its local adjustment (and
// keyframe culling) is skipped; the last one of the queue is adjusted.
TEST_F(GrowingMap, WhileKeyFramesWaitTheLocalAdjustmentIsSkippedButEachKeyFrameIsMapped) {
  std::vector<Eigen::Vector3d> fresh;
  const KeyFramePtr four = KeyFrameFourSeeingNewPoints(&fresh);
  const KeyFramePtr five = TrackedKeyFrame();
  const KeyFramePtr six = TrackedKeyFrame();
  BowDatabase database(16);
  LocalMappingOptions options;
  options.triangulation_neighbours = 4;
  LocalMapping mapping(Camera(), pyramid_, MatcherOptions{}, options, &map_, &database);
  // Keyframe 4 waits in triangulation until 5 and 6 are queued behind it.
  std::promise<void> all_queued;
  std::shared_future<void> queued = all_queued.get_future().share();
  std::atomic<int> triangulations{0};
  mapping.SetBeforeTriangulation([&] {
    if (triangulations++ == 0) queued.wait();
  });
  // What each keyframe looks like once mapped (before later keyframes cull anything).
  struct Mapped {
    KeyFrameId id;
    bool in_map;
    int observed;  // map points that list it as an observer
    std::size_t new_points;
  };
  std::vector<Mapped> mapped;
  mapping.SetKeyFrameMapped([&](const KeyFramePtr& keyframe) {
    std::lock_guard<std::mutex> lock(map_.mutex());
    int observed = 0;
    for (const auto& [id, point] : map_.points())
      observed += point->observations.count(keyframe->id);
    std::size_t new_points = 0;
    if (keyframe == four) {
      for (const auto& [point, truth] : NewPointsOf(*four, fresh))
        new_points += (point->position - truth).norm() < 1e-6 ? 1 : 0;
    }
    mapped.push_back({keyframe->id, map_.GetKeyFrame(keyframe->id) == keyframe && !keyframe->bad,
                      observed, new_points});
  });
  mapping.Start();
  for (const KeyFramePtr& keyframe : {four, five, six}) mapping.Insert(keyframe);
  all_queued.set_value();
  mapping.Stop();

  const LocalMappingStats stats = mapping.Stats();
  EXPECT_EQ(stats.keyframes, 3);
  EXPECT_EQ(stats.local_adjustments_skipped, 2);  // 4 (5 and 6 waiting) and 5 (6 waiting)
  EXPECT_EQ(stats.ba_seconds.count(), 1u);        // 6's
  EXPECT_EQ(stats.local_adjustments_interrupted, 0);
  ASSERT_EQ(mapped.size(), 3u);
  for (std::size_t i = 0; i < mapped.size(); ++i) {
    EXPECT_EQ(mapped[i].id, 4 + i);
    EXPECT_TRUE(mapped[i].in_map) << mapped[i].id;
    EXPECT_GE(mapped[i].observed, kPoints) << mapped[i].id;
  }
  EXPECT_GE(mapped[0].new_points, 15u) << "keyframe 4's new points were not triangulated";
}

// A keyframe inserted while the local adjustment solves stops it at the end of the
// iteration under way: the mapper takes the new keyframe instead of finishing a window
// that the new keyframe's adjustment solves again anyway.
TEST_F(GrowingMap, AKeyFrameInsertedWhileTheLocalAdjustmentSolvesStopsIt) {
  const KeyFramePtr four = TrackedKeyFrame();
  const SE3 truth = four->T_cw;
  four->T_cw = SE3(Eigen::Matrix3d::Identity(), truth.translation() + kOffset);
  const KeyFramePtr five = TrackedKeyFrame();
  BowDatabase database(16);
  LocalMapping mapping(Camera(), pyramid_, MatcherOptions{}, LocalMappingOptions{}, &map_,
                       &database);
  int solves = 0;
  mapping.SetBeforeLocalSolve([&] {
    if (solves++ > 0) return;
    std::thread tracker([&] { mapping.Insert(five); });  // as tracking would
    tracker.join();
  });
  mapping.Start();
  mapping.Insert(four);
  mapping.Stop();

  const LocalMappingStats stats = mapping.Stats();
  EXPECT_EQ(stats.local_adjustments_interrupted, 1);
  EXPECT_EQ(stats.local_adjustments_skipped, 0);  // 5 came after 4's adjustment had begun
  ASSERT_EQ(stats.ba_iterations.size(), 2u);
  EXPECT_EQ(stats.ba_iterations[0], 1) << "4's adjustment went on after the request";
  EXPECT_GT(stats.ba_iterations[1], 2);
  // 5's adjustment, which has 4 in its window, brought 4 back.
  EXPECT_LT((four->Centre() - truth.Inverse().translation()).norm(), 0.005);
}

}  // namespace
}  // namespace ocg
