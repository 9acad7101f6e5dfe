// ObjectPoints: what is derived from an object's points is kept through the changes that
// cannot alter it, and is always what a fresh computation gives.
#include <gtest/gtest.h>

#include <random>
#include <utility>

#include "ocg/objects/map_object.h"

namespace ocg {
namespace {

Eigen::Vector3d PositionOf(int i) {
  return Eigen::Vector3d(0.01 * (i % 7) - 0.03, 0.013 * (i % 5) - 0.026, 0.01 * i);
}

// An object with a cuboid at the origin and n points on it, each with votes votes, plus
// one far behind it (the background caught in its boxes).
MapObject ObjectWithPoints(int n, int votes) {
  MapObject object;
  object.has_cuboid = true;
  object.cuboid.size = Eigen::Vector3d(0.4, 0.4, 0.4);
  for (int i = 0; i < n; ++i)
    object.points.Vote(static_cast<std::uint64_t>(i), votes, PositionOf(i));
  object.points.Vote(1000, votes, Eigen::Vector3d(0, 0, 3.0));
  return object;
}

// ObjectWithPoints(12, 3) and a point with 1 vote among them (id 50), its set read at 3
// votes (cached).
MapObject WithAnUncountedPoint() {
  MapObject object = ObjectWithPoints(12, 3);
  object.points.Vote(50, 1, Eigen::Vector3d(0.0, 0.0, 0.05));
  PointSetOf(object, 3);
  return object;
}

// The point set as ObjectPointIds defines it, computed here from scratch.
ObjectPoints::PointSet FreshSet(const MapObject& object, int min_votes) {
  std::vector<std::uint64_t> ids;
  std::vector<Eigen::Vector3d> positions;
  for (const auto& [id, point] : object.points) {
    if (point.votes < min_votes) continue;
    if (object.has_cuboid &&
        (point.position - object.cuboid.centre).norm() > object.cuboid.size.maxCoeff())
      continue;
    ids.push_back(id);
    positions.push_back(point.position);
  }
  ObjectPoints::PointSet set;
  const RobustBounds bounds = RobustPointBounds(positions, 3.0);
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (bounds.valid && !bounds.Contains(positions[i])) continue;
    set.ids.push_back(ids[i]);
    set.positions.push_back(positions[i]);
  }
  set.bounds = RobustPointBounds(set.positions, 3.0);
  return set;
}

std::vector<std::uint64_t> FreshIds(const MapObject& object, int min_votes) {
  return FreshSet(object, min_votes).ids;
}

// Whether the object's (cached) point set holds the point.
bool InSet(const MapObject& object, std::uint64_t id, int min_votes) {
  const std::vector<std::uint64_t>& ids = PointSetOf(object, min_votes).ids;
  return std::find(ids.begin(), ids.end(), id) != ids.end();
}

int FreshCount(const MapObject& object, int min_votes) {
  int count = 0;
  for (const auto& [id, point] : object.points) count += point.votes >= min_votes;
  return count;
}

// The cached set and count are what a fresh computation gives, member by member.
void ExpectFresh(const MapObject& object, int min_votes) {
  const ObjectPoints::PointSet& cached = PointSetOf(object, min_votes);
  const ObjectPoints::PointSet fresh = FreshSet(object, min_votes);
  EXPECT_EQ(cached.ids, fresh.ids);
  EXPECT_EQ(cached.positions, fresh.positions);
  EXPECT_EQ(cached.bounds.valid, fresh.bounds.valid);
  if (fresh.bounds.valid) {
    EXPECT_EQ(cached.bounds.low, fresh.bounds.low);
    EXPECT_EQ(cached.bounds.high, fresh.bounds.high);
  }
  EXPECT_EQ(object.points.VotedCount(min_votes), FreshCount(object, min_votes));
}

TEST(ObjectPoints, ReadingKeepsTheCachedSet) {
  const MapObject object = ObjectWithPoints(10, 2);
  ExpectFresh(object, 2);
  const std::uint64_t computed = object.points.sets_computed();
  EXPECT_NE(object.points.find(3), object.points.end());
  EXPECT_EQ(object.points.at(3).votes, 2);
  for (const auto& entry : object.points) EXPECT_GE(entry.second.votes, 2);
  ExpectFresh(object, 2);
  EXPECT_EQ(object.points.sets_computed(), computed);
}

TEST(ObjectPoints, VotesOnCountedPointsAtTheirPositionsKeepTheCachedSet) {
  MapObject object = ObjectWithPoints(12, 3);
  object.points.Vote(50, 1, Eigen::Vector3d(0.0, 0.0, 0.05));  // below the threshold
  ExpectFresh(object, 3);
  const std::uint64_t computed = object.points.sets_computed();
  // What AddPointVotes does when the object is seen again: a vote on each point in the
  // box, at the position tracking gives, which is where the object has it.
  std::vector<PointObservation> seen;
  for (int i = 0; i < 12; i += 2)
    seen.push_back({static_cast<std::uint64_t>(i), Eigen::Vector2d::Zero(), PositionOf(i)});
  std::vector<const PointObservation*> box_points;
  for (const PointObservation& point : seen) box_points.push_back(&point);
  AddPointVotes(object, box_points);
  AddPointVotes(object, box_points);
  EXPECT_EQ(object.points.at(4).votes, 5);
  // A vote on a point that stays below the threshold, wherever it is; a new descriptor.
  object.points.Vote(50, 1, Eigen::Vector3d(0.0, 0.1, 0.05));
  object.points.Vote(51, 2, Eigen::Vector3d(1.0, 0.0, 0.0));
  object.points.SetDescriptor(object.points.find(3), Descriptor{});
  ExpectFresh(object, 3);
  EXPECT_EQ(object.points.sets_computed(), computed);
  // Another threshold is another set.
  ExpectFresh(object, 2);
  EXPECT_EQ(object.points.sets_computed(), computed + 1);
}

TEST(ObjectPoints, AVoteThatCrossesTheThresholdChangesTheSet) {
  MapObject object = ObjectWithPoints(12, 3);
  object.points.Vote(50, 2, Eigen::Vector3d(0.0, 0.0, 0.05));
  EXPECT_FALSE(InSet(object, 50, 3));
  EXPECT_EQ(object.points.VotedCount(3), 13);
  PointObservation seen{50, Eigen::Vector2d::Zero(), Eigen::Vector3d(0.0, 0.0, 0.05)};
  AddPointVotes(object, {&seen});  // 2 -> 3 votes, the same position
  EXPECT_TRUE(InSet(object, 50, 3));
  ExpectFresh(object, 3);
  // A new point with enough votes at once, then one joined from another object.
  object.points.Vote(60, 3, Eigen::Vector3d(0.01, 0.0, 0.06));
  EXPECT_EQ(object.points.VotedCount(3), 15);
  ExpectFresh(object, 3);
  object.points.Vote(61, 1, Eigen::Vector3d(0.02, 0.0, 0.06));
  ExpectFresh(object, 3);
  object.points.Join(61, ObjectPoint{2, Eigen::Vector3d(5, 5, 5), std::nullopt});
  EXPECT_EQ(object.points.at(61).position, Eigen::Vector3d(0.02, 0.0, 0.06));  // kept
  EXPECT_TRUE(InSet(object, 61, 3));
  ExpectFresh(object, 3);
}

TEST(ObjectPoints, ACountedPointThatMovesChangesTheSet) {
  MapObject object = WithAnUncountedPoint();
  std::uint64_t computed = object.points.sets_computed();
  // An uncounted point moves: the set stays.
  object.points.Move(object.points.find(50), Eigen::Vector3d(0.0, 0.0, 0.06));
  ExpectFresh(object, 3);
  EXPECT_EQ(object.points.sets_computed(), computed);
  // A counted point moves by a hair (FollowMap), then by a vote at another position.
  object.points.Move(object.points.find(4), PositionOf(4) + Eigen::Vector3d(0, 0, 1e-9));
  EXPECT_EQ(PointSetOf(object, 3).positions[4], PositionOf(4) + Eigen::Vector3d(0, 0, 1e-9));
  ExpectFresh(object, 3);
  EXPECT_GT(object.points.sets_computed(), computed);
  computed = object.points.sets_computed();
  PointObservation seen{5, Eigen::Vector2d::Zero(), PositionOf(5) + Eigen::Vector3d(0.001, 0, 0)};
  AddPointVotes(object, {&seen});
  ExpectFresh(object, 3);
  EXPECT_GT(object.points.sets_computed(), computed);
  // The far point moves onto the object: in reach of the centre, it joins the set.
  object.points.Move(object.points.find(1000), Eigen::Vector3d(0.0, 0.0, 0.05));
  EXPECT_TRUE(InSet(object, 1000, 3));
  ExpectFresh(object, 3);
}

TEST(ObjectPoints, ErasingACountedPointChangesTheSetAndAnUncountedOneKeepsIt) {
  MapObject object = WithAnUncountedPoint();
  const std::uint64_t computed = object.points.sets_computed();
  EXPECT_EQ(object.points.erase(50), 1U);
  EXPECT_EQ(object.points.erase(50), 0U);
  ExpectFresh(object, 3);
  EXPECT_EQ(object.points.sets_computed(), computed);
  object.points.erase(object.points.find(2));
  ExpectFresh(object, 3);
  EXPECT_EQ(object.points.VotedCount(3), 12);
  EXPECT_GT(object.points.sets_computed(), computed);
}

TEST(ObjectPoints, TheVotedCountFollowsVotesAddedAndPointsErased) {
  MapObject object = ObjectWithPoints(10, 1);
  EXPECT_EQ(object.points.VotedCount(2), 0);
  EXPECT_EQ(object.points.VotedCount(1), 11);  // another threshold: not the cached count
  for (std::uint64_t id = 0; id < 4; ++id)
    object.points.Vote(id, 1, PositionOf(static_cast<int>(id)));
  EXPECT_EQ(object.points.VotedCount(2), 4);
  PointObservation seen{7, Eigen::Vector2d::Zero(), Eigen::Vector3d(0, 0, 0.07)};
  AddPointVotes(object, {&seen});
  EXPECT_EQ(object.points.VotedCount(2), 5);
  object.points.erase(0);
  EXPECT_EQ(object.points.VotedCount(2), 4);
}

TEST(ObjectPoints, ThePointSetIsAFreshOneAfterTheCuboidChanges) {
  MapObject object = ObjectWithPoints(12, 3);
  const std::vector<std::uint64_t> first = ObjectPointIds(object, 3);
  EXPECT_EQ(first, FreshIds(object, 3));
  EXPECT_EQ(std::count(first.begin(), first.end(), 1000), 0);  // beyond the cuboid's reach
  // The cuboid moves to the far point: the set is read again with the new centre.
  object.cuboid.centre = Eigen::Vector3d(0, 0, 2.9);
  const std::vector<std::uint64_t> moved = ObjectPointIds(object, 3);
  EXPECT_EQ(moved, FreshIds(object, 3));
  EXPECT_NE(moved, first);
  object.cuboid.centre = Eigen::Vector3d::Zero();
  EXPECT_EQ(ObjectPointIds(object, 3), first);
  object.cuboid.size = Eigen::Vector3d(4, 4, 4);
  ExpectFresh(object, 3);
  const ObjectPoints::PointSet& set = PointSetOf(object, 3);
  EXPECT_EQ(set.bounds.valid, set.positions.size() >= 5);
}

TEST(ObjectPoints, AbsorbingAndBoundingKeepTheSetFresh) {
  MapObject object = ObjectWithPoints(12, 3);
  MapObject other = ObjectWithPoints(20, 1);  // shares ids 0-11 and 1000, adds 12-19
  ExpectFresh(object, 3);
  Absorb(object, other, 100);
  EXPECT_EQ(object.points.at(15).votes, 1);
  EXPECT_EQ(object.points.at(3).votes, 4);
  ExpectFresh(object, 3);
  ExpectFresh(object, 2);
  BoundPoints(object, 8);  // 21 points > 8 + 2: the 8 most voted stay
  EXPECT_EQ(object.points.size(), 8U);
  ExpectFresh(object, 2);
}

// Random writes of every kind, each followed by a read at one of two thresholds: the
// cached set and count never differ from fresh ones.
TEST(ObjectPoints, RandomWritesNeverLeaveAStaleSet) {
  std::mt19937 random(47);
  std::uniform_int_distribution<int> operation(0, 5), id_of(0, 30), votes_of(1, 3);
  std::uniform_real_distribution<double> coordinate(-0.3, 0.3);
  const auto position = [&] {
    return Eigen::Vector3d(coordinate(random), coordinate(random), coordinate(random));
  };
  MapObject object = ObjectWithPoints(15, 2);
  std::uint64_t kept = 0;
  for (int step = 0; step < 3000; ++step) {
    const auto id = static_cast<std::uint64_t>(id_of(random));
    const auto point = object.points.find(id);
    switch (operation(random)) {
      case 0:
        object.points.Vote(id, votes_of(random), position());
        break;
      case 1:  // a vote at the point's own position
        object.points.Vote(id, 1,
                           point == object.points.end() ? position() : point->second.position);
        break;
      case 2:
        object.points.Join(id, ObjectPoint{votes_of(random), position(), std::nullopt});
        break;
      case 3:
        if (point != object.points.end()) object.points.Move(point, position());
        break;
      case 4:
        if (point != object.points.end()) object.points.SetDescriptor(point, Descriptor{});
        break;
      default:
        object.points.erase(id);
        break;
    }
    const std::uint64_t before = object.points.sets_computed();
    ExpectFresh(object, step % 7 == 0 ? 5 : 4);
    kept += object.points.sets_computed() == before;
    if (::testing::Test::HasFailure()) FAIL() << "step " << step;
  }
  EXPECT_GT(kept, 300U);  // some writes kept the set
}

TEST(ObjectPoints, ACopyKeepsItsOwnCacheWhenTheOriginalChanges) {
  MapObject object = ObjectWithPoints(8, 2);
  EXPECT_EQ(object.points.VotedCount(2), 9);
  const MapObject copy = object;  // copies the cache with the points it was made from
  object.points.erase(0);
  object.points.erase(1);
  EXPECT_EQ(object.points.VotedCount(2), 7);
  EXPECT_EQ(copy.points.VotedCount(2), 9);
  EXPECT_EQ(ObjectPointIds(copy, 2), FreshIds(copy, 2));
}

}  // namespace
}  // namespace ocg
