#pragma once
// The before/after snapshot pair of a map diff (ocg_diff --snapshots, docs/sessions.md).

#include "ocg/objects/map_diff.h"
#include "ocg/viewer/map_view.h"

namespace ocg {

// Every object in the colour of its OCG state in its own map (the same object looks the
// same in both snapshots and in the run's), so that only a diff's ghosts are grey.
struct DiffScenes {
  MapScene before;  // the first map's objects as they were
  // The second map's objects (those new at their place labelled "added" or "moved here"),
  // removed objects as ghosts, moved ones as ghosts at the old place with an arrow to the
  // new one.
  MapScene after;
};

// background: points, keyframes and trajectory to draw behind both (may be empty); its
// objects and moves are replaced (its up is the maps' up).
DiffScenes MakeDiffScenes(const MapDiff& diff, const MapScene& background);

}  // namespace ocg
