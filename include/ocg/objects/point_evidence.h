#pragma once
// The "points" evidence (OCG.mode "points", SLAM runs): an object the detector missed that
// the keyframe still shows by its own map points (present_by_points; judgement term
// "points"). Its provider is registered in src/objects/evidence/point_evidence.cc.

#include <cstdint>
#include <vector>

#include "ocg/objects/evidence_provider.h"

namespace ocg {

// OCG.mode "points": whether a frame still shows the object by its own map points. Of its
// point set (ObjectPointIds) the points that project inside the image from T_cw, at least
// Objects.presence_min_points and a share Objects.presence_min_share were tracked in the
// frame (tracked: its tracked map point ids, sorted) or, with frame, found by their
// descriptors near their projections (SearchPointsInFrame). A detector that misses an
// object does not change its texture; an object carried away takes its points with it,
// and what is left at its place (the table behind) was never most of its set. Tracking
// alone rarely sees them again: it follows its local map, and an object's points were made
// in the few frames it was detected in.
bool PresentByPoints(const MapObject& object, const std::vector<std::uint64_t>& tracked,
                     const SE3& T_cw, const PinholeCamera& camera, const ObjectsOptions& options,
                     const FrameFeatureSearch* frame = nullptr);

// The "points" evidence so far: keyframes given a frame to search, objects searched,
// objects found present, and the thread CPU time it took.
struct PointPresenceStats {
  std::int64_t keyframes = 0;
  std::int64_t keyframes_with_presence = 0;
  std::int64_t objects_searched = 0;
  std::int64_t objects_present = 0;
  double cpu_seconds = 0.0;
};

// "present_by_points": the map objects not detected since the previous keyframe that the
// keyframe shows by their points (PresentByPoints with the last frame's tracked points).
class PointPresenceEvidence : public EvidenceProvider {
 public:
  const char* Field() const override { return "present_by_points"; }
  void AddFrame(const std::vector<PointObservation>* points) override;
  void Fill(const KeyframeEvidence& keyframe, KeyframeObservation* observation) override;
  const PointPresenceStats& stats() const { return stats_; }

 private:
  // The map point ids the last frame tracked, sorted; empty without a SLAM map.
  std::vector<std::uint64_t> last_tracked_points_;
  PointPresenceStats stats_;
};

}  // namespace ocg
