#pragma once
// Trajectory error metrics computed the way the TUM benchmark (evaluate_ate.py,
// evaluate_rpe.py) and evo (evo_ape, evo_rpe) compute them.

#include <cstddef>
#include <string>
#include <vector>

#include "ocg/core/lie.h"
#include "ocg/io/trajectory.h"

namespace ocg {

struct PoseAssociation {
  std::size_t reference_index = 0;
  std::size_t estimate_index = 0;
};

// TUM's associate.py: every (reference, estimate) pair closer than max_dt seconds is a
// candidate; candidates are taken greedily from the smallest time difference, each pose
// used at most once. Result ordered by estimate timestamp.
std::vector<PoseAssociation> AssociateByTimestamp(const std::vector<StampedPose>& reference,
                                                  const std::vector<StampedPose>& estimate,
                                                  double max_dt);

enum class AlignmentMode { kSim3, kSE3, kNone };
// "sim3", "se3", "none"; throws std::invalid_argument otherwise.
AlignmentMode ParseAlignmentMode(const std::string& text);
std::string ToString(AlignmentMode mode);

struct ErrorStatistics {
  std::size_t count = 0;
  double rmse = 0.0;
  double mean = 0.0;
  double median = 0.0;
  double std = 0.0;  // population standard deviation, as numpy.std
  double min = 0.0;
  double max = 0.0;
};
ErrorStatistics ComputeStatistics(std::vector<double> errors);

struct AteOptions {
  AlignmentMode alignment = AlignmentMode::kSim3;
  double max_dt = 0.02;  // seconds
};

struct AteResult {
  std::vector<PoseAssociation> pairs;
  Sim3 reference_from_estimate;  // the alignment applied to the estimate
  ErrorStatistics translation;   // metres (reference units)
  std::vector<double> errors;    // one per pair
};

// Absolute trajectory error of the positions. Throws std::invalid_argument when fewer
// than 3 pairs associate (alignment needs 3) or the estimate is degenerate.
AteResult ComputeAte(const std::vector<StampedPose>& reference,
                     const std::vector<StampedPose>& estimate, const AteOptions& options);

struct RpeOptions {
  AlignmentMode alignment = AlignmentMode::kSim3;  // only its scale matters for RPE
  double max_dt = 0.02;
  double delta = 1.0;             // distance between the two poses of a relative motion
  bool delta_in_seconds = false;  // false: delta counts associated poses
};

struct RpeResult {
  std::size_t associated = 0;
  double scale = 1.0;
  ErrorStatistics translation;   // metres
  ErrorStatistics rotation_deg;  // degrees
};

RpeResult ComputeRpe(const std::vector<StampedPose>& reference,
                     const std::vector<StampedPose>& estimate, const RpeOptions& options);

}  // namespace ocg
