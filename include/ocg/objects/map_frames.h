#pragma once
// Whether two saved object maps are in one world frame, as a diff of them needs
// (ocg_diff, docs/sessions.md): a later session continuing the earlier one's map file is by
// construction; otherwise the objects tell. In one frame most objects keep their place as
// given; maps in two frames (a pose-given map and a SLAM map, two SLAM runs from empty
// maps) put few objects at the same place as given, and many once one of them is turned,
// scaled and shifted onto the other.

#include <string>

#include "ocg/objects/map_diff.h"

namespace ocg {

struct FrameCheckOptions {
  // Same class within this many larger extents: at the same place (MapDiffOptions).
  double same_place_factor = 1.0;
  // The maps are in two frames when a similarity transform puts at least this many
  // objects at the same place...
  int min_aligned = 3;
  // ...and at least this many times as many as without one.
  double aligned_ratio = 2.0;
  // Throws std::invalid_argument naming the field.
  void Check() const;
};

struct FrameCheck {
  bool one_frame = true;
  // Why, as a sentence: the session record, or the counts and the transform.
  std::string evidence;
  int same_place_as_given = 0;  // after's objects at the place of a before object
  int same_place_aligned = 0;   // the same after the best transform found
  // That transform, after's map onto before's, about each map's up: scale, turn about up
  // (radians) and the length of its shift (before's map units).
  double scale = 1.0;
  double turn = 0.0;
  double shift = 0.0;
};

// Session record first (ContinuesMapOf); else the objects: every transform that puts two
// same-class pairs at the same place (each map's up aligned, then scale, turn and shift
// from the two pairs) is tried, and the one putting most objects at the same place is
// compared with none. A transform near the identity (scale within 5 %, turn within 3
// degrees, shift within one extent) does not count against one frame.
FrameCheck CheckOneFrame(const SavedObjectMap& before, const SavedObjectMap& after,
                         const FrameCheckOptions& options);

}  // namespace ocg
