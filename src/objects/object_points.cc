#include "ocg/objects/object_points.h"

namespace ocg {

int ObjectPoints::VotedCount(int min_votes) const {
  if (!voted_ || voted_->revision != revision_ || voted_->min_votes != min_votes) {
    int count = 0;
    for (const auto& [id, point] : points_) count += point.votes >= min_votes ? 1 : 0;
    voted_ = VotedCache{revision_, min_votes, count};
  }
  return voted_->count;
}

const ObjectPoints::PointSet& ObjectPoints::Set(int min_votes,
                                                const std::optional<Eigen::Vector3d>& centre,
                                                double reach) const {
  if (set_ && set_->revision == revision_ && set_->min_votes == min_votes &&
      set_->centre == centre && set_->reach == reach) {
    return set_->set;
  }
  // Where the boxes' rays meet says which of the points in them are on the object: the
  // background behind it can hold most of them when the camera moves little.
  std::vector<std::uint64_t> voted_ids;
  std::vector<Eigen::Vector3d> voted;
  for (const auto& [id, point] : points_) {
    if (point.votes < min_votes) continue;
    if (centre && (point.position - *centre).norm() > reach) continue;
    voted_ids.push_back(id);
    voted.push_back(point.position);
  }
  PointSet set;
  const RobustBounds voted_bounds = RobustPointBounds(voted, 3.0);
  if (!voted_bounds.valid) {
    set.ids = std::move(voted_ids);
    set.positions = std::move(voted);
  } else {
    for (std::size_t i = 0; i < voted.size(); ++i) {
      if (!voted_bounds.Contains(voted[i])) continue;
      set.ids.push_back(voted_ids[i]);
      set.positions.push_back(voted[i]);
    }
  }
  set.bounds = RobustPointBounds(set.positions, 3.0);
  set_ = SetCache{revision_, min_votes, centre, reach, std::move(set)};
  return set_->set;
}

}  // namespace ocg
