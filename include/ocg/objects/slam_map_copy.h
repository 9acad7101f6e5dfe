#pragma once
// The object layer's own copy of the SLAM map (SLAM runs): the map points (position and
// descriptor) and the keyframes' rotations, kept up to date from what SLAM says changed
// at each keyframe, so that following the map costs what changed, not what the map holds.

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include "ocg/core/lie.h"
#include "ocg/features/descriptor.h"

namespace ocg {

// What a SLAM run tells the object layer at a keyframe, after its bundle adjustment.
struct SlamMapChanges {
  // Camera poses by the frame numbers given to AddFrame: those of SightingFrames() whose
  // pose changed (or may have) since the last call; the sightings of other frames keep
  // theirs (a pose for every frame of a long run at every keyframe would grow with it).
  std::map<std::int64_t, SE3> frame_poses;
  // The lists below hold the whole map: the copy starts over from them (the first call, a
  // loop correction, a global adjustment, a merge, a switch of map). Otherwise they hold
  // what changed since the last call.
  bool everything = false;
  struct Point {
    std::uint64_t id = 0;
    std::optional<Eigen::Vector3d> position;  // world; none: the point is gone
    Descriptor descriptor{};
  };
  std::vector<Point> points;
  // Keyframes' camera-to-world rotations by keyframe id; none: the keyframe is gone.
  std::vector<std::pair<std::uint64_t, std::optional<Eigen::Matrix3d>>> camera_rotations;
};

class SlamMapCopy {
 public:
  struct Point {
    Eigen::Vector3d position;
    Descriptor descriptor;
  };
  // Returns the points added and removed (moved ones are not counted).
  std::size_t Apply(const SlamMapChanges& changes);
  // By id, in no order (a hash map: a keyframe's thousands of changed points each cost a
  // lookup, not a walk down a tree of the whole map).
  const std::unordered_map<std::uint64_t, Point>& points() const { return points_; }
  const std::map<std::uint64_t, Eigen::Matrix3d>& camera_rotations() const { return rotations_; }
  // By id, as the SLAM map orders them.
  std::vector<Eigen::Vector3d> Positions() const;
  std::vector<Eigen::Matrix3d> Rotations() const;
  // CameraUpPrior of the keyframes' rotations, from sums kept as they come and go (a
  // keyframe costs what changed, not the keyframes the map holds).
  Eigen::Vector3d CameraUpPrior() const;

 private:
  // The rotations' sums CameraUpPrior reads: x axes' scatter, -y axes.
  Eigen::Matrix3d x_scatter_ = Eigen::Matrix3d::Zero();
  Eigen::Vector3d minus_y_sum_ = Eigen::Vector3d::Zero();
  void AddToSums(const Eigen::Matrix3d& R_wc, double sign);
  std::unordered_map<std::uint64_t, Point> points_;
  std::map<std::uint64_t, Eigen::Matrix3d> rotations_;
};

}  // namespace ocg
