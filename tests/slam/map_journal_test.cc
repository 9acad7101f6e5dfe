// The map journal: a reader that keeps a copy of the map from what changed (the object
// layer) sees the map as a full read does, after points and keyframes are added, moved,
// culled or replaced, a loop correction and a merge; and what it reads after a change
// is the change, whatever the map's size.
#include "ocg/slam/map_journal.h"

#include <gtest/gtest.h>

#include <map>
#include <random>

#include "ocg/slam/map.h"
#include "ocg/slam/map_operations.h"
#include "random_map.h"
#include "test_support.h"

namespace ocg {
namespace {

// A reader's copy, kept from the changes.
struct Copy {
  std::optional<std::uint64_t> version;
  std::map<std::uint64_t, MapPointState> points;
  std::map<std::uint64_t, Eigen::Matrix3d> rotations;
  std::size_t read = 0;  // states in the last changes
  bool everything = false;

  void Follow(const Map& map) {
    const MapChanges changes = ChangesSince(map, version);
    version = changes.version;
    everything = changes.everything;
    read = changes.points.size() + changes.keyframes.size();
    if (changes.everything) {
      points.clear();
      rotations.clear();
    }
    for (const MapPointState& point : changes.points) {
      if (point.live) {
        points[point.id] = point;
      } else {
        points.erase(point.id);
      }
    }
    for (const KeyFrameState& keyframe : changes.keyframes) {
      if (keyframe.live) {
        rotations[keyframe.id] = keyframe.R_wc;
      } else {
        rotations.erase(keyframe.id);
      }
    }
  }
};

// The copy holds exactly what a full read gives, bit for bit.
void ExpectSameAsFullRead(const Copy& copy, const Map& map) {
  const MapChanges full = ChangesSince(map, std::nullopt);
  ASSERT_EQ(copy.points.size(), full.points.size());
  for (const MapPointState& point : full.points) {
    const auto found = copy.points.find(point.id);
    ASSERT_NE(found, copy.points.end()) << "point " << point.id;
    EXPECT_EQ(found->second.position, point.position) << "point " << point.id;
    EXPECT_EQ(found->second.descriptor, point.descriptor) << "point " << point.id;
  }
  ASSERT_EQ(copy.rotations.size(), full.keyframes.size());
  for (const KeyFrameState& keyframe : full.keyframes) {
    const auto found = copy.rotations.find(keyframe.id);
    ASSERT_NE(found, copy.rotations.end()) << "keyframe " << keyframe.id;
    EXPECT_EQ(found->second, keyframe.R_wc) << "keyframe " << keyframe.id;
  }
}

MapPointPtr NewPoint(Map& map, const Eigen::Vector3d& position) {
  auto point = std::make_shared<MapPoint>();
  point->id = map.NextMapPointId();
  point->position = position;
  point->map = map.current_map();
  map.Add(point);
  return point;
}

TEST(MapJournal, CopyFollowsAddsMovesCullsCorrectionsAndMerges) {
  Map map;
  testing::FillRandomMap(40, 60, 7, &map);
  Copy copy;
  copy.Follow(map);
  EXPECT_TRUE(copy.everything);
  ExpectSameAsFullRead(copy, map);

  // Nothing changed: nothing to read.
  copy.Follow(map);
  EXPECT_FALSE(copy.everything);
  EXPECT_EQ(copy.read, 0u);

  // Points added, with their descriptors set from their observations.
  std::vector<KeyFramePtr> live;
  for (const auto& [id, keyframe] : map.keyframes())
    if (!keyframe->bad) live.push_back(keyframe);
  for (int i = 0; i < 20; ++i) {
    const MapPointPtr point = NewPoint(map, Eigen::Vector3d(0.1 * i, 0.2, 3.0));
    for (int n = 0; n < 3; ++n) {
      const KeyFramePtr& keyframe = live[static_cast<std::size_t>(3 * i + n) % live.size()];
      for (std::size_t f = 1; f < keyframe->points.size(); f += 3) {
        if (keyframe->points[f]) continue;
        map.AddObservation(keyframe, static_cast<int>(f), point);
        break;
      }
    }
    map.UpdatePointDescriptor(point);
  }
  copy.Follow(map);
  EXPECT_FALSE(copy.everything);
  EXPECT_EQ(copy.read, 20u);
  ExpectSameAsFullRead(copy, map);

  // A bundle adjustment's write-back moves keyframes and points.
  const ScalePyramid pyramid = MakeScalePyramid(8, 1.2);
  const std::vector<KeyFramePtr> window(live.end() - 5, live.end());
  KeyFrameAdjustment adjustment = PrepareAdjustment(map, testing::TestCamera(), pyramid, window);
  ASSERT_FALSE(adjustment.points.empty());
  for (auto& point : adjustment.problem.points) point.position += Eigen::Vector3d(0.01, 0, 0);
  for (auto& keyframe : adjustment.problem.keyframes) {
    keyframe.T_cw = SE3(Eigen::Matrix3d(Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitY())),
                        Eigen::Vector3d::Zero()) *
                    keyframe.T_cw;
  }
  ApplyAdjustment(map, pyramid, adjustment);
  copy.Follow(map);
  EXPECT_FALSE(copy.everything);
  ExpectSameAsFullRead(copy, map);

  // Culls: a point erased, one replaced by another, one losing its views, a keyframe culled.
  std::vector<MapPointPtr> points;
  for (const auto& [id, point] : map.points()) points.push_back(point);
  map.ErasePoint(points[3]);
  map.ReplacePoint(points[5], points[6]);
  map.UpdatePointDescriptor(points[6]);
  while (!points[9]->observations.empty() && !points[9]->bad) {
    map.EraseObservation(map.GetKeyFrame(points[9]->observations.begin()->first), points[9]);
  }
  map.EraseKeyFrame(live[10]);
  copy.Follow(map);
  EXPECT_FALSE(copy.everything);
  EXPECT_EQ(copy.points.count(points[3]->id), 0u);
  EXPECT_EQ(copy.points.count(points[5]->id), 0u);
  EXPECT_EQ(copy.rotations.count(live[10]->id), 0u);
  ExpectSameAsFullRead(copy, map);

  // A loop correction moves the whole map: the copy reads it all.
  for (const auto& [id, point] : map.points()) point->position *= 1.5;
  map.CountCorrection();
  copy.Follow(map);
  EXPECT_TRUE(copy.everything);
  ExpectSameAsFullRead(copy, map);

  // A second map, merged into the first one's frame.
  const int second = map.StartNewMap();
  copy.Follow(map);
  EXPECT_TRUE(copy.everything);
  EXPECT_TRUE(copy.points.empty());
  for (int i = 0; i < 40; ++i) NewPoint(map, Eigen::Vector3d(0.0, 0.1 * i, 4.0));
  copy.Follow(map);
  EXPECT_FALSE(copy.everything);
  EXPECT_EQ(copy.points.size(), 40u);
  map.MoveMap(second, 0, Sim3(2.0, Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 0, 0)));
  copy.Follow(map);
  EXPECT_TRUE(copy.everything);
  ExpectSameAsFullRead(copy, map);
  EXPECT_GT(copy.points.size(), 40u);
}

// What a reader reads after a keyframe's worth of changes does not grow with the map.
TEST(MapJournal, ChangesReadDoNotDependOnTheMapSize) {
  std::vector<std::size_t> read;
  for (const int keyframes : {20, 400}) {
    Map map;
    testing::FillRandomMap(keyframes, 60, 3, &map);
    Copy copy;
    copy.Follow(map);
    EXPECT_GT(copy.read, static_cast<std::size_t>(keyframes * 10));
    for (int i = 0; i < 25; ++i) NewPoint(map, Eigen::Vector3d(0.1 * i, 0.0, 2.0));
    std::vector<MapPointPtr> points;
    for (const auto& [id, point] : map.points()) points.push_back(point);
    for (int i = 0; i < 10; ++i) map.ErasePoint(points[static_cast<std::size_t>(7 * i)]);
    copy.Follow(map);
    ExpectSameAsFullRead(copy, map);
    read.push_back(copy.read);
  }
  EXPECT_EQ(read[0], 35u);
  EXPECT_EQ(read[1], 35u);
}

// The changed points' states, each found by id (Map::FindPoint): runs of neighbours, lone
// points far apart, the first and the last point, culled ones, all read as a full read
// gives them.
TEST(MapJournal, ChangedPointsNearAndFarApartReadAsAFullRead) {
  Map map;
  testing::FillRandomMap(200, 60, 3, &map);
  Copy copy;
  copy.Follow(map);
  std::vector<MapPointPtr> points;
  for (const auto& [id, point] : map.points()) points.push_back(point);
  ASSERT_GT(points.size(), 500u);
  std::vector<std::size_t> changed = {0, points.size() - 1};
  for (std::size_t i = 100; i < 130; ++i) changed.push_back(i);                // a run
  for (std::size_t i = 131; i < 300; i += 3) changed.push_back(i);             // near, with gaps
  for (std::size_t i = 300; i < points.size(); i += 41) changed.push_back(i);  // far apart
  for (const std::size_t i : changed) {
    points[i]->position += Eigen::Vector3d(0.01, 0.0, 0.0);
    map.journal().Point(points[i]->id);  // as the adjustments' write-back notes it
  }
  for (const std::size_t i : {5u, 120u, 400u}) map.ErasePoint(points[i]);
  copy.Follow(map);
  EXPECT_FALSE(copy.everything);
  ExpectSameAsFullRead(copy, map);
}

// A point's descriptor is updated at each new observation and mostly stays as it was: the
// journal notes the update only when the descriptor changed (a reader that followed it
// would read the same state again).
TEST(MapJournal, ADescriptorUpdateIsNotedOnlyWhenTheDescriptorChanged) {
  Map map;
  testing::FillRandomMap(20, 60, 3, &map);
  MapPointPtr point;
  for (const auto& [id, candidate] : map.points()) {
    if (candidate->observations.size() >= 2) point = candidate;
  }
  ASSERT_NE(point, nullptr);
  map.UpdatePointDescriptor(point);
  const Descriptor descriptor = point->descriptor;
  const std::uint64_t version = map.journal().version();
  map.UpdatePointDescriptor(point);
  EXPECT_EQ(map.journal().version(), version);
  point->descriptor = Descriptor{};
  ASSERT_NE(point->descriptor, descriptor);
  map.UpdatePointDescriptor(point);
  EXPECT_EQ(point->descriptor, descriptor);
  EXPECT_EQ(map.journal().version(), version + 1);
}

// With a point tolerance, an adjustment's move is noted once the point is more than the
// tolerance from where the reader last read it: the reader's copy stays within the
// tolerance of the map and hears of a point after its moves add up, not at each one.
TEST(MapJournal, MovesBelowThePointToleranceFromTheLastReadAreNotNoted) {
  Map map;
  testing::FillRandomMap(20, 60, 3, &map);
  map.journal().SetPointTolerance(0.001);
  Copy copy;
  copy.Follow(map);
  auto it = map.points().begin();
  const MapPointPtr a = it->second, b = std::next(it)->second;
  const Eigen::Vector3d a_read = a->position, b_read = b->position;
  const auto move = [&](const MapPointPtr& point, double dx) {
    point->position += Eigen::Vector3d(dx, 0.0, 0.0);
    map.NotePointMoved(*point);  // as the adjustments' write-back
  };
  const std::uint64_t version = map.journal().version();
  move(a, 0.0006);
  move(b, 0.0006);
  EXPECT_EQ(map.journal().version(), version);  // within the tolerance of the last read
  move(a, 0.0006);                              // 1.2 mm from it: noted
  EXPECT_EQ(map.journal().version(), version + 1);
  copy.Follow(map);
  EXPECT_EQ(copy.points.at(a->id).position, a->position);
  EXPECT_EQ(copy.points.at(b->id).position, b_read);
  EXPECT_LE((copy.points.at(b->id).position - b->position).norm(), 0.001);
  // Read again at its new place: the next small move is measured from there.
  move(a, 0.0006);
  EXPECT_EQ(map.journal().version(), version + 1);
  EXPECT_NE(a->position, a_read);
  // Tolerance 0: every move is noted; a write-back that leaves a point where it was read
  // is not.
  map.journal().SetPointTolerance(0.0);
  const MapPointPtr c = std::next(it, 2)->second;
  move(c, 0.0);
  EXPECT_EQ(map.journal().version(), version + 1);
  move(c, 1e-9);
  EXPECT_EQ(map.journal().version(), version + 2);
  move(a, 0.0);  // 0.6 mm from where it was read
  move(b, 0.0);  // 0.6 mm
  EXPECT_EQ(map.journal().version(), version + 4);
  copy.Follow(map);
  ExpectSameAsFullRead(copy, map);
}

// The journal keeps at most its capacity: a reader further behind reads everything.
TEST(MapJournal, AReaderBehindTheBoundReadsEverything) {
  MapJournal journal(4);
  std::vector<std::uint64_t> points, keyframes;
  std::uint64_t now = 0;
  for (std::uint64_t id = 0; id < 3; ++id) journal.Point(id);
  EXPECT_TRUE(journal.ChangedSince(0, &points, &keyframes, &now));
  EXPECT_EQ(points, (std::vector<std::uint64_t>{0, 1, 2}));
  EXPECT_EQ(now, 3u);
  journal.KeyFrame(9);
  journal.Point(1);  // a point changed twice is read once
  EXPECT_TRUE(journal.ChangedSince(1, &points, &keyframes, &now));
  EXPECT_EQ(points, (std::vector<std::uint64_t>{1, 2}));
  EXPECT_EQ(keyframes, (std::vector<std::uint64_t>{9}));
  EXPECT_FALSE(journal.ChangedSince(0, &points, &keyframes, &now));  // entry 1 is gone
  EXPECT_TRUE(journal.ChangedSince(5, &points, &keyframes, &now));
  EXPECT_TRUE(points.empty());
  journal.Everything();
  EXPECT_FALSE(journal.ChangedSince(5, &points, &keyframes, &now));
  EXPECT_TRUE(journal.ChangedSince(6, &points, &keyframes, &now));
}

}  // namespace
}  // namespace ocg
