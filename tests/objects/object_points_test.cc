// ObjectPoints: what is derived from an object's points is kept until they change, and is
// then what a fresh computation gives.
#include <gtest/gtest.h>

#include <utility>

#include "ocg/objects/map_object.h"

namespace ocg {
namespace {

// An object with a cuboid at the origin and n points on it, each with votes votes, plus
// one far behind it (the background caught in its boxes).
MapObject ObjectWithPoints(int n, int votes) {
  MapObject object;
  object.has_cuboid = true;
  object.cuboid.size = Eigen::Vector3d(0.4, 0.4, 0.4);
  for (int i = 0; i < n; ++i) {
    ObjectPoint& point = object.points[static_cast<std::uint64_t>(i)];
    point.votes = votes;
    point.position = Eigen::Vector3d(0.01 * (i % 7) - 0.03, 0.013 * (i % 5) - 0.026, 0.01 * i);
  }
  object.points[1000] = ObjectPoint{votes, Eigen::Vector3d(0, 0, 3.0), std::nullopt};
  return object;
}

// The point set as ObjectPointIds defines it, computed here from scratch.
std::vector<std::uint64_t> FreshIds(const MapObject& object, int min_votes) {
  std::vector<std::uint64_t> ids;
  std::vector<Eigen::Vector3d> positions;
  for (const auto& [id, point] : std::as_const(object.points)) {
    if (point.votes < min_votes) continue;
    if (object.has_cuboid &&
        (point.position - object.cuboid.centre).norm() > object.cuboid.size.maxCoeff())
      continue;
    ids.push_back(id);
    positions.push_back(point.position);
  }
  const RobustBounds bounds = RobustPointBounds(positions, 3.0);
  if (!bounds.valid) return ids;
  std::vector<std::uint64_t> kept;
  for (std::size_t i = 0; i < ids.size(); ++i)
    if (bounds.Contains(positions[i])) kept.push_back(ids[i]);
  return kept;
}

TEST(ObjectPoints, ReadingKeepsTheRevisionAndEveryWritingAccessMakesANewOne) {
  MapObject object = ObjectWithPoints(10, 2);
  const MapObject& reader = object;
  const std::uint64_t before = object.points.revision();
  EXPECT_NE(reader.points.find(3), reader.points.end());
  EXPECT_EQ(reader.points.at(3).votes, 2);
  for (const auto& entry : reader.points) EXPECT_GE(entry.second.votes, 2);
  EXPECT_EQ(object.points.revision(), before);
  object.points.find(3)->second.votes = 5;
  EXPECT_GT(object.points.revision(), before);
  const std::uint64_t after_find = object.points.revision();
  object.points.erase(object.points.find(4));
  EXPECT_GT(object.points.revision(), after_find);
}

TEST(ObjectPoints, TheVotedCountFollowsVotesAddedAndPointsErased) {
  MapObject object = ObjectWithPoints(10, 1);
  EXPECT_EQ(object.points.VotedCount(2), 0);
  EXPECT_EQ(object.points.VotedCount(1), 11);  // another threshold: not the cached count
  for (std::uint64_t id = 0; id < 4; ++id) ++object.points[id].votes;
  EXPECT_EQ(object.points.VotedCount(2), 4);
  PointObservation seen{7, Eigen::Vector2d::Zero(), Eigen::Vector3d(0, 0, 0.07)};
  AddPointVotes(object, {&seen});
  EXPECT_EQ(object.points.VotedCount(2), 5);
  object.points.erase(0);
  EXPECT_EQ(object.points.VotedCount(2), 4);
}

TEST(ObjectPoints, ThePointSetIsAFreshOneAfterItsPointsOrTheCuboidChange) {
  MapObject object = ObjectWithPoints(12, 3);
  const std::vector<std::uint64_t> first = ObjectPointIds(object, 3);
  EXPECT_EQ(first, FreshIds(object, 3));
  EXPECT_EQ(std::count(first.begin(), first.end(), 1000), 0);  // beyond the cuboid's reach
  // The cuboid moves to the far point: the set is read again with the new centre.
  object.cuboid.centre = Eigen::Vector3d(0, 0, 2.9);
  const std::vector<std::uint64_t> moved = ObjectPointIds(object, 3);
  EXPECT_EQ(moved, FreshIds(object, 3));
  EXPECT_NE(moved, first);
  // A point moved through a mutable iterator, then read.
  object.cuboid.centre = Eigen::Vector3d::Zero();
  EXPECT_EQ(ObjectPointIds(object, 3), first);
  for (auto& [id, point] : object.points) {
    if (id == 1000) point.position = Eigen::Vector3d(0.0, 0.0, 0.05);
  }
  const ObjectPoints::PointSet& set = PointSetOf(object, 3);
  EXPECT_EQ(set.ids, FreshIds(object, 3));
  EXPECT_EQ(std::count(set.ids.begin(), set.ids.end(), 1000), 1);
  EXPECT_EQ(set.bounds.valid, set.positions.size() >= 5);
  const RobustBounds fresh = RobustPointBounds(set.positions, 3.0);
  EXPECT_EQ(set.bounds.low, fresh.low);
  EXPECT_EQ(set.bounds.high, fresh.high);
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
