#pragma once
// An object's SLAM map points (the points seen inside its boxes, by map point id) and what
// is derived from them, kept until they change.
//
// Association scores every detection against every object and candidate of its class at
// every frame, and its point cue needs two things of each: how many points the object
// holds with enough votes, and the robust bounds of its point set (ObjectPointSet). Both
// walk the whole set; computed afresh they cost as much as the rest of a frame's
// association once a revisited room holds about a hundred objects and candidates, most of
// them unchanged since the last frame. So the container counts its changes: every access
// that can write (the non-const members) makes a new revision, and what was derived at an
// older revision is computed again on its next use. Reading through the const members
// keeps the revision.
//
// Not for two threads at once, as the rest of an object (the const members fill the cache).
// A cache filled while a mutable iterator is held is not told of writes made through it
// later: write first, then read.

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <vector>

#include "ocg/features/descriptor.h"
#include "ocg/objects/map_cues.h"

namespace ocg {

// A SLAM map point seen inside an object's boxes (SLAM runs only).
struct ObjectPoint {
  int votes = 0;                                       // boxes it was inside
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // world, when last tracked
  // The map point's ORB descriptor as of the last FollowMap that gave one. Not kept in map
  // files (the SLAM map holds it; the next FollowMap gives it back).
  std::optional<Descriptor> descriptor;
};

class ObjectPoints {
 public:
  using Container = std::map<std::uint64_t, ObjectPoint>;
  using iterator = Container::iterator;
  using const_iterator = Container::const_iterator;
  using value_type = Container::value_type;

  ObjectPoints() = default;
  explicit ObjectPoints(Container points) : points_(std::move(points)) {}

  // Reading: the revision stays.
  const_iterator begin() const { return points_.begin(); }
  const_iterator end() const { return points_.end(); }
  const_iterator find(std::uint64_t id) const { return points_.find(id); }
  const ObjectPoint& at(std::uint64_t id) const { return points_.at(id); }
  std::size_t count(std::uint64_t id) const { return points_.count(id); }
  std::size_t size() const { return points_.size(); }
  bool empty() const { return points_.empty(); }
  const Container& container() const { return points_; }

  // Writing: each call makes a new revision, whether or not the caller writes.
  iterator begin() { return Changed().begin(); }
  iterator end() { return Changed().end(); }
  iterator find(std::uint64_t id) { return Changed().find(id); }
  ObjectPoint& at(std::uint64_t id) { return Changed().at(id); }
  ObjectPoint& operator[](std::uint64_t id) { return Changed()[id]; }
  iterator erase(iterator point) { return Changed().erase(point); }
  std::size_t erase(std::uint64_t id) { return Changed().erase(id); }

  // Counts the changes: a value derived at an older revision is stale.
  std::uint64_t revision() const { return revision_; }

  // The points with at least min_votes votes: how many (cached until the points change).
  int VotedCount(int min_votes) const;

  // The object's point set (map_object.h's ObjectPointIds: the points with at least
  // min_votes votes, within reach of the cuboid's centre when there is one, and within 3
  // robust sigmas of their median) and its robust bounds (3 robust sigmas), cached until
  // the points, the centre, the reach or min_votes change.
  struct PointSet {
    std::vector<std::uint64_t> ids;          // in id order
    std::vector<Eigen::Vector3d> positions;  // of ids, world
    RobustBounds bounds;                     // of positions
  };
  const PointSet& Set(int min_votes, const std::optional<Eigen::Vector3d>& centre,
                      double reach) const;

 private:
  Container& Changed() {
    ++revision_;
    return points_;
  }

  Container points_;
  std::uint64_t revision_ = 0;
  struct VotedCache {
    std::uint64_t revision = 0;
    int min_votes = 0;
    int count = 0;
  };
  mutable std::optional<VotedCache> voted_;
  struct SetCache {
    std::uint64_t revision = 0;
    int min_votes = 0;
    std::optional<Eigen::Vector3d> centre;
    double reach = 0.0;
    PointSet set;
  };
  mutable std::optional<SetCache> set_;
};

}  // namespace ocg
