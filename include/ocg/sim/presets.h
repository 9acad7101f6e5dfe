#pragma once
// Built-in scenes mirroring the paper's four semi-static sequences plus a static one and
// a small one for tests: smoke, straight_1, straight_2, round_1, round_2, desk_static; and
// session_a, the first visit of a session pair (no changes while the camera watches).
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

// What changes between two visits of a room (MakeLaterVisit), and the later visit's camera.
struct VisitChanges {
  int moves = 4;
  int removals = 1;
  int additions = 1;
  double path_start = 0.5;   // added to the previous path's start, share of a lap (wrapped)
  double duration = 0.0;     // seconds; 0: the previous visit's
  double gap = 3 * 86400.0;  // seconds from the previous visit's end to this one's start
};

// The changes --preset names with --session-of: session_b (VisitChanges' defaults) or a room
// preset (its in-session changes happen between the visits instead). Throws
// std::invalid_argument listing the names when name is neither.
VisitChanges PresetVisitChanges(const std::string& name);

// A later visit of the room `previous` rendered (its history holds its changes): the same
// room, furniture, look, detector and camera path, every object where the previous visit
// left it except `changes` of them moved, removed or added (chosen from seed, none while
// the camera watches); each changed object's before_session says where it was. The camera
// starts changes.path_start of a lap further on the same path, so it starts elsewhere but
// looks at what the previous visit mapped (its duration must cover a lap). Frame 0 comes
// changes.gap seconds after the previous visit's end. Ids of kept objects stay; added
// objects take new ones. Throws std::invalid_argument when the changes do not fit or the
// previous visit lasts less than a lap.
Scene MakeLaterVisit(const Scene& previous, const VisitChanges& changes, std::uint64_t seed);

}  // namespace ocg::sim
