#pragma once
// Least-squares alignment of corresponding 3-D point sets (Umeyama 1991).

#include <Eigen/Core>
#include <vector>

#include "ocg/core/lie.h"

namespace ocg {

struct AlignmentResult {
  Sim3 target_from_source;  // scale 1 unless estimated
  double rmse = 0.0;        // residual after alignment, in target units
};

// Finds the similarity (with_scale) or rigid transform minimising
// sum |target_i - T * source_i|^2. Throws std::invalid_argument when the sets differ in
// size, hold fewer than 3 points, or are degenerate (all points coincide).
AlignmentResult AlignPoints(const std::vector<Eigen::Vector3d>& source,
                            const std::vector<Eigen::Vector3d>& target, bool with_scale);

}  // namespace ocg
