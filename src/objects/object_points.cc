#include "ocg/objects/object_points.h"

namespace ocg {

namespace {

bool Counted(const ObjectPoint* point, int min_votes) {
  return point != nullptr && point->votes >= min_votes;
}

}  // namespace

void ObjectPoints::Vote(std::uint64_t id, int votes, const Eigen::Vector3d& position) {
  const auto [entry, added] = points_.try_emplace(id);
  const ObjectPoint before{entry->second.votes, entry->second.position, std::nullopt};
  entry->second.votes += votes;
  entry->second.position = position;
  Changed(added ? nullptr : &before, &entry->second);
}

void ObjectPoints::Join(std::uint64_t id, const ObjectPoint& from) {
  const auto [entry, added] = points_.try_emplace(id);
  const ObjectPoint before{entry->second.votes, entry->second.position, std::nullopt};
  if (entry->second.votes == 0) entry->second.position = from.position;
  entry->second.votes += from.votes;
  Changed(added ? nullptr : &before, &entry->second);
}

void ObjectPoints::Move(const_iterator point, const Eigen::Vector3d& position) {
  const iterator entry = points_.erase(point, point);  // the same point, writable
  const ObjectPoint before{entry->second.votes, entry->second.position, std::nullopt};
  entry->second.position = position;
  Changed(&before, &entry->second);
}

void ObjectPoints::SetDescriptor(const_iterator point, const Descriptor& descriptor) {
  points_.erase(point, point)->second.descriptor = descriptor;  // not in what is cached
}

ObjectPoints::const_iterator ObjectPoints::erase(const_iterator point) {
  Changed(&point->second, nullptr);
  return points_.erase(point);
}

std::size_t ObjectPoints::erase(std::uint64_t id) {
  const auto point = points_.find(id);
  if (point == points_.end()) return 0;
  erase(point);
  return 1;
}

void ObjectPoints::Changed(const ObjectPoint* before, const ObjectPoint* after) {
  if (voted_) {
    voted_->count +=
        (Counted(after, voted_->min_votes) ? 1 : 0) - (Counted(before, voted_->min_votes) ? 1 : 0);
  }
  if (set_) {
    const bool was = Counted(before, set_->min_votes), is = Counted(after, set_->min_votes);
    // A counted point's position is in the set, its bounds and the reach test.
    if (was != is || (is && before->position != after->position)) set_.reset();
  }
}

int ObjectPoints::VotedCount(int min_votes) const {
  if (!voted_ || voted_->min_votes != min_votes) {
    int count = 0;
    for (const auto& [id, point] : points_) count += point.votes >= min_votes ? 1 : 0;
    voted_ = VotedCache{min_votes, count};
  }
  return voted_->count;
}

const ObjectPoints::PointSet& ObjectPoints::Set(int min_votes,
                                                const std::optional<Eigen::Vector3d>& centre,
                                                double reach) const {
  if (set_ && set_->min_votes == min_votes && set_->centre == centre && set_->reach == reach) {
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
  ++sets_computed_;
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
  set_ = SetCache{min_votes, centre, reach, std::move(set)};
  return set_->set;
}

}  // namespace ocg
