#include "ocg/objects/slam_map_copy.h"

#include <algorithm>

#include "ocg/objects/map_cues.h"

namespace ocg {

std::size_t SlamMapCopy::Apply(const SlamMapChanges& changes) {
  std::size_t added_or_removed = 0;
  if (changes.everything) {
    added_or_removed = points_.size();
    points_.clear();
    rotations_.clear();
    x_scatter_.setZero();
    minus_y_sum_.setZero();
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
    const auto kept = rotations_.find(id);
    if (kept != rotations_.end()) {
      AddToSums(kept->second, -1.0);
      rotations_.erase(kept);
    }
    if (rotation) {
      rotations_.emplace(id, *rotation);
      AddToSums(*rotation, 1.0);
    }
  }
  return added_or_removed;
}

std::vector<Eigen::Vector3d> SlamMapCopy::Positions() const {
  std::vector<std::uint64_t> ids;
  ids.reserve(points_.size());
  for (const auto& [id, point] : points_) ids.push_back(id);
  std::sort(ids.begin(), ids.end());
  std::vector<Eigen::Vector3d> positions;
  positions.reserve(ids.size());
  for (const std::uint64_t id : ids) positions.push_back(points_.at(id).position);
  return positions;
}

void SlamMapCopy::AddToSums(const Eigen::Matrix3d& R_wc, double sign) {
  x_scatter_ += sign * (R_wc.col(0) * R_wc.col(0).transpose());
  minus_y_sum_ -= sign * R_wc.col(1);
}

Eigen::Vector3d SlamMapCopy::CameraUpPrior() const {
  return ocg::CameraUpPrior(x_scatter_, minus_y_sum_, rotations_.size());
}

std::vector<Eigen::Matrix3d> SlamMapCopy::Rotations() const {
  std::vector<Eigen::Matrix3d> rotations;
  rotations.reserve(rotations_.size());
  for (const auto& [id, rotation] : rotations_) rotations.push_back(rotation);
  return rotations;
}

}  // namespace ocg
