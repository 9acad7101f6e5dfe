#pragma once
// Evidence sources: each fills one field of the OCG's keyframe observation
// (KeyframeObservation, ocg/ocg/observation.h) from the object map, and the OCG weighs that
// field by one judgement term (ocg/ocg/judgement_terms.h). The object map asks its
// providers at every keyframe (ObjectMap::MakeKeyframeObservation). In the manner of
// OpenVINS's one class per updater.
//
// A source is one file, src/objects/evidence/NAME.cc: its provider class and one
// OCG_EVIDENCE_SOURCE(NAME, Class, "mode") line. The build lists that folder's files
// (src/objects/CMakeLists.txt), so the registry (EvidenceSources) holds every source without
// a line elsewhere; EvidenceProvidersFor gives those the OCG's modes turn on.

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

// One source of the registry.
struct EvidenceSource {
  // The judgement term (OCG.mode part, judgement_terms.h) that turns it on and reads its
  // field, or nullptr: always on.
  const char* mode;
  std::unique_ptr<EvidenceProvider> (*make)();
};

// Every source, in the order of their fields in VisitObservationFields (observation.h),
// "updates" last: the order the object map asks them in. Throws std::logic_error when a
// provider's field is no field of the observation, two fill one field, or a mode is no term.
const std::vector<EvidenceSource>& EvidenceSources();

// The providers of the sources modes turns on, in EvidenceSources()'s order: "observed" and
// "updates" always, "present_by_points" with "points".
std::vector<std::unique_ptr<EvidenceProvider>> EvidenceProvidersFor(const OcgModes& modes);

// Registers the provider class PROVIDER of src/objects/evidence/NAME.cc (NAME: the file's
// name without ".cc") under MODE (a judgement term's name, or nullptr: always on). Write it
// once in that file, inside namespace ocg.
#define OCG_EVIDENCE_SOURCE(NAME, PROVIDER, MODE)                        \
  void OcgEvidenceSource_##NAME(std::vector<EvidenceSource>& sources);   \
  void OcgEvidenceSource_##NAME(std::vector<EvidenceSource>& sources) {  \
    sources.push_back({MODE, []() -> std::unique_ptr<EvidenceProvider> { \
                         return std::make_unique<PROVIDER>();            \
                       }});                                              \
  }

}  // namespace ocg
