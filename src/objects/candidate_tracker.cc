#include "ocg/objects/candidate_tracker.h"

#include <algorithm>

namespace ocg {

void CandidateTracker::Start(const ObjectSighting& sighting,
                             const std::vector<const PointObservation*>& box_points) {
  MapObject candidate;
  candidate.id = next_id_--;
  candidate.class_id = sighting.class_id;
  candidate.sightings.Add(sighting, static_cast<std::size_t>(context_.options.max_sightings));
  AddPointVotes(candidate, box_points);
  candidate.first_frame = candidate.last_frame = sighting.frame;
  candidate.first_timestamp = candidate.last_timestamp = sighting.timestamp;
  candidates_.emplace(candidate.id, std::move(candidate));
}

bool CandidateTracker::PredictsSharply(const std::vector<BoxView>& track,
                                       const Eigen::Vector3d& point, const SE3& T_cw) const {
  double spread = 0.0, nearest = 180.0;
  for (const BoxView& view : track) {
    spread = std::max(spread, ParallaxDeg(point, view.T_cw, track.back().T_cw));
    nearest = std::min(nearest, ParallaxDeg(point, view.T_cw, T_cw));
  }
  return nearest <= std::max(context_.options.candidate_min_parallax_deg, spread);
}

MapObject* CandidateTracker::AcrossGap(const ObjectDetection& detection, std::int64_t frame,
                                       double timestamp, const SE3& T_cw, int session) {
  if (context_.options.candidate_gap_seconds <= 0 || detection.truncated) return nullptr;
  MapObject* best = nullptr;
  double best_fit = 0.0;
  for (auto& [id, candidate] : candidates_) {
    // Candidates with a predicted box had their chance in the assignment.
    if (candidate.class_id != detection.class_id || candidate.last_frame >= frame ||
        frame - candidate.last_frame <= context_.options.predicted_box_frames ||
        timestamp - candidate.last_timestamp > context_.options.candidate_gap_seconds) {
      continue;
    }
    // Its untruncated boxes of this session (an earlier session's place may hold another
    // object now), thinned as for a triangulation; the last one is kept.
    std::vector<BoxView> usable;
    for (const ObjectSighting& sighting : candidate.sightings) {
      if (!sighting.truncated && sighting.session == session)
        usable.push_back({sighting.T_cw, sighting.box});
    }
    if (usable.empty()) continue;
    std::vector<BoxView> track;
    for (std::size_t index :
         Thinned(usable.size(), static_cast<std::size_t>(context_.options.max_rays)))
      track.push_back(usable[index]);
    const TrackFit fit =
        FitOfBoxToTrack(track, {T_cw, detection.box}, context_.camera,
                        context_.options.min_reacquire_iou, context_.options.min_inlier_share);
    if (fit.iou <= best_fit || !PredictsSharply(track, fit.point, T_cw)) continue;
    best_fit = fit.iou;
    best = &candidate;
  }
  return best;
}

void CandidateTracker::Update(std::int64_t frame, double timestamp,
                              const std::function<bool(MapObject& candidate)>& ready) {
  for (auto it = candidates_.begin(); it != candidates_.end();) {
    MapObject& candidate = it->second;
    // A candidate waits for a box across a detector gap for candidate_gap_seconds (with 0,
    // the first frame after candidate_max_missed_frames ends it, as before).
    const bool waited_too_long =
        frame - candidate.last_frame > context_.options.candidate_max_missed_frames &&
        timestamp - candidate.last_timestamp > context_.options.candidate_gap_seconds;
    const bool taken = !waited_too_long && candidate.last_frame == frame &&
                       Reestimate(candidate, true, context_) && ready(candidate);
    it = waited_too_long || taken ? candidates_.erase(it) : std::next(it);
  }
}

}  // namespace ocg
