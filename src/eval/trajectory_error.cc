#include "ocg/eval/trajectory_error.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <tuple>

#include "ocg/core/alignment.h"

namespace ocg {
namespace {

std::vector<std::size_t> OrderByTime(const std::vector<StampedPose>& poses) {
  std::vector<std::size_t> order(poses.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return poses[a].timestamp < poses[b].timestamp;
  });
  return order;
}

Sim3 Align(const std::vector<StampedPose>& reference, const std::vector<StampedPose>& estimate,
           const std::vector<PoseAssociation>& pairs, AlignmentMode mode) {
  if (mode == AlignmentMode::kNone) return Sim3();
  std::vector<Eigen::Vector3d> source, target;
  for (const PoseAssociation& pair : pairs) {
    source.push_back(estimate[pair.estimate_index].T_wc.translation());
    target.push_back(reference[pair.reference_index].T_wc.translation());
  }
  return AlignPoints(source, target, mode == AlignmentMode::kSim3).target_from_source;
}

std::vector<PoseAssociation> RequirePairs(const std::vector<StampedPose>& reference,
                                          const std::vector<StampedPose>& estimate, double max_dt,
                                          std::size_t minimum) {
  std::vector<PoseAssociation> pairs = AssociateByTimestamp(reference, estimate, max_dt);
  if (pairs.size() < minimum) {
    throw std::invalid_argument(
        "only " + std::to_string(pairs.size()) + " of " + std::to_string(estimate.size()) +
        " estimated poses have a reference pose within " + std::to_string(max_dt) + " s (need " +
        std::to_string(minimum) +
        "): check that both files use the same time base, or raise --max-dt");
  }
  return pairs;
}

}  // namespace

std::vector<PoseAssociation> AssociateByTimestamp(const std::vector<StampedPose>& reference,
                                                  const std::vector<StampedPose>& estimate,
                                                  double max_dt) {
  const std::vector<std::size_t> reference_order = OrderByTime(reference);
  std::vector<double> reference_times;
  reference_times.reserve(reference.size());
  for (std::size_t index : reference_order) reference_times.push_back(reference[index].timestamp);

  using Candidate = std::tuple<double, std::size_t, std::size_t>;  // |dt|, estimate, reference
  std::vector<Candidate> candidates;
  for (std::size_t e = 0; e < estimate.size(); ++e) {
    const double time = estimate[e].timestamp;
    auto it = std::lower_bound(reference_times.begin(), reference_times.end(), time - max_dt);
    for (; it != reference_times.end() && *it <= time + max_dt; ++it) {
      const std::size_t r = reference_order[static_cast<std::size_t>(it - reference_times.begin())];
      candidates.emplace_back(std::abs(*it - time), e, r);
    }
  }
  std::sort(candidates.begin(), candidates.end());
  std::vector<bool> reference_used(reference.size(), false);
  std::vector<bool> estimate_used(estimate.size(), false);
  std::vector<PoseAssociation> pairs;
  for (const auto& [dt, e, r] : candidates) {
    if (reference_used[r] || estimate_used[e]) continue;
    reference_used[r] = estimate_used[e] = true;
    pairs.push_back({r, e});
  }
  std::sort(pairs.begin(), pairs.end(), [&](const PoseAssociation& a, const PoseAssociation& b) {
    return std::make_pair(estimate[a.estimate_index].timestamp, a.estimate_index) <
           std::make_pair(estimate[b.estimate_index].timestamp, b.estimate_index);
  });
  return pairs;
}

AlignmentMode ParseAlignmentMode(const std::string& text) {
  if (text == "sim3") return AlignmentMode::kSim3;
  if (text == "se3") return AlignmentMode::kSE3;
  if (text == "none") return AlignmentMode::kNone;
  throw std::invalid_argument("unknown alignment '" + text + "' (use sim3, se3 or none)");
}

std::string ToString(AlignmentMode mode) {
  switch (mode) {
    case AlignmentMode::kSim3:
      return "sim3";
    case AlignmentMode::kSE3:
      return "se3";
    case AlignmentMode::kNone:
      return "none";
  }
  return "?";
}

ErrorStatistics ComputeStatistics(std::vector<double> errors) {
  ErrorStatistics stats;
  stats.count = errors.size();
  if (errors.empty()) return stats;
  const double count = static_cast<double>(errors.size());
  double sum = 0.0, sum_squares = 0.0;
  for (double error : errors) {
    sum += error;
    sum_squares += error * error;
  }
  stats.mean = sum / count;
  stats.rmse = std::sqrt(sum_squares / count);
  double variance = 0.0;
  for (double error : errors) variance += (error - stats.mean) * (error - stats.mean);
  stats.std = std::sqrt(variance / count);
  std::sort(errors.begin(), errors.end());
  stats.min = errors.front();
  stats.max = errors.back();
  const std::size_t middle = errors.size() / 2;
  stats.median =
      errors.size() % 2 == 1 ? errors[middle] : 0.5 * (errors[middle - 1] + errors[middle]);
  return stats;
}

AteResult ComputeAte(const std::vector<StampedPose>& reference,
                     const std::vector<StampedPose>& estimate, const AteOptions& options) {
  AteResult result;
  result.pairs = RequirePairs(reference, estimate, options.max_dt, 3);
  result.reference_from_estimate = Align(reference, estimate, result.pairs, options.alignment);
  result.errors.reserve(result.pairs.size());
  for (const PoseAssociation& pair : result.pairs) {
    const Eigen::Vector3d aligned =
        result.reference_from_estimate * estimate[pair.estimate_index].T_wc.translation();
    result.errors.push_back((reference[pair.reference_index].T_wc.translation() - aligned).norm());
  }
  result.translation = ComputeStatistics(result.errors);
  return result;
}

RpeResult ComputeRpe(const std::vector<StampedPose>& reference,
                     const std::vector<StampedPose>& estimate, const RpeOptions& options) {
  if (!(options.delta > 0)) throw std::invalid_argument("RPE delta must be positive");
  const std::vector<PoseAssociation> pairs = RequirePairs(
      reference, estimate, options.max_dt, options.alignment == AlignmentMode::kNone ? 2 : 3);
  RpeResult result;
  result.associated = pairs.size();
  result.scale = Align(reference, estimate, pairs, options.alignment).scale();

  std::vector<double> translation_errors, rotation_errors;
  const std::size_t frame_step = static_cast<std::size_t>(std::llround(options.delta));
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    std::size_t j = i + frame_step;
    if (options.delta_in_seconds) {
      const double start = estimate[pairs[i].estimate_index].timestamp;
      j = i + 1;
      while (j < pairs.size() &&
             estimate[pairs[j].estimate_index].timestamp - start < options.delta) {
        ++j;
      }
    }
    if (j >= pairs.size() || (!options.delta_in_seconds && frame_step == 0)) break;
    const SE3& ref_i = reference[pairs[i].reference_index].T_wc;
    const SE3& ref_j = reference[pairs[j].reference_index].T_wc;
    const SE3& est_i = estimate[pairs[i].estimate_index].T_wc;
    const SE3& est_j = estimate[pairs[j].estimate_index].T_wc;
    const SE3 reference_motion = ref_i.Inverse() * ref_j;
    SE3 estimated_motion = est_i.Inverse() * est_j;
    estimated_motion =
        SE3(estimated_motion.quaternion(), result.scale * estimated_motion.translation());
    const SE3 error = reference_motion.Inverse() * estimated_motion;
    translation_errors.push_back(error.translation().norm());
    rotation_errors.push_back(LogSO3(error.rotation()).norm() * 180.0 / M_PI);
  }
  result.translation = ComputeStatistics(translation_errors);
  result.rotation_deg = ComputeStatistics(rotation_errors);
  return result;
}

}  // namespace ocg
