#include "ocg/objects/point_evidence.h"

#include <algorithm>

#include "ocg/core/cpu_time.h"

namespace ocg {

OCG_EVIDENCE_SOURCE(point_evidence, PointPresenceEvidence, "points")

bool PresentByPoints(const MapObject& object, const std::vector<std::uint64_t>& tracked,
                     const SE3& T_cw, const PinholeCamera& camera, const ObjectsOptions& options,
                     const FrameFeatureSearch* frame) {
  const bool searchable = frame != nullptr && frame->features != nullptr;
  if (tracked.empty() && !searchable) return false;
  int in_image = 0;
  int seen = 0;
  std::vector<PointToFind> to_find;
  for (std::uint64_t id : ObjectPointIds(object, options.min_point_votes)) {
    const ObjectPoint& point = object.points.at(id);
    const Eigen::Vector3d in_camera = T_cw * point.position;
    if (in_camera.z() <= 0.0 || !camera.IsInImage(camera.ProjectUndistorted(in_camera))) continue;
    ++in_image;
    if (std::binary_search(tracked.begin(), tracked.end(), id)) {
      ++seen;
    } else if (searchable && point.descriptor) {
      to_find.push_back({point.position, *point.descriptor});
    }
  }
  if (!to_find.empty()) seen += SearchPointsInFrame(to_find, T_cw, camera, *frame).found;
  return seen >= options.presence_min_points && seen >= options.presence_min_share * in_image;
}

void PointPresenceEvidence::AddFrame(const std::vector<PointObservation>* points) {
  last_tracked_points_.clear();
  if (points == nullptr) return;
  for (const PointObservation& point : *points) last_tracked_points_.push_back(point.id);
  std::sort(last_tracked_points_.begin(), last_tracked_points_.end());
}

void PointPresenceEvidence::Fill(const KeyframeEvidence& keyframe,
                                 KeyframeObservation* observation) {
  const double cpu_start = ThreadCpuSeconds();
  const bool searched = keyframe.frame != nullptr && keyframe.frame->features != nullptr;
  for (const auto& [id, object] : keyframe.objects) {
    if (keyframe.detected.count(id) > 0) continue;
    if (searched) ++stats_.objects_searched;
    if (PresentByPoints(object, last_tracked_points_, keyframe.T_cw, keyframe.map.camera,
                        keyframe.map.options, keyframe.frame))
      observation->present_by_points.push_back(id);
  }
  if (!searched) return;
  ++stats_.keyframes;
  if (!observation->present_by_points.empty()) ++stats_.keyframes_with_presence;
  stats_.objects_present += static_cast<std::int64_t>(observation->present_by_points.size());
  stats_.cpu_seconds += ThreadCpuSeconds() - cpu_start;
}

}  // namespace ocg
