#pragma once
// What a SLAM run tells the object layer as its map grows (SlamMapChanges), without
// running SLAM: a floor (z = 0, up +z) with clutter above it, seen by upright cameras
// turning about z. Each keyframe adds points, moves the newest ones (the local bundle
// adjustment's window) and the newest keyframes' rotations a little, and culls some
// points, as local mapping does. For the object layer's tests and bench.

#include <cstdint>
#include <deque>
#include <random>
#include <vector>

#include "ocg/objects/slam_map_copy.h"

namespace ocg::testing {

struct GrowingSlamMapOptions {
  int points_per_keyframe = 100;  // added
  int culled_per_keyframe = 20;   // of the older points
  int window_keyframes = 10;      // whose points and rotations the adjustment moves
  double clutter_share = 0.3;     // points off the floor
  std::uint64_t seed = 1;
};

class GrowingSlamMap {
 public:
  explicit GrowingSlamMap(GrowingSlamMapOptions options = GrowingSlamMapOptions());
  // The next keyframe's changes (the first call: everything, one keyframe's points).
  SlamMapChanges NextKeyframe();
  int keyframes() const { return keyframes_; }
  std::size_t points() const { return live_.size(); }

 private:
  Eigen::Vector3d NewPosition();
  Eigen::Matrix3d Rotation(int keyframe, double wobble) const;
  GrowingSlamMapOptions options_;
  std::mt19937_64 random_;
  int keyframes_ = 0;
  std::uint64_t next_point_ = 0;
  // The live points' ids with their positions, the window's (the newest) last.
  std::vector<std::pair<std::uint64_t, Eigen::Vector3d>> live_;
};

}  // namespace ocg::testing
