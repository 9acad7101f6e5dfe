#include "ocg/ocg/judgement.h"

#include <algorithm>
#include <cmath>

#include "ocg/ocg/judgement_terms.h"
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
  const std::vector<JudgementTerm>& terms = JudgementTerms();
  for (std::size_t i = 0; i < terms.size() && fraction > 0.0; ++i) {
    if (terms[i].expected && modes.has(i))
      fraction = terms[i].expected(fraction, geometry, T_cw, camera, options);
  }
  return fraction;
}

Judgement JudgeObject(const StateAndDoubt& current, const ObjectEvidence& evidence,
                      const ObjectGeometry& geometry, const SE3& T_cw, const PinholeCamera& camera,
                      const OcgOptions& options, const OcgModes& modes,
                      const KeyframeObservation* observation, ObjectId id, const GraphView* graph) {
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
  // The improved modes, in the order of their list (judgement_terms.h): the baselines
  // above switch none on.
  const std::vector<JudgementTerm>& terms = JudgementTerms();
  const TermInput input{id, observation, evidence, geometry, T_cw, camera, options, graph};
  for (std::size_t i = 0; i < terms.size(); ++i) {
    if (terms[i].present && modes.has(i) && terms[i].present(input)) {
      judgement.next = NextState(current, true, judgement.rate, 0.0, options);
      return judgement;
    }
  }
  for (std::size_t i = 0; i < terms.size(); ++i) {
    if (!terms[i].rate || !modes.has(i)) continue;
    if (const std::optional<double> rate = terms[i].rate(input)) {
      judgement.judged_by_geometry = true;
      judgement.rate = *rate;
    }
  }

  double increment = 0.0;
  // Only states 3 and 4 use the increment: skip the projections for the others.
  if (current.state == ObjectState::kUnknown || current.state == ObjectState::kSuspicious) {
    double fraction = ExpectedInView(geometry, T_cw, camera, options, modes);
    for (std::size_t i = 0; i < terms.size(); ++i) {
      if (terms[i].expected_now && modes.has(i)) fraction = terms[i].expected_now(fraction, input);
    }
    increment = DoubtIncrement(judgement.rate, fraction > 0.0, options) * fraction;
    for (std::size_t i = 0; i < terms.size(); ++i) {
      if (terms[i].blocks_increment && modes.has(i) && terms[i].blocks_increment(input))
        increment = 0.0;
    }
    judgement.missed = increment > 0.0;
    for (std::size_t i = 0; i < terms.size() && judgement.missed; ++i) {
      if (terms[i].miss_weight && modes.has(i)) increment *= terms[i].miss_weight(input);
    }
  }
  judgement.next = NextState(current, false, judgement.rate, increment, options);
  return judgement;
}

}  // namespace ocg
