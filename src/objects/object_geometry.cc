#include "ocg/objects/object_geometry.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "ocg/core/statistics.h"

namespace ocg {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Weighted least-squares point nearest to the rays; false when they are (nearly) parallel.
bool NearestPoint(const std::vector<Ray>& rays, const std::vector<double>& weights,
                  Eigen::Vector3d* point) {
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Eigen::Matrix3d projector =
        Eigen::Matrix3d::Identity() - rays[i].direction * rays[i].direction.transpose();
    normal += weights[i] * projector;
    rhs += weights[i] * projector * rays[i].origin;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(normal);
  if (eigen.eigenvalues()(0) < 1e-9 * std::max(1.0, eigen.eigenvalues()(2))) return false;
  *point = normal.ldlt().solve(rhs);
  return point->allFinite();
}

}  // namespace

double DistanceToRay(const Eigen::Vector3d& point, const Ray& ray) {
  const Eigen::Vector3d offset = point - ray.origin;
  return (offset - offset.dot(ray.direction) * ray.direction).norm();
}

Ray PixelRay(const Eigen::Vector2d& pixel, const SE3& T_cw, const PinholeCamera& camera) {
  const SE3 T_wc = T_cw.Inverse();
  Ray ray;
  ray.origin = T_wc.translation();
  ray.direction = (T_wc.rotation() * camera.Unproject(pixel)).normalized();
  return ray;
}

RayIntersection IntersectRays(const std::vector<Ray>& rays, double min_sigma,
                              double min_inlier_share) {
  RayIntersection result;
  result.inliers.assign(rays.size(), false);
  if (rays.size() < 2) return result;
  std::vector<double> weights(rays.size(), 1.0);
  Eigen::Vector3d point;
  if (!NearestPoint(rays, weights, &point)) return result;
  std::vector<double> distances(rays.size());
  double sigma = min_sigma;
  for (int iteration = 0; iteration < 10; ++iteration) {
    for (std::size_t i = 0; i < rays.size(); ++i) distances[i] = DistanceToRay(point, rays[i]);
    sigma = std::max(min_sigma, 1.4826 * Median(distances));
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const double scaled = distances[i] / sigma;
      weights[i] = 1.0 / (1.0 + scaled * scaled);  // Cauchy
    }
    Eigen::Vector3d next;
    if (!NearestPoint(rays, weights, &next)) return result;
    const double step = (next - point).norm();
    point = next;
    if (step < 1e-6) break;
  }
  Eigen::Vector3d mean_direction = Eigen::Vector3d::Zero();
  double squared = 0.0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const double distance = DistanceToRay(point, rays[i]);
    const bool in_front = (point - rays[i].origin).dot(rays[i].direction) > 0;
    if (distance > 3.0 * sigma || !in_front) continue;
    result.inliers[i] = true;
    ++result.inlier_count;
    squared += distance * distance;
    mean_direction += rays[i].direction;
  }
  if (result.inlier_count < 2) return result;
  result.point = point;
  result.rms_distance = std::sqrt(squared / result.inlier_count);
  // Twice the widest angle to the mean direction: the spread of the inlier rays.
  mean_direction.normalize();
  double widest = 0.0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (!result.inliers[i]) continue;
    widest =
        std::max(widest, std::acos(std::clamp(rays[i].direction.dot(mean_direction), -1.0, 1.0)));
  }
  result.parallax_deg = 2.0 * widest * 180.0 / kPi;
  result.valid = result.inlier_count >= min_inlier_share * static_cast<double>(rays.size());
  return result;
}

Cuboid EstimateCuboid(const Eigen::Vector3d& centre, const std::vector<BoxView>& views,
                      const PinholeCamera& camera, const Eigen::Matrix3d& R_wg) {
  Cuboid cuboid;
  cuboid.centre = centre;
  // Per view: metric width and height at the centre's depth, the azimuth of the viewing
  // ray and its elevation, in the gravity frame.
  std::vector<double> widths, heights, azimuths, elevations;
  for (const BoxView& view : views) {
    const double depth = (view.T_cw * centre).z();
    if (depth <= 1e-3) continue;
    const Eigen::Vector3d ray = R_wg.transpose() * (centre - view.T_cw.Inverse().translation());
    widths.push_back(view.box.Width() * depth / camera.fx);
    heights.push_back(view.box.Height() * depth / camera.fy);
    azimuths.push_back(std::atan2(ray.y(), ray.x()));
    elevations.push_back(std::asin(std::clamp(std::abs(ray.z()) / ray.norm(), 0.0, 1.0)));
  }
  if (widths.empty()) return cuboid;

  // Footprint a x b at yaw psi spans a|sin(psi - phi)| + b|cos(psi - phi)| across a ray of
  // azimuth phi. Azimuth spread: the widest gap between sorted azimuths tells it.
  std::vector<double> sorted = azimuths;
  std::sort(sorted.begin(), sorted.end());
  double widest_gap = sorted.front() + 2 * kPi - sorted.back();
  for (std::size_t i = 1; i < sorted.size(); ++i)
    widest_gap = std::max(widest_gap, sorted[i] - sorted[i - 1]);
  const double spread = 2 * kPi - widest_gap;
  double a = Median(widths), b = a, yaw = 0.0;
  if (spread > 30.0 * kPi / 180.0 && widths.size() >= 3) {
    double best_error = std::numeric_limits<double>::infinity();
    for (int step = 0; step < 30; ++step) {  // yaw in [0, 90) degrees: a and b swap beyond
      const double psi = step * (kPi / 2) / 30;
      Eigen::MatrixXd design(static_cast<Eigen::Index>(widths.size()), 2);
      Eigen::VectorXd target(static_cast<Eigen::Index>(widths.size()));
      for (std::size_t i = 0; i < widths.size(); ++i) {
        const auto row = static_cast<Eigen::Index>(i);
        design(row, 0) = std::abs(std::sin(psi - azimuths[i]));
        design(row, 1) = std::abs(std::cos(psi - azimuths[i]));
        target(row) = widths[i];
      }
      Eigen::Vector2d fit = design.colPivHouseholderQr().solve(target);
      fit = fit.cwiseMax(0.0);
      const double error = (design * fit - target).squaredNorm();
      if (error < best_error) {
        best_error = error;
        a = fit(0);
        b = fit(1);
        yaw = psi;
      }
    }
    const double floor = 0.2 * std::max(a, b);  // a side fitted to ~0 is unobserved, not flat
    a = std::max(a, floor);
    b = std::max(b, floor);
  }
  // Seen from elevation e, the box height spans h cos(e) plus the footprint's depth along
  // the ray times sin(e).
  std::vector<double> vertical;
  for (std::size_t i = 0; i < heights.size(); ++i) {
    const double depth_extent =
        a * std::abs(std::cos(yaw - azimuths[i])) + b * std::abs(std::sin(yaw - azimuths[i]));
    const double cosine = std::cos(elevations[i]);
    if (cosine < 0.3) continue;  // looking nearly straight down: height unobservable
    vertical.push_back((heights[i] - depth_extent * std::sin(elevations[i])) / cosine);
  }
  const double height = vertical.empty() ? Median(heights) : Median(vertical);
  cuboid.size = Eigen::Vector3d(a, b, std::max(height, 0.1 * std::max(a, b)));
  cuboid.yaw = yaw;
  return cuboid;
}

}  // namespace ocg
