#pragma once
// Evidence sources: each fills one field of the OCG's keyframe observation
// (KeyframeObservation, ocg/ocg/observation.h) from the object map, and the OCG weighs that
// field by one judgement term (ocg/ocg/judgement.h, ObjectEvidence). The object map holds
// its providers in one list and asks each at every keyframe (ObjectMap::
// MakeKeyframeObservation); a new source is a provider, its field and its judgement term.
// In the manner of OpenVINS's one class per updater. EvidenceProvidersFor is the one list
// of the sources and the OCG modes that turn them on.

#include <cstdint>
#include <map>
#include <memory>
#include <vector>

#include "ocg/objects/map_cues.h"
#include "ocg/objects/map_object.h"
#include "ocg/objects/point_presence.h"
#include "ocg/ocg/observation.h"
#include "ocg/ocg/options.h"

namespace ocg {

// What a provider reads at a keyframe: the object map as the hygiene left it.
struct KeyframeEvidence {
  const std::map<ObjectId, MapObject>& objects;  // the live map objects
  // The map objects detected since the previous keyframe: id -> last frame detected.
  const std::map<ObjectId, std::int64_t>& detected;
  // The map objects whose geometry changed since the previous keyframe.
  const std::map<ObjectId, bool>& geometry_changed;
  std::int64_t session_first_frame = 0;  // of the session the frames are given in
  const SE3& T_cw;                       // the keyframe's pose, world to camera
  // The keyframe's features (SLAM runs), read during the call only; null: none.
  const FrameFeatureSearch* frame = nullptr;
  const ObjectMapContext& map;
};

class EvidenceProvider {
 public:
  virtual ~EvidenceProvider() = default;
  // The KeyframeObservation member it fills (its name in observation.h).
  virtual const char* Field() const = 0;
  // Each frame the map is given, before its detections are associated: the SLAM map
  // points tracked in it (null without a SLAM map).
  virtual void AddFrame(const std::vector<PointObservation>* /*points*/) {}
  // Fills the field of observation for this keyframe.
  virtual void Fill(const KeyframeEvidence& keyframe, KeyframeObservation* observation) = 0;
};

// "observed": the map objects detected in this session's frames since the previous
// keyframe (judgement: ObjectEvidence::observed).
class DetectionEvidence : public EvidenceProvider {
 public:
  const char* Field() const override { return "observed"; }
  void Fill(const KeyframeEvidence& keyframe, KeyframeObservation* observation) override;
};

// "updates": the centroid, world extent and class of each map object whose geometry
// changed since the previous keyframe (the OCG's geometry of the object).
class GeometryEvidence : public EvidenceProvider {
 public:
  const char* Field() const override { return "updates"; }
  void Fill(const KeyframeEvidence& keyframe, KeyframeObservation* observation) override;
};

// The providers of the sources modes asks for, in the order the object map asks them:
// "observed" and "updates" always, "present_by_points" with "points".
std::vector<std::unique_ptr<EvidenceProvider>> EvidenceProvidersFor(const OcgModes& modes);

}  // namespace ocg
