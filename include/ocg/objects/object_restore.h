#pragma once
// Restore (OCG.mode "restore"): a removed object found again at its own place.

#include <map>

#include "ocg/objects/map_object.h"

namespace ocg {

// The live object standing in for gone (removed): of its class, first detected after its
// last sighting (never seen beside it), in its place (world extents overlapping by more
// than Objects.restore_overlap); the largest overlap wins. Null when none.
const MapObject* StandInFor(const MapObject& gone, const std::map<ObjectId, MapObject>& objects,
                            const ObjectMapContext& context);

}  // namespace ocg
