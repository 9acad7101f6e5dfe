#include "ocg/objects/slam_map_copy.h"

namespace ocg {

std::size_t SlamMapCopy::Apply(const SlamMapChanges& changes) {
  std::size_t added_or_removed = 0;
  if (changes.everything) {
    added_or_removed = points_.size();
    points_.clear();
    rotations_.clear();
  }
  for (const SlamMapChanges::Point& point : changes.points) {
    if (!point.position) {
      added_or_removed += points_.erase(point.id);
      continue;
    }
    const auto [it, added] =
        points_.insert_or_assign(point.id, Point{*point.position, point.descriptor});
    added_or_removed += added ? 1 : 0;
  }
  for (const auto& [id, rotation] : changes.camera_rotations) {
    if (rotation) {
      rotations_.insert_or_assign(id, *rotation);
    } else {
      rotations_.erase(id);
    }
  }
  return added_or_removed;
}

std::vector<Eigen::Vector3d> SlamMapCopy::Positions() const {
  std::vector<Eigen::Vector3d> positions;
  positions.reserve(points_.size());
  for (const auto& [id, point] : points_) positions.push_back(point.position);
  return positions;
}

std::vector<Eigen::Matrix3d> SlamMapCopy::Rotations() const {
  std::vector<Eigen::Matrix3d> rotations;
  rotations.reserve(rotations_.size());
  for (const auto& [id, rotation] : rotations_) rotations.push_back(rotation);
  return rotations;
}

}  // namespace ocg
