#include "ocg/slam/map.h"

#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

namespace ocg {
namespace {

// Keyframes at x = 0, 1, 2, ... with `features` empty feature slots each.
KeyFramePtr AddKeyFrame(Map& map, int features) {
  auto keyframe = std::make_shared<KeyFrame>();
  keyframe->id = map.NextKeyFrameId();
  keyframe->T_cw =
      SE3(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-static_cast<double>(keyframe->id), 0, 0));
  keyframe->features.keypoints.assign(static_cast<std::size_t>(features), cv::KeyPoint(10, 10, 31));
  keyframe->features.descriptors.assign(static_cast<std::size_t>(features), Descriptor{});
  keyframe->points.assign(static_cast<std::size_t>(features), nullptr);
  map.Add(keyframe);
  return keyframe;
}

MapPointPtr AddPoint(Map& map, const std::vector<std::pair<KeyFramePtr, int>>& seen_by) {
  auto point = std::make_shared<MapPoint>();
  point->id = map.NextMapPointId();
  point->position = {0.5, 0.0, 3.0};
  point->reference = seen_by.front().first->id;
  map.Add(point);
  for (const auto& [keyframe, feature] : seen_by) map.AddObservation(keyframe, feature, point);
  return point;
}

// A frame placed on a keyframe that still waits for local mapping (threaded mode), and a
// merge meanwhile moves the keyframe's map into another under a scale: the frame is
// found through that keyframe's own anchor (a keyframe of the map), its relative
// translation taken into the new map's units.
TEST(Map, APoseOnAKeyFrameNotYetLinkedFollowsAMergeThroughItsAnchor) {
  Map map;
  map.StartNewMap();                               // map 1, merged into map 0 below
  const KeyFramePtr linked = AddKeyFrame(map, 0);  // map 1, at x = 0
  linked->map = 1;
  const SE3 T_pending_cw(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-0.4, 0.0, 0.0));
  auto pending = std::make_shared<KeyFrame>();  // at x = 0.4: made by tracking, queued
  pending->id = map.NextKeyFrameId();
  pending->T_cw = T_pending_cw;
  pending->map = 1;
  pending->anchor = Anchor{linked, T_pending_cw * linked->T_cw.Inverse(), 1, map.corrections()};
  const SE3 T_frame_cw(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-0.5, 0.0, 0.0));
  const Anchor frame{pending, T_frame_cw * pending->T_cw.Inverse(), 1, map.corrections()};
  // Map 1 goes into map 0 at half the scale, shifted by 2 m along y.
  const Sim3 S_into_from(0.5, Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.0, 2.0, 0.0));
  map.MoveMap(1, 0, S_into_from);
  map.CountCorrection();
  EXPECT_DOUBLE_EQ(map.ScaleInto(1, 0), 0.5);
  EXPECT_DOUBLE_EQ(map.ScaleInto(0, 0), 1.0);
  const std::optional<AnchoredPose> pose = PoseFromAnchor(map, frame);
  ASSERT_TRUE(pose);
  EXPECT_EQ(pose->map, 0);
  // The frame stood at x = 0.5 in map 1: x = 0.25, y = 2 in map 0.
  EXPECT_LT((pose->T_cw.Inverse().translation() - Eigen::Vector3d(0.25, 2.0, 0.0)).norm(), 1e-12);
}

// Local mapping, holding the lock between two steps, lets a tracker that waits for it go
// first; the mutex alone would let local mapping go on (it still holds the lock) and the
// tracker would wait for every later step too.
TEST(MapLock, AWaitingTrackerGoesBeforeTheNextStepOfLocalMapping) {
  Map map;
  std::vector<std::string> order;  // written under the map lock only
  std::unique_lock<std::mutex> mapping(map.mutex());
  EXPECT_FALSE(map.LetWaitingTrackerIn(mapping));  // nobody waits: keeps the lock
  EXPECT_TRUE(mapping.owns_lock());
  std::thread tracker([&] {
    const std::unique_lock<std::mutex> lock = map.LockForTracking();
    order.push_back("tracker");
  });
  while (!map.TrackerWaiting()) std::this_thread::yield();
  EXPECT_TRUE(map.LetWaitingTrackerIn(mapping, std::chrono::seconds(10)));
  EXPECT_TRUE(mapping.owns_lock());
  order.push_back("mapping");
  mapping.unlock();
  tracker.join();
  EXPECT_EQ(order, (std::vector<std::string>{"tracker", "mapping"}));
  EXPECT_FALSE(map.TrackerWaiting());
}

TEST(Map, CovisibilityNeedsFifteenSharedPointsOrTakesTheBest) {
  Map map;
  const KeyFramePtr a = AddKeyFrame(map, 40);
  const KeyFramePtr b = AddKeyFrame(map, 40);
  const KeyFramePtr c = AddKeyFrame(map, 40);
  for (int i = 0; i < 20; ++i) AddPoint(map, {{a, i}, {b, i}});      // a-b: 20
  for (int i = 20; i < 30; ++i) AddPoint(map, {{a, i}, {c, i}});     // a-c: 10
  for (int i = 0; i < 5; ++i) AddPoint(map, {{b, 20 + i}, {c, i}});  // b-c: 5
  map.UpdateConnections(b);
  map.UpdateConnections(c);
  map.UpdateConnections(a);
  EXPECT_EQ(a->covisible.at(b->id), 20);
  EXPECT_EQ(a->covisible.count(c->id), 0u);  // 10 < 15
  // c shares fewer than 15 with everyone: it keeps an edge to its best (a, 10).
  ASSERT_EQ(c->covisible.size(), 1u);
  EXPECT_EQ(c->covisible.at(a->id), 10);
  EXPECT_EQ(a->ordered_covisible.front(), b->id);
  // Spanning tree: a later keyframe's parent is its best covisible keyframe.
  EXPECT_TRUE(b->has_parent);
  EXPECT_EQ(b->parent, a->id);
  EXPECT_TRUE(a->children.count(b->id));
  EXPECT_FALSE(a->has_parent);  // the first keyframe is the root
}

TEST(Map, APointLeftWithTwoViewsOrFewerIsErased) {
  // ORB-SLAM2's rule for monocular points: two views are the least a point is made from,
  // and one that has lost views down to two is not trusted any more.
  Map map;
  const KeyFramePtr a = AddKeyFrame(map, 4);
  const KeyFramePtr b = AddKeyFrame(map, 4);
  const KeyFramePtr c = AddKeyFrame(map, 4);
  const KeyFramePtr d = AddKeyFrame(map, 4);
  const MapPointPtr point = AddPoint(map, {{a, 0}, {b, 1}, {c, 2}, {d, 3}});
  map.EraseObservation(a, point);
  EXPECT_FALSE(point->bad);
  EXPECT_EQ(point->observations.size(), 3u);
  EXPECT_EQ(a->points[0], nullptr);
  EXPECT_NE(point->reference, a->id);  // the reference moved to a keyframe that sees it
  map.EraseObservation(b, point);
  EXPECT_TRUE(point->bad);
  EXPECT_EQ(map.points().count(point->id), 0u);
  EXPECT_EQ(c->points[2], nullptr);
  EXPECT_EQ(d->points[3], nullptr);
}

TEST(Map, ReplacingAPointMovesItsObservations) {
  Map map;
  const KeyFramePtr a = AddKeyFrame(map, 4);
  const KeyFramePtr b = AddKeyFrame(map, 4);
  const KeyFramePtr c = AddKeyFrame(map, 4);
  const MapPointPtr keep = AddPoint(map, {{a, 0}, {b, 0}});
  const MapPointPtr duplicate = AddPoint(map, {{b, 1}, {c, 1}});
  map.ReplacePoint(duplicate, keep);
  EXPECT_TRUE(duplicate->bad);
  EXPECT_EQ(map.points().count(duplicate->id), 0u);
  EXPECT_EQ(keep->observations.size(), 3u);  // a, b (already), c
  EXPECT_EQ(c->points[1], keep);
  EXPECT_EQ(b->points[0], keep);
  EXPECT_EQ(b->points[1], nullptr);  // b saw both: the second slot is freed
}

// FindPoint's hash index holds what points() holds, through every way a point enters or
// leaves the map: added (also again under its id), culled, replaced, a map reset, Clear.
TEST(Map, FindPointAgreesWithThePointsAfterAddsCullsReplacementsAndResets) {
  Map map;
  const auto expect_agrees = [&map](const char* after) {
    SCOPED_TRACE(after);
    for (MapPointId id = 0; id < map.next_map_point_id() + 2; ++id) {
      const auto held = map.points().find(id);
      EXPECT_EQ(map.FindPoint(id), held == map.points().end() ? nullptr : held->second.get())
          << "point " << id;
    }
  };
  std::vector<KeyFramePtr> keyframes;
  for (int k = 0; k < 6; ++k) keyframes.push_back(AddKeyFrame(map, 40));
  std::vector<MapPointPtr> points;
  for (int i = 0; i < 30; ++i) {
    const std::size_t k = static_cast<std::size_t>(i % 3);
    points.push_back(AddPoint(
        map,
        {{keyframes[k], i}, {keyframes[k + 1], i}, {keyframes[k + 2], i}, {keyframes[k + 3], i}}));
  }
  expect_agrees("adds");
  map.ErasePoint(points[0]);
  map.ErasePoint(points[29]);
  map.EraseObservation(keyframes[0], points[3]);
  map.EraseObservation(keyframes[1], points[3]);  // two views left: culled
  expect_agrees("culls");
  map.ReplacePoint(points[7], points[8]);
  map.ReplacePoint(points[10], points[9]);
  expect_agrees("replacements");
  auto again = std::make_shared<MapPoint>(*points[12]);  // the same id, another point
  map.Add(again);
  expect_agrees("an id added again");
  EXPECT_EQ(map.FindPoint(points[12]->id), again.get());
  EXPECT_EQ(map.FindPoint(map.next_map_point_id()), nullptr);  // never made
  const int second = map.StartNewMap();
  const KeyFramePtr other = AddKeyFrame(map, 4);
  other->map = second;
  const KeyFramePtr other_b = AddKeyFrame(map, 4);
  other_b->map = second;
  const KeyFramePtr other_c = AddKeyFrame(map, 4);
  other_c->map = second;
  const MapPointPtr in_second = AddPoint(map, {{other, 0}, {other_b, 0}, {other_c, 0}});
  in_second->map = second;
  expect_agrees("a second map");
  map.EraseMap(second);
  expect_agrees("a map reset");
  EXPECT_EQ(map.FindPoint(in_second->id), nullptr);
  EXPECT_NE(map.FindPoint(points[1]->id), nullptr);
  map.Clear();
  expect_agrees("Clear");
  EXPECT_EQ(map.FindPoint(points[1]->id), nullptr);
}

TEST(Map, ErasingAKeyFrameHandsItsChildrenToItsParent) {
  Map map;
  const KeyFramePtr a = AddKeyFrame(map, 60);
  const KeyFramePtr b = AddKeyFrame(map, 60);
  const KeyFramePtr c = AddKeyFrame(map, 60);
  for (int i = 0; i < 20; ++i) AddPoint(map, {{a, i}, {b, i}, {c, i}});
  for (int i = 20; i < 40; ++i) AddPoint(map, {{b, i}, {c, i}});
  map.UpdateConnections(a);
  map.UpdateConnections(b);
  map.UpdateConnections(c);
  ASSERT_EQ(b->parent, a->id);  // b shares more with c, but c is newer
  ASSERT_EQ(c->parent, b->id);  // c shares 40 with b, 20 with a
  map.EraseKeyFrame(b);
  EXPECT_TRUE(b->bad);
  EXPECT_EQ(c->parent, a->id);
  EXPECT_TRUE(a->children.count(c->id));
  EXPECT_EQ(a->covisible.count(b->id), 0u);
  // Points left with two views or fewer are gone (all of them here).
  for (int i = 0; i < 40; ++i) EXPECT_EQ(c->points[static_cast<std::size_t>(i)], nullptr);
  EXPECT_TRUE(map.points().empty());
  // The first keyframe is never erased.
  map.EraseKeyFrame(a);
  EXPECT_FALSE(a->bad);
}

// A culled keyframe stays for the frames placed relative to it, but its features, BoW
// vectors and point slots (most of its memory) go: a long run revisiting places makes and
// culls keyframes there without end, and kept them whole.
TEST(Map, AnErasedKeyFrameKeepsOnlyWhatPosesRelativeToItNeed) {
  Map map;
  const KeyFramePtr a = AddKeyFrame(map, 60);
  const KeyFramePtr b = AddKeyFrame(map, 60);
  for (int i = 0; i < 20; ++i) AddPoint(map, {{a, i}, {b, i}});
  map.UpdateConnections(a);
  map.UpdateConnections(b);
  b->bow.entries = {{3, 0.5}, {7, 0.5}};
  b->feature_vector[2] = {0, 1};
  b->T_cw = SE3(Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY())),
                Eigen::Vector3d(0.1, 0.0, -0.2));
  const SE3 T_c_b(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.0, 0.05, 0.0));
  const Eigen::Matrix4d before = PoseFromReference(map, b->id, T_c_b)->Matrix();
  map.EraseKeyFrame(b);
  ASSERT_TRUE(b->bad);
  EXPECT_EQ(b->features.size(), 0u);
  EXPECT_EQ(b->features.descriptors.capacity(), 0u);
  EXPECT_EQ(b->features.undistorted.capacity(), 0u);
  EXPECT_TRUE(b->bow.empty());
  EXPECT_TRUE(b->feature_vector.empty());
  EXPECT_EQ(b->points.capacity(), 0u);
  // Frames placed relative to it still find their pose, and follow its parent.
  ASSERT_TRUE(PoseFromReference(map, b->id, T_c_b));
  EXPECT_TRUE(PoseFromReference(map, b->id, T_c_b)->Matrix().isApprox(before, 1e-12));
  a->T_cw = SE3(Eigen::Quaterniond::Identity(), Eigen::Vector3d(1.0, 0.0, 0.0)) * a->T_cw;
  EXPECT_FALSE(PoseFromReference(map, b->id, T_c_b)->Matrix().isApprox(before, 1e-6));
}

TEST(Map, DistinctiveDescriptorHasTheLeastMedianDistance) {
  Map map;
  std::vector<KeyFramePtr> keyframes;
  for (int k = 0; k < 4; ++k) keyframes.push_back(AddKeyFrame(map, 1));
  // Three similar descriptors and one far away: the distinctive one is the middle one.
  keyframes[0]->features.descriptors[0] = {0b0001, 0, 0, 0};
  keyframes[1]->features.descriptors[0] = {0b0011, 0, 0, 0};
  keyframes[2]->features.descriptors[0] = {0b0111, 0, 0, 0};
  keyframes[3]->features.descriptors[0] = {~0ull, ~0ull, 0, 0};
  const MapPointPtr point =
      AddPoint(map, {{keyframes[0], 0}, {keyframes[1], 0}, {keyframes[2], 0}, {keyframes[3], 0}});
  map.UpdatePointDescriptor(point);
  EXPECT_EQ(point->descriptor, keyframes[1]->features.descriptors[0]);
  // Geometry: the normal points from the cameras to the point; scale distances follow
  // the reference observation's level.
  map.UpdatePointGeometry(point, MakeScalePyramid(8, 1.2));
  EXPECT_GT(point->normal.z(), 0.5);
  const double distance = (point->position - keyframes[0]->Centre()).norm();
  EXPECT_NEAR(point->max_distance, distance, 1e-9);  // level 0
  EXPECT_NEAR(point->min_distance, distance / std::pow(1.2, 7), 1e-9);
}

}  // namespace
}  // namespace ocg
