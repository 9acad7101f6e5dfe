#pragma once
// What an object SLAM system hands the OCG once per keyframe. Nothing here depends on
// how objects are detected or mapped, so any object SLAM system can drive the OCG.

#include <cstdint>
#include <map>
#include <optional>
#include <vector>

#include "ocg/core/camera.h"
#include "ocg/core/lie.h"

namespace ocg {

using ObjectId = std::int64_t;

// New or changed geometry of one object, world frame. Fields left empty keep the last value.
struct ObjectGeometryUpdate {
  std::optional<Eigen::Vector3d> centroid;
  // Extent along the world axes (full sizes); used by the "in_image" mode only.
  std::optional<Eigen::Vector3d> size;
  std::optional<int> class_id;  // COCO-80 index, for the change log
};

struct KeyframeObservation {
  std::int64_t keyframe_id = 0;
  double timestamp = 0.0;
  SE3 T_cw;  // world to camera
  PinholeCamera camera;
  std::vector<ObjectId> observed;  // map objects matched to a detection in this keyframe
  std::map<ObjectId, ObjectGeometryUpdate> updates;
  // Objects the map dropped for its own reasons since the last keyframe (duplicates merged
  // into another): forgotten before this keyframe's update, without a change-log entry.
  std::vector<ObjectId> forgotten;
  // Objects the OCG removed that the map found again at their own place ("restore" mode):
  // back in the graph before this keyframe's update, in state 1 with no doubt, with the
  // edges they had when removed (to objects still in the graph). An id the OCG did not
  // remove, or removed in a mode without "restore", is ignored: it re-enters as a new node
  // when observed.
  std::vector<ObjectId> restored;
  // Objects not detected whose own SLAM map points the keyframe tracked ("points" mode;
  // the object map decides, docs/objects.md): the thing at their place still looks as
  // they did, so a detector miss there is no evidence of absence. Ignored in other modes.
  std::vector<ObjectId> present_by_points;
};

}  // namespace ocg
