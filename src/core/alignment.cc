#include "ocg/core/alignment.h"

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ocg {

AlignmentResult AlignPoints(const std::vector<Eigen::Vector3d>& source,
                            const std::vector<Eigen::Vector3d>& target, bool with_scale) {
  if (source.size() != target.size()) {
    throw std::invalid_argument("AlignPoints: " + std::to_string(source.size()) +
                                " source points but " + std::to_string(target.size()) +
                                " target points");
  }
  if (source.size() < 3) {
    throw std::invalid_argument("AlignPoints: need at least 3 point pairs, got " +
                                std::to_string(source.size()));
  }
  const Eigen::Index count = static_cast<Eigen::Index>(source.size());
  Eigen::Matrix3Xd source_matrix(3, count);
  Eigen::Matrix3Xd target_matrix(3, count);
  for (Eigen::Index i = 0; i < count; ++i) {
    source_matrix.col(i) = source[static_cast<size_t>(i)];
    target_matrix.col(i) = target[static_cast<size_t>(i)];
  }
  Eigen::Vector3d source_mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& point : source) source_mean += point;
  source_mean /= static_cast<double>(count);
  double source_spread = 0.0;
  for (const Eigen::Vector3d& point : source) source_spread += (point - source_mean).squaredNorm();
  if (!(source_spread > 1e-18)) {
    throw std::invalid_argument("AlignPoints: degenerate source points (all coincide)");
  }
  const Eigen::Matrix4d transform = Eigen::umeyama(source_matrix, target_matrix, with_scale);
  AlignmentResult result;
  result.target_from_source = Sim3::FromMatrix(transform);
  double squared_error = 0.0;
  for (Eigen::Index i = 0; i < count; ++i) {
    squared_error +=
        (target_matrix.col(i) - result.target_from_source * Eigen::Vector3d(source_matrix.col(i)))
            .squaredNorm();
  }
  result.rmse = std::sqrt(squared_error / static_cast<double>(count));
  return result;
}

}  // namespace ocg
