#pragma once
// Built-in scenes mirroring the paper's four semi-static sequences plus a static one and
// a small one for tests: smoke, straight_1, straight_2, round_1, round_2, desk_static;
// session_a, the first visit of a session pair (no changes while the camera watches); and
// walkers, desk_static's table and objects in a larger room with people walking through.
// Moves are scheduled later, by the generator, at times when neither place is visible.

#include <string>
#include <vector>

#include "ocg/sim/scene.h"

namespace ocg::sim {

std::vector<std::string> PresetNames();
// walkers: desk_static's table and objects in a larger room (8.6 x 7 m) with a wider camera
// path (radius 2.4 m), so people fit between the camera and the table; PlanWalkers plans them.
// Throws std::invalid_argument listing the names when name is unknown.
Scene MakePreset(const std::string& name, std::uint64_t seed);

// A move requested by a preset: object id, new place, and the earliest time for it.
struct PlannedMove {
  int object_id = 0;
  Eigen::Vector3d new_centre = Eigen::Vector3d::Zero();
  double new_yaw = 0.0;
  double earliest = 0.0;  // seconds
  bool removal = false;   // removed instead of moved
  // Stand-ins, tried in order when this change has no moment at which it goes unseen
  // (ScheduleMoves): the same object to another place, or another object that changes in
  // no other plan. Their places are free of every planned place.
  std::vector<PlannedMove> alternatives;
};

// People walking through a scene's room (a bonn-style dynamic scene), from first_time to
// the scene's end: passes along straight lines across the floor, clear of the table, the
// cabinets and the shelf, at 0.8-1.3 m/s, about a third stopping for 1-2.5 s on the way.
// A pass starts every 1.5-5 s, at most two walkers are in the room at once, and each pass
// keeps at least min_camera_distance (horizontally) from the camera, stays clear of the
// other walkers and shows in the camera's view for at least a second. Two passes in three
// cross the camera's view close in front of it (large occluders), along the table edge the
// camera faces; the others go anywhere. Deterministic in seed; the scene's own random draws
// are untouched.
std::vector<Walker> PlanWalkers(const Scene& scene, std::uint64_t seed, double first_time = 3.0,
                                double min_camera_distance = 1.0);

// The moves a preset wants (empty for custom scenes and desk_static). Each move and removal
// carries up to three alternatives, drawn after every planned change with a generator of
// their own, so they alter none of the planned changes.
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
