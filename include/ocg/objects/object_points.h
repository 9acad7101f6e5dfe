#pragma once
// An object's SLAM map points (the points seen inside its boxes, by map point id) and what
// is derived from them, kept until a change that can alter it.
//
// Association scores every detection against every object and candidate of its class at
// every frame, and its point cue needs two things of each: how many points the object
// holds with enough votes, and the robust bounds of its point set (ObjectPointSet). Both
// walk the whole set; computed afresh they cost as much as the rest of a frame's
// association once a revisited room holds about a hundred objects and candidates, most of
// them unchanged since the last frame. So the container keeps them until a change that
// can alter them. The points are written only through the members that say what they
// change (Vote, Join, Move, SetDescriptor, erase), and each compares the point before and
// after with the min_votes the cached values were made for: the count is made again only
// when a point starts or stops being counted, the point set also when a counted point's
// position changes; a vote on a point counted already, a vote below the threshold or a
// new descriptor keep both. (An object seen in a frame gets a vote on each point in its
// box; most of them are counted already and keep their positions.)
//
// Not for two threads at once, as the rest of an object (the const members fill the cache).

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

  // Reading.
  const_iterator begin() const { return points_.begin(); }
  const_iterator end() const { return points_.end(); }
  const_iterator find(std::uint64_t id) const { return points_.find(id); }
  const ObjectPoint& at(std::uint64_t id) const { return points_.at(id); }
  std::size_t count(std::uint64_t id) const { return points_.count(id); }
  std::size_t size() const { return points_.size(); }
  bool empty() const { return points_.empty(); }
  const Container& container() const { return points_; }

  // Writing: what is cached is dropped only when the change can alter it.
  // votes more votes for the point (a new point when it has none), which is at position now.
  void Vote(std::uint64_t id, int votes, const Eigen::Vector3d& position);
  // from's votes added to the point's (Absorb); the point takes from's position when it had
  // no votes, and keeps its descriptor.
  void Join(std::uint64_t id, const ObjectPoint& from);
  // The point is at position now.
  void Move(const_iterator point, const Eigen::Vector3d& position);
  void SetDescriptor(const_iterator point, const Descriptor& descriptor);
  const_iterator erase(const_iterator point);
  std::size_t erase(std::uint64_t id);

  // The points with at least min_votes votes: how many (cached until one starts or stops
  // being counted).
  int VotedCount(int min_votes) const;

  // The object's point set (map_object.h's ObjectPointIds: the points with at least
  // min_votes votes, within reach of the cuboid's centre when there is one, and within 3
  // robust sigmas of their median) and its robust bounds (3 robust sigmas), cached until
  // a point starts or stops being counted, a counted point moves, or the centre, the reach
  // or min_votes change.
  struct PointSet {
    std::vector<std::uint64_t> ids;          // in id order
    std::vector<Eigen::Vector3d> positions;  // of ids, world
    RobustBounds bounds;                     // of positions
  };
  const PointSet& Set(int min_votes, const std::optional<Eigen::Vector3d>& centre,
                      double reach) const;
  // How many times Set computed the set (tests: what a change kept).
  std::uint64_t sets_computed() const { return sets_computed_; }

 private:
  // The point at id changed from before (null: it was not held) to after (null: erased):
  // drops what was derived from the points when the change can alter it.
  void Changed(const ObjectPoint* before, const ObjectPoint* after);

  Container points_;
  struct VotedCache {
    int min_votes = 0;
    int count = 0;
  };
  mutable std::optional<VotedCache> voted_;
  struct SetCache {
    int min_votes = 0;
    std::optional<Eigen::Vector3d> centre;
    double reach = 0.0;
    PointSet set;
  };
  mutable std::optional<SetCache> set_;
  mutable std::uint64_t sets_computed_ = 0;
};

}  // namespace ocg
