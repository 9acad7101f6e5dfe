#pragma once
// Candidates: the tracks of detections no map object took, kept (negative ids) until
// their boxes' rays meet and they become map objects, or until they wait too long for
// another box. A view of the object map's candidates for one call (ObjectMap::AddFrame).

#include <cstdint>
#include <functional>
#include <map>
#include <vector>

#include "ocg/objects/map_object.h"
#include "ocg/objects/object_geometry.h"

namespace ocg {

class CandidateTracker {
 public:
  // candidates and next_id (the next candidate's id, counting down) are the object map's.
  CandidateTracker(std::map<ObjectId, MapObject>* candidates, ObjectId* next_id,
                   const ObjectMapContext& context)
      : candidates_(*candidates), next_id_(*next_id), context_(context) {}

  // A new candidate of the sighting (frame and time its own), voting for box_points.
  void Start(const ObjectSighting& sighting,
             const std::vector<const PointObservation*>& box_points);
  // The candidate an unassociated, untruncated box continues after a detector gap (longer
  // than Objects.predicted_box_frames, within Objects.candidate_gap_seconds; the box fits
  // its track of session's boxes: FitOfBoxToTrack), the best fitting one; null when none.
  MapObject* AcrossGap(const ObjectDetection& detection, std::int64_t frame, double timestamp,
                       const SE3& T_cw, int session);
  // After the frame's sightings: ends the candidates that waited too long (not detected for
  // more than Objects.candidate_max_missed_frames nor within candidate_gap_seconds), and
  // hands each one detected in frame whose rays now meet (Reestimate as a candidate) to
  // ready, which returns whether it took it (the candidate then leaves).
  void Update(std::int64_t frame, double timestamp,
              const std::function<bool(MapObject& candidate)>& ready);

 private:
  // Whether a box at point, seen from T_cw, is predicted sharply by the track's views
  // (Objects.candidate_gap_seconds): the view is within candidate_min_parallax_deg of one
  // of them (from nearly one place the depth does not matter: the box is where the last
  // one was), or within the track's own spread of views (which fixes the depth). From
  // farther round, the object of a track whose depth is free could be anywhere along a
  // line across the image, and a box of its class there is as likely another object.
  bool PredictsSharply(const std::vector<BoxView>& track, const Eigen::Vector3d& point,
                       const SE3& T_cw) const;

  std::map<ObjectId, MapObject>& candidates_;
  ObjectId& next_id_;
  const ObjectMapContext& context_;
};

}  // namespace ocg
