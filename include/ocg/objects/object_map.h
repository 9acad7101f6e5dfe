#pragma once
// The object map: detections associated frame by frame to map objects and candidates,
// candidates promoted once they are triangulated, duplicates merged, and removals of the
// OCG applied. Feeds the OCG one KeyframeObservation per keyframe.
//
// Not thread-safe: ObjectMapper serialises every call (see object_mapper.h).

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "ocg/core/camera.h"
#include "ocg/core/lie.h"
#include "ocg/objects/box.h"
#include "ocg/objects/objects_options.h"
#include "ocg/ocg/change_detector.h"
#include "ocg/ocg/observation.h"

namespace ocg {

struct ObjectSighting {
  std::int64_t frame = 0;
  SE3 T_cw;
  Box2 box;
  bool truncated = false;
  int class_id = 0;  // as detected (detectors confuse cup and bowl, book and laptop)
};

// A map object, or a candidate (id < 0) not yet triangulated.
struct MapObject {
  ObjectId id = 0;
  int class_id = 0;                       // the most frequent class of its sightings
  std::vector<ObjectSighting> sightings;  // every one, in frame order
  Cuboid cuboid;
  bool has_cuboid = false;
  std::int64_t first_frame = 0;
  std::int64_t last_frame = 0;
  double first_timestamp = 0.0;
  double last_timestamp = 0.0;
  std::int64_t keyframes_in_map = 0;  // keyframes since promotion
};

struct ObjectChange {
  // "removed" (by the OCG), "merged" (a duplicate, hygiene) or "dropped" (too few
  // sightings, hygiene)
  std::string type;
  std::int64_t keyframe_id = 0;
  double timestamp = 0.0;
  ObjectId object_id = 0;
  ObjectId merged_into = 0;  // "merged" only
  int class_id = 0;
  Cuboid cuboid;  // the last estimate
  std::size_t sightings = 0;
  double doubt = 0.0;  // "removed" only
};

struct FrameAssociation {
  // (detection index, object id) for map objects; candidates are not listed.
  std::vector<std::pair<int, ObjectId>> matched;
  int new_candidates = 0;
  std::vector<ObjectId> promoted;  // candidates that became map objects in this frame
};

class ObjectMap {
 public:
  ObjectMap(ObjectsOptions options, PinholeCamera camera);

  // Associates this frame's (filtered) detections, updates the objects that got one,
  // starts, promotes and drops candidates.
  FrameAssociation AddFrame(std::int64_t frame, double timestamp, const SE3& T_cw,
                            const std::vector<ObjectDetection>& detections);

  // The OCG's input for a keyframe at the last added frame: the map objects detected in
  // any frame since the previous keyframe, with the geometry of those that changed.
  // Hygiene first: merges duplicates and drops objects with too few sightings (returned
  // in merges; the OCG is told to forget them through the observation).
  KeyframeObservation MakeKeyframeObservation(std::int64_t keyframe_id, double timestamp,
                                              const SE3& T_cw, std::vector<ObjectChange>* merges);

  // The OCG declared the object an outlier: it leaves the map and enters the change log.
  void Remove(const RemovalEvent& event);

  const std::map<ObjectId, MapObject>& objects() const { return objects_; }
  std::size_t CandidateCount() const { return candidates_.size(); }
  const std::vector<ObjectChange>& changes() const { return changes_; }
  const ObjectsOptions& options() const { return options_; }
  const PinholeCamera& camera() const { return camera_; }
  const Eigen::Matrix3d& gravity_frame() const { return R_wg_; }

 private:
  // Re-estimates centre and cuboid from the sightings; false when they do not meet.
  bool Reestimate(MapObject& object, bool candidate) const;
  void Merge(ObjectId kept, ObjectId absorbed, std::int64_t keyframe_id, double timestamp,
             std::vector<ObjectChange>* merges);
  double AssociationScore(const MapObject& object, const ObjectDetection& detection,
                          std::int64_t frame, const SE3& T_cw) const;

  ObjectsOptions options_;
  PinholeCamera camera_;
  Eigen::Matrix3d R_wg_;
  std::map<ObjectId, MapObject> objects_;
  std::map<ObjectId, MapObject> candidates_;                  // negative ids
  std::map<ObjectId, std::int64_t> observed_since_keyframe_;  // id -> last frame
  std::map<ObjectId, bool> geometry_changed_;
  std::vector<ObjectChange> changes_;
  ObjectId next_object_id_ = 1;
  ObjectId next_candidate_id_ = -1;
};

// objects.json (SPEC 5): the live objects with their cuboid and OCG state.
std::string ObjectsJson(const ObjectMap& map, const std::vector<ObjectStatus>& states);
// changes.json: {"changes": [{"type": "removed" | "merged", ...}]}.
std::string ObjectChangesJson(const std::vector<ObjectChange>& changes);

}  // namespace ocg
