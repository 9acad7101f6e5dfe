#include "ocg/objects/evidence_provider.h"

#include "ocg/objects/point_evidence.h"

namespace ocg {

void DetectionEvidence::Fill(const KeyframeEvidence& keyframe, KeyframeObservation* observation) {
  for (const auto& [id, frame] : keyframe.detected) {
    if (frame >= keyframe.session_first_frame && keyframe.objects.count(id) > 0)
      observation->observed.push_back(id);
  }
}

void GeometryEvidence::Fill(const KeyframeEvidence& keyframe, KeyframeObservation* observation) {
  for (const auto& [id, changed] : keyframe.geometry_changed) {
    const auto it = keyframe.objects.find(id);
    if (it == keyframe.objects.end() || !it->second.has_cuboid) continue;
    ObjectGeometryUpdate& update = observation->updates[id];
    update.centroid = it->second.cuboid.centre;
    update.size = WorldExtent(it->second.cuboid, keyframe.map.R_wg);
    update.class_id = it->second.class_id;
  }
}

std::vector<std::unique_ptr<EvidenceProvider>> EvidenceProvidersFor(const OcgModes& modes) {
  std::vector<std::unique_ptr<EvidenceProvider>> providers;
  providers.push_back(std::make_unique<DetectionEvidence>());
  if (modes.point_presence) providers.push_back(std::make_unique<PointPresenceEvidence>());
  providers.push_back(std::make_unique<GeometryEvidence>());
  return providers;
}

}  // namespace ocg
