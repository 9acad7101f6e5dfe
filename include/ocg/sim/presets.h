#pragma once
// Built-in scenes mirroring the paper's four semi-static sequences plus a static one and
// a small one for tests: smoke, straight_1, straight_2, round_1, round_2, desk_static.
// Moves are scheduled later, by the generator, at times when neither place is visible.

#include <string>
#include <vector>

#include "ocg/sim/scene.h"

namespace ocg::sim {

std::vector<std::string> PresetNames();
// Throws std::invalid_argument listing the names when name is unknown.
Scene MakePreset(const std::string& name, std::uint64_t seed);

// A move requested by a preset: object id, new place, and the earliest time for it.
struct PlannedMove {
  int object_id = 0;
  Eigen::Vector3d new_centre = Eigen::Vector3d::Zero();
  double new_yaw = 0.0;
  double earliest = 0.0;  // seconds
  bool removal = false;   // removed instead of moved
};

// The moves a preset wants (empty for custom scenes and desk_static).
std::vector<PlannedMove> PresetMoves(const std::string& name, const Scene& scene,
                                     std::uint64_t seed);

}  // namespace ocg::sim
