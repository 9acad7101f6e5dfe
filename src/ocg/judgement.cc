#include "ocg/ocg/judgement.h"

#include <algorithm>

#include "ocg/ocg/observability.h"

namespace ocg {

bool GeometricallyVisible(const ObjectGeometry& geometry, const SE3& T_cw,
                          const PinholeCamera& camera, const OcgOptions& options) {
  if (!geometry.centroid || geometry.max_observed_distance <= 0.0) return false;
  return CentroidInImage(*geometry.centroid, T_cw, camera, options.image_margin) &&
         DistanceFromCamera(*geometry.centroid, T_cw) <=
             options.distance_slack * geometry.max_observed_distance;
}

Judgement JudgeObject(const StateAndDoubt& current, const ObjectEvidence& evidence,
                      const ObjectGeometry& geometry, const SE3& T_cw, const PinholeCamera& camera,
                      const OcgOptions& options, const OcgModes& modes) {
  Judgement judgement;
  judgement.rate = ActiveEdgeRate(evidence.observed_weight, evidence.total_weight);
  if (evidence.observed) {
    judgement.next = NextState(current, true, judgement.rate, 0.0, options);
    return judgement;
  }
  if (modes.strategy == ChangeStrategy::kOff) {
    judgement.next = current;
    if (current.state == ObjectState::kObserved)
      judgement.next.state = ObjectState::kRecentlyObserved;
    return judgement;
  }
  if (modes.strategy == ChangeStrategy::kVisibility) {
    // The doubt counts the keyframes since the last detection in which the object should
    // have been seen; state 4 while it counts.
    judgement.judged_by_geometry = true;
    judgement.next = current;
    if (GeometricallyVisible(geometry, T_cw, camera, options)) {
      judgement.next.doubt += 1.0;
      judgement.next.state = judgement.next.doubt >= options.visibility_keyframes
                                 ? ObjectState::kOutlier
                                 : ObjectState::kSuspicious;
    } else if (current.state == ObjectState::kObserved) {
      judgement.next.state = ObjectState::kRecentlyObserved;
    }
    return judgement;
  }
  if (evidence.degree == 0 && modes.isolated_fallback) {
    judgement.judged_by_geometry = true;
    judgement.rate =
        GeometricallyVisible(geometry, T_cw, camera, options) ? options.isolated_rate : 0.0;
  }

  double increment = 0.0;
  // Only states 3 and 4 use the increment: skip the projections for the others.
  if (current.state == ObjectState::kUnknown || current.state == ObjectState::kSuspicious) {
    bool in_image = geometry.centroid && CentroidInImage(*geometry.centroid, T_cw, camera);
    double fraction = 1.0;
    if (in_image && modes.box_in_image && geometry.size) {
      fraction = BoxFractionInImage(*geometry.centroid, *geometry.size, T_cw, camera);
      in_image = fraction >= options.min_box_fraction;
    }
    increment = DoubtIncrement(judgement.rate, in_image, options) * fraction;
    if (modes.dropout_guard && evidence.degree > 0) {
      const std::size_t required = std::min<std::size_t>(
          static_cast<std::size_t>(options.guard_min_neighbours), evidence.degree);
      if (evidence.observed_neighbours < required) increment = 0.0;
    }
  }
  judgement.next = NextState(current, false, judgement.rate, increment, options);
  return judgement;
}

}  // namespace ocg
