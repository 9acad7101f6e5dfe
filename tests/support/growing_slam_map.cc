#include "growing_slam_map.h"

#include <Eigen/Geometry>
#include <algorithm>

namespace ocg::testing {

GrowingSlamMap::GrowingSlamMap(GrowingSlamMapOptions options)
    : options_(options), random_(options.seed) {}

Eigen::Vector3d GrowingSlamMap::NewPosition() {
  std::uniform_real_distribution<double> across(-5.0, 5.0), noise(-0.005, 0.005), unit(0.0, 1.0);
  const Eigen::Vector3d on_floor(across(random_), across(random_), noise(random_));
  if (unit(random_) >= options_.clutter_share) return on_floor;
  return on_floor + Eigen::Vector3d(0, 0, 2.0 * unit(random_));
}

Eigen::Matrix3d GrowingSlamMap::Rotation(int keyframe, double wobble) const {
  // Camera to world: looking horizontally along the turning direction, y axis down.
  Eigen::Matrix3d looking_along_y;
  looking_along_y << 1, 0, 0, 0, 0, 1, 0, -1, 0;
  const double yaw = 0.05 * keyframe + wobble;
  return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * looking_along_y;
}

SlamMapChanges GrowingSlamMap::NextKeyframe() {
  SlamMapChanges changes;
  changes.everything = keyframes_ == 0;
  std::uniform_real_distribution<double> shift(-0.001, 0.001);
  // The window's points (the newest) and rotations move a little.
  const std::size_t window =
      std::min(live_.size(),
               static_cast<std::size_t>(options_.window_keyframes * options_.points_per_keyframe));
  for (std::size_t i = live_.size() - window; i < live_.size(); ++i) {
    live_[i].second += Eigen::Vector3d(shift(random_), shift(random_), shift(random_));
    changes.points.push_back({live_[i].first, live_[i].second, {}});
  }
  for (int k = std::max(0, keyframes_ - options_.window_keyframes); k < keyframes_; ++k) {
    changes.camera_rotations.emplace_back(static_cast<std::uint64_t>(k),
                                          Rotation(k, shift(random_)));
  }
  // Older points culled.
  if (live_.size() > window + static_cast<std::size_t>(options_.culled_per_keyframe)) {
    std::uniform_int_distribution<std::size_t> older(0, live_.size() - window - 1);
    for (int i = 0; i < options_.culled_per_keyframe; ++i) {
      const std::size_t at = older(random_) % (live_.size() - window);
      changes.points.push_back({live_[at].first, std::nullopt, {}});
      // The last older point takes its place; only the window shifts.
      const std::size_t last_older = live_.size() - window - 1;
      live_[at] = live_[last_older];
      live_.erase(live_.begin() + static_cast<std::ptrdiff_t>(last_older));
    }
  }
  // The keyframe and its new points.
  changes.camera_rotations.emplace_back(static_cast<std::uint64_t>(keyframes_),
                                        Rotation(keyframes_, 0.0));
  for (int i = 0; i < options_.points_per_keyframe; ++i) {
    Descriptor descriptor;
    for (auto& word : descriptor) word = random_();
    live_.emplace_back(next_point_++, NewPosition());
    changes.points.push_back({live_.back().first, live_.back().second, descriptor});
  }
  ++keyframes_;
  return changes;
}

}  // namespace ocg::testing
