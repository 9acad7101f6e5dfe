#include "ocg/ocg/judgement.h"

#include <algorithm>
#include <cmath>

#include "ocg/ocg/observability.h"

namespace ocg {

bool GeometricallyVisible(const ObjectGeometry& geometry, const SE3& T_cw,
                          const PinholeCamera& camera, const OcgOptions& options) {
  if (!geometry.centroid || geometry.max_observed_distance <= 0.0) return false;
  return CentroidInImage(*geometry.centroid, T_cw, camera, options.image_margin) &&
         DistanceFromCamera(*geometry.centroid, T_cw) <=
             options.distance_slack * geometry.max_observed_distance;
}

void RecordDetectedView(ObjectGeometry& geometry, const Eigen::Vector3d& camera_centre,
                        const OcgOptions& options, bool record_direction) {
  ++geometry.detected_keyframes;
  if (!geometry.centroid) return;
  const Eigen::Vector3d towards_camera = camera_centre - *geometry.centroid;
  const double distance = towards_camera.norm();
  geometry.max_observed_distance = std::max(geometry.max_observed_distance, distance);
  if (!record_direction || distance <= 0.0) return;
  const Eigen::Vector3d direction = towards_camera / distance;
  const double spacing = std::cos(options.view_max_angle_deg * M_PI / 180.0 / 3.0);
  for (const Eigen::Vector3d& known : geometry.view_directions) {
    if (known.dot(direction) >= spacing) return;
  }
  geometry.view_directions.push_back(direction);
}

double MissWeight(const ObjectGeometry& geometry, const OcgOptions& options) {
  const double p = (geometry.detected_keyframes + 1.0) /
                   (geometry.detected_keyframes + geometry.missed_keyframes + 2.0);
  return std::min(1.0, std::log(1.0 - p) / std::log(1.0 - options.reliable_detection_rate));
}

double DropoutWeight(std::uint64_t observed_weight, std::uint64_t in_view_weight,
                     const OcgOptions& options) {
  if (in_view_weight == 0) return 1.0;
  const double share = std::min(1.0, static_cast<double>(observed_weight) / in_view_weight);
  if (share >= options.dropout_full_share) return 1.0;
  return std::log(1.0 - share) / std::log(1.0 - options.dropout_full_share);
}

bool InDetectedView(const ObjectGeometry& geometry, const SE3& T_cw, const OcgOptions& options) {
  if (!geometry.centroid || geometry.view_directions.empty()) return true;
  const Eigen::Vector3d towards_camera = T_cw.Inverse().translation() - *geometry.centroid;
  const double distance = towards_camera.norm();
  if (distance > options.distance_slack * geometry.max_observed_distance) return false;
  if (distance <= 0.0) return true;
  const double limit = std::cos(options.view_max_angle_deg * M_PI / 180.0);
  const Eigen::Vector3d direction = towards_camera / distance;
  return std::any_of(geometry.view_directions.begin(), geometry.view_directions.end(),
                     [&](const Eigen::Vector3d& known) { return known.dot(direction) >= limit; });
}

double ExpectedInView(const ObjectGeometry& geometry, const SE3& T_cw, const PinholeCamera& camera,
                      const OcgOptions& options, const OcgModes& modes) {
  if (!geometry.centroid || !CentroidInImage(*geometry.centroid, T_cw, camera)) return 0.0;
  double fraction = 1.0;
  if (modes.box_in_image && geometry.size) {
    fraction = BoxFractionInImage(*geometry.centroid, *geometry.size, T_cw, camera);
    if (fraction < options.min_box_fraction) return 0.0;
  }
  // A detector finds an object from where it found it before: farther away it is too
  // small, from another side it looks different or is hidden by what it stands behind.
  if (modes.detected_view && !InDetectedView(geometry, T_cw, options)) return 0.0;
  return fraction;
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
  if (evidence.present_by_points && modes.point_presence &&
      modes.strategy == ChangeStrategy::kGraph) {
    // Its own points are where they were and look as they did: the detector missed it.
    // Present, as if detected; the caller gives it no edge and no detection record (only
    // detections feed the graph).
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
    double fraction = ExpectedInView(geometry, T_cw, camera, options, modes);
    // Hidden behind objects nearer the camera: a detector cannot find it there.
    if (modes.occlusion && evidence.occluded_share >= options.max_occluded_share) fraction = 0.0;
    increment = DoubtIncrement(judgement.rate, fraction > 0.0, options) * fraction;
    if (modes.dropout_guard && evidence.degree > 0) {
      const std::size_t required = std::min<std::size_t>(
          static_cast<std::size_t>(options.guard_min_neighbours), evidence.degree);
      if (evidence.observed_neighbours < required) increment = 0.0;
    }
    // A miss says little about an object the detector often misses: the doubt grows by
    // how unlikely its absence is under its own detection rate.
    judgement.missed = increment > 0.0;
    if (judgement.missed && modes.detection_reliability) increment *= MissWeight(geometry, options);
    // Missed together with most of what is in view: the detector failed across the view,
    // which says little about this object.
    if (judgement.missed && modes.dropout_discount)
      increment *= DropoutWeight(evidence.observed_weight, evidence.in_view_weight, options);
  }
  judgement.next = NextState(current, false, judgement.rate, increment, options);
  return judgement;
}

}  // namespace ocg
