#pragma once
// Association: which map object or candidate each of a frame's detections continues. Each
// pair of one class is scored by its cues (the predicted box, the projected cuboid, the
// object's map points in the box), and one assignment of least total cost decides.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "ocg/objects/map_object.h"

namespace ocg {

// For each detection, the index into entities it continues, or -1. entities: the map
// objects (the first object_count) then the candidates, which lose a tie. box_points[d]:
// the tracked map points in detection d's box; with_points false (no SLAM map) leaves the
// point cues out. session: the session of the frame (an object last seen in an earlier
// one must show its own points in the box).
std::vector<int> AssociateDetections(
    const std::vector<MapObject*>& entities, std::size_t object_count,
    const std::vector<ObjectDetection>& detections,
    const std::vector<std::vector<const PointObservation*>>& box_points, bool with_points,
    std::int64_t frame, const SE3& T_cw, int session, const ObjectMapContext& context);

}  // namespace ocg
