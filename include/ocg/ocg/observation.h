#pragma once
// What an object SLAM system hands the OCG once per keyframe. Nothing here depends on
// how objects are detected or mapped, so any object SLAM system can drive the OCG.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ocg/core/camera.h"
#include "ocg/core/lie.h"

namespace ocg {

using ObjectId = std::int64_t;

// New or changed geometry of one object, world frame. Fields left empty keep the last value.
// Its fields are listed by VisitObjectUpdateFields below.
struct ObjectGeometryUpdate {
  std::optional<Eigen::Vector3d> centroid;
  // Extent along the world axes (full sizes); used by the "in_image" mode only.
  std::optional<Eigen::Vector3d> size;
  std::optional<int> class_id;  // COCO-80 index, for the change log
};

// Its fields are listed by VisitObservationFields below: a new field is added there too.
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

// How a field of the observation appears in its serialized forms: the replay format
// (SPEC 3.1, one JSON object per keyframe, ocg_replay and ocg_observations.jsonl) and
// Python's ChangeDetector.process and observation dicts.
enum class FieldUse {
  kRequired,                 // absent is an error
  kOptional,                 // absent is empty (or 0); always written
  kOptionalOmittedWhenEmpty  // absent is empty; written only when not empty
};

struct ObservationField {
  const char* name;  // the key in the replay format and in Python (SPEC 3.1's names)
  FieldUse use;
  const char* unit;     // "" when the value has none
  const char* meaning;  // for the docs and Python's help
  // Per-object fields ({object id: value} maps): what one entry is called in messages
  // ("centroid of object 3"). nullptr for the keyframe's own fields.
  const char* entry = nullptr;
  bool non_negative = false;  // every number of the value must be >= 0

  bool optional() const { return use != FieldUse::kRequired; }
  bool written_when_empty() const { return use != FieldUse::kOptionalOmittedWhenEmpty; }
};

// The value's form in the serialized forms, named for messages and the docs. A field of a
// type with no name here has no reader or writer either: add the type to both formats.
inline const char* ObservationFieldType(const std::int64_t&) { return "integer"; }
inline const char* ObservationFieldType(const int&) { return "integer"; }
inline const char* ObservationFieldType(const double&) { return "number"; }
inline const char* ObservationFieldType(const SE3&) {
  return "4x4 matrix (replay: 16 numbers, row-major)";
}
inline const char* ObservationFieldType(const PinholeCamera&) { return "camera"; }
inline const char* ObservationFieldType(const std::vector<ObjectId>&) {
  return "list of object ids";
}
inline const char* ObservationFieldType(const std::optional<Eigen::Vector3d>&) {
  return "{object id: [x, y, z]}";
}
inline const char* ObservationFieldType(const std::optional<int>&) {
  return "{object id: integer}";
}

// Calls visit(field, observation.member...) for every field of the keyframe's own (not
// per object), in one fixed order: the one list behind the replay reader and writer and
// the Python binding. Several observations may be given (visit then gets one member of
// each, to compare or copy them); they may be const. The per-object geometry (updates)
// is listed by VisitObjectUpdateFields.
template <typename Visitor, typename... Observation>
void VisitObservationFields(Visitor&& visit, Observation&... observation) {
  using U = FieldUse;
  visit(ObservationField{"keyframe", U::kRequired, "", "keyframe id, increasing"},
        observation.keyframe_id...);
  visit(
      ObservationField{"timestamp", U::kOptional, "s", "time of the keyframe, for the change log"},
      observation.timestamp...);
  visit(ObservationField{"T_cw", U::kRequired, "m (translation)",
                         "world to camera (camera x right, y down, z forward); its rotation block "
                         "must be a rotation, its last row [0, 0, 0, 1]"},
        observation.T_cw...);
  visit(ObservationField{"camera", U::kRequired, "px", "the keyframe's camera model"},
        observation.camera...);
  visit(ObservationField{"observed", U::kRequired, "",
                         "map objects matched to a detection in this keyframe"},
        observation.observed...);
  visit(ObservationField{"forgotten", U::kOptionalOmittedWhenEmpty, "",
                         "objects the map dropped for its own reasons (merged duplicates): out "
                         "of the graph before the update, no change-log entry"},
        observation.forgotten...);
  visit(ObservationField{"restored", U::kOptionalOmittedWhenEmpty, "",
                         "removed objects the map found again at their place (mode restore): "
                         "back in state 1 with their edges"},
        observation.restored...);
  visit(ObservationField{"present_by_points", U::kOptionalOmittedWhenEmpty, "",
                         "objects not detected whose own map points the keyframe tracked (mode "
                         "points): present, doubt cleared"},
        observation.present_by_points...);
}

// Calls visit(field, update.member...) for every per-object value, in one fixed order
// (the map file stores them in this order). In the serialized forms each is a map
// {object id: value} named field.name, holding the objects whose value is given.
template <typename Visitor, typename... Update>
void VisitObjectUpdateFields(Visitor&& visit, Update&... update) {
  using U = FieldUse;
  visit(ObservationField{"centroids", U::kOptional, "m, world frame",
                         "centroids new or changed; others keep their last one", "centroid"},
        update.centroid...);
  visit(ObservationField{"sizes", U::kOptionalOmittedWhenEmpty, "m, along the world axes",
                         "extents (mode in_image)", "size", /*non_negative=*/true},
        update.size...);
  visit(ObservationField{"classes", U::kOptionalOmittedWhenEmpty, "COCO-80 id",
                         "object classes, for the change log", "class"},
        update.class_id...);
}

// The camera's own fields, in the replay format's "camera" object and Python's camera
// dict. The distortion coefficients are optional and written together, when the camera
// has distortion.
template <typename Visitor, typename... Camera>
void VisitCameraFields(Visitor&& visit, Camera&... camera) {
  using U = FieldUse;
  visit(ObservationField{"fx", U::kRequired, "px", "focal length"}, camera.fx...);
  visit(ObservationField{"fy", U::kRequired, "px", "focal length"}, camera.fy...);
  visit(ObservationField{"cx", U::kRequired, "px", "principal point"}, camera.cx...);
  visit(ObservationField{"cy", U::kRequired, "px", "principal point"}, camera.cy...);
  visit(ObservationField{"width", U::kRequired, "px", "image width"}, camera.width...);
  visit(ObservationField{"height", U::kRequired, "px", "image height"}, camera.height...);
  visit(ObservationField{"k1", U::kOptionalOmittedWhenEmpty, "", "radial distortion"},
        camera.k1...);
  visit(ObservationField{"k2", U::kOptionalOmittedWhenEmpty, "", "radial distortion"},
        camera.k2...);
  visit(ObservationField{"k3", U::kOptionalOmittedWhenEmpty, "", "radial distortion"},
        camera.k3...);
  visit(ObservationField{"p1", U::kOptionalOmittedWhenEmpty, "", "tangential distortion"},
        camera.p1...);
  visit(ObservationField{"p2", U::kOptionalOmittedWhenEmpty, "", "tangential distortion"},
        camera.p2...);
}

// For an unknown-field message: nullopt when name is a field visit_fields lists, else the
// names it lists, joined by ", ". visit_fields(visit) calls the Visit*Fields above.
template <typename VisitFields>
std::optional<std::string> KnownNamesIfUnlisted(const std::string& name,
                                                VisitFields&& visit_fields) {
  bool listed = false;
  std::string names;
  visit_fields([&](const ObservationField& field, const auto&...) {
    listed = listed || name == field.name;
    names += (names.empty() ? "" : ", ") + std::string(field.name);
  });
  if (listed) return std::nullopt;
  return names;
}

}  // namespace ocg
