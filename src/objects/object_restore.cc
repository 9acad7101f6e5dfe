#include "ocg/objects/object_restore.h"

namespace ocg {

const MapObject* StandInFor(const MapObject& gone, const std::map<ObjectId, MapObject>& objects,
                            const ObjectMapContext& context) {
  const MapObject* found = nullptr;
  double best = context.options.restore_overlap;
  for (const auto& [id, object] : objects) {
    if (!object.has_cuboid || object.class_id != gone.class_id ||
        object.first_timestamp <= gone.last_timestamp) {
      continue;
    }
    const double overlap =
        OverlapShare(gone.cuboid.centre, WorldExtent(gone.cuboid, context.R_wg),
                     object.cuboid.centre, WorldExtent(object.cuboid, context.R_wg));
    if (overlap > best) {
      best = overlap;
      found = &object;
    }
  }
  return found;
}

}  // namespace ocg
