#include "ocg/objects/map_cues.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Eigenvalues>

#include "ocg/core/statistics.h"

namespace ocg {
namespace {

Eigen::Vector3d Mean(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) mean += p;
  return mean / static_cast<double>(points.size());
}

Eigen::Matrix3d Covariance(const std::vector<Eigen::Vector3d>& points,
                           const Eigen::Vector3d& mean) {
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : points) scatter += (p - mean) * (p - mean).transpose();
  return scatter / static_cast<double>(points.size());
}

// Least-squares plane through the points: the normal is the direction of least spread.
SupportingPlane FitPlane(const std::vector<Eigen::Vector3d>& points) {
  SupportingPlane plane;
  plane.valid = true;
  const Eigen::Vector3d mean = Mean(points);
  plane.inlier_covariance = Covariance(points, mean);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(plane.inlier_covariance);
  plane.normal = solver.eigenvectors().col(0);
  plane.offset = -plane.normal.dot(mean);
  plane.inliers = static_cast<int>(points.size());
  return plane;
}

}  // namespace

std::vector<const PointObservation*> PointsInBox(const std::vector<PointObservation>& points,
                                                 const Box2& box, double shrink_share) {
  const double dx = shrink_share * box.Width(), dy = shrink_share * box.Height();
  std::vector<const PointObservation*> inside;
  for (const PointObservation& point : points) {
    if (point.pixel.x() >= box.x0 + dx && point.pixel.x() <= box.x1 - dx &&
        point.pixel.y() >= box.y0 + dy && point.pixel.y() <= box.y1 - dy) {
      inside.push_back(&point);
    }
  }
  return inside;
}

RobustBounds RobustPointBounds(const std::vector<Eigen::Vector3d>& positions, double sigmas,
                               double min_spread) {
  RobustBounds bounds;
  if (positions.size() < 5) return bounds;
  bounds.valid = true;
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<double> values;
    values.reserve(positions.size());
    for (const Eigen::Vector3d& p : positions) values.push_back(p[axis]);
    const double median = Median(values);
    for (double& value : values) value = std::abs(value - median);
    const double spread = std::max(min_spread, 1.4826 * Median(values));
    bounds.low[axis] = median - sigmas * spread;
    bounds.high[axis] = median + sigmas * spread;
  }
  return bounds;
}

Eigen::Vector3d CameraUpPrior(const std::vector<Eigen::Matrix3d>& camera_to_world_rotations) {
  Eigen::Matrix3d x_scatter = Eigen::Matrix3d::Zero();
  Eigen::Vector3d minus_y_sum = Eigen::Vector3d::Zero();
  for (const Eigen::Matrix3d& R_wc : camera_to_world_rotations) {
    x_scatter += R_wc.col(0) * R_wc.col(0).transpose();
    minus_y_sum -= R_wc.col(1);
  }
  return CameraUpPrior(x_scatter, minus_y_sum, camera_to_world_rotations.size());
}

Eigen::Vector3d CameraUpPrior(const Eigen::Matrix3d& x_scatter, const Eigen::Vector3d& minus_y_sum,
                              std::size_t count) {
  if (count == 0) return -Eigen::Vector3d::UnitY();
  const Eigen::Vector3d& mean_up = minus_y_sum;
  // With the camera panning, the x axes span the horizontal plane and the direction they
  // leave out is up; a camera that never turns leaves a plane of choices, in which the
  // mean -y (tilted by the camera's pitch) decides.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(x_scatter);
  const double total = x_scatter.trace();
  if (solver.eigenvalues()(1) > 0.05 * total) {
    Eigen::Vector3d up = solver.eigenvectors().col(0);
    return up.dot(mean_up) < 0 ? -up : up;
  }
  const Eigen::Vector3d x = solver.eigenvectors().col(2);
  const Eigen::Vector3d up = mean_up - mean_up.dot(x) * x;
  return up.norm() > 1e-9 ? up.normalized() : Eigen::Vector3d(-Eigen::Vector3d::UnitY());
}

SupportingPlane FindSupportingPlane(const std::vector<Eigen::Vector3d>& points,
                                    const Eigen::Vector3d& prior_up, double max_tilt_deg,
                                    double inlier_share, int iterations, std::uint64_t seed) {
  SupportingPlane best;
  if (points.size() < 30) return best;
  const Eigen::Vector3d up = prior_up.normalized();
  // Scale-free threshold: a monocular map's unit is arbitrary.
  Eigen::Vector3d median;
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<double> values;
    for (const Eigen::Vector3d& p : points) values.push_back(p[axis]);
    median[axis] = Median(values);
  }
  std::vector<double> distances;
  for (const Eigen::Vector3d& p : points) distances.push_back((p - median).norm());
  const double threshold = inlier_share * Median(distances);
  if (threshold <= 0.0) return best;
  const double min_cos = std::cos(max_tilt_deg * M_PI / 180.0);

  // Hypotheses are scored on at most kScoredPoints (evenly strided): a map of 20,000 points
  // would otherwise cost a keyframe tens of milliseconds.
  constexpr std::size_t kScoredPoints = 4000;
  const std::size_t stride = points.size() / kScoredPoints + 1;
  std::vector<Eigen::Vector3d> scored;
  for (std::size_t i = 0; i < points.size(); i += stride) scored.push_back(points[i]);
  std::mt19937_64 random(seed);
  std::uniform_int_distribution<std::size_t> pick(0, points.size() - 1);
  Eigen::Vector3d best_normal = up;
  double best_offset = 0.0;
  int best_count = 0;
  for (int iteration = 0; iteration < iterations; ++iteration) {
    const Eigen::Vector3d& a = points[pick(random)];
    const Eigen::Vector3d& b = points[pick(random)];
    const Eigen::Vector3d& c = points[pick(random)];
    Eigen::Vector3d normal = (b - a).cross(c - a);
    if (normal.norm() < 1e-12) continue;
    normal.normalize();
    if (normal.dot(up) < 0) normal = -normal;
    if (normal.dot(up) < min_cos) continue;
    const double offset = -normal.dot(a);
    int count = 0;
    for (const Eigen::Vector3d& p : scored) count += std::abs(normal.dot(p) + offset) < threshold;
    if (count > best_count) {
      best_count = count;
      best_normal = normal;
      best_offset = offset;
    }
  }
  if (best_count * static_cast<int>(stride) < 30) return best;
  std::vector<Eigen::Vector3d> inliers;
  for (const Eigen::Vector3d& p : points) {
    if (std::abs(best_normal.dot(p) + best_offset) < threshold) inliers.push_back(p);
  }
  best = FitPlane(inliers);
  if (best.normal.dot(up) < 0) {
    best.normal = -best.normal;
    best.offset = -best.offset;
  }
  if (best.normal.dot(up) < min_cos) {  // the refit tilted away: keep the sampled plane
    best.normal = best_normal;
    best.offset = best_offset;
  }
  return best;
}

Eigen::Vector3d RefineUpWithBottoms(const SupportingPlane& plane,
                                    const std::vector<Eigen::Vector3d>& bottoms,
                                    double level_tolerance) {
  if (!plane.valid) return plane.normal;
  std::vector<std::pair<double, Eigen::Vector3d>> by_height;
  for (const Eigen::Vector3d& bottom : bottoms)
    by_height.emplace_back(plane.normal.dot(bottom), bottom);
  std::sort(by_height.begin(), by_height.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  Eigen::Matrix3d total = plane.inlier_covariance;
  int levels = 0;
  for (std::size_t start = 0; start < by_height.size();) {
    std::size_t end = start + 1;
    while (end < by_height.size() &&
           by_height[end].first - by_height[end - 1].first <= level_tolerance)
      ++end;
    if (end - start >= 3) {
      std::vector<Eigen::Vector3d> level;
      for (std::size_t i = start; i < end; ++i) level.push_back(by_height[i].second);
      total += Covariance(level, Mean(level));
      ++levels;
    }
    start = end;
  }
  if (levels == 0) return plane.normal;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(total);
  const Eigen::Vector3d up = solver.eigenvectors().col(0);
  return up.dot(plane.normal) < 0 ? -up : up;
}

}  // namespace ocg
