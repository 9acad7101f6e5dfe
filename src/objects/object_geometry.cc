#include "ocg/objects/object_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>

#include "ocg/core/convex_hull.h"
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
  double squared = 0.0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const double distance = DistanceToRay(point, rays[i]);
    const bool in_front = (point - rays[i].origin).dot(rays[i].direction) > 0;
    if (distance > 3.0 * sigma || !in_front) continue;
    result.inliers[i] = true;
    ++result.inlier_count;
    squared += distance * distance;
  }
  if (result.inlier_count < 2) return result;
  result.point = point;
  result.rms_distance = std::sqrt(squared / result.inlier_count);
  // The largest angle between two inlier rays, exactly.
  double smallest_cosine = 1.0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (!result.inliers[i]) continue;
    for (std::size_t j = i + 1; j < rays.size(); ++j) {
      if (result.inliers[j])
        smallest_cosine = std::min(smallest_cosine, rays[i].direction.dot(rays[j].direction));
    }
  }
  result.parallax_deg = std::acos(std::clamp(smallest_cosine, -1.0, 1.0)) * 180.0 / kPi;
  result.valid = result.inlier_count >= min_inlier_share * static_cast<double>(rays.size());
  return result;
}

TrackFit FitOfBoxToTrack(const std::vector<BoxView>& track, const BoxView& view,
                         const PinholeCamera& camera, double min_iou, double min_share) {
  TrackFit best;
  if (track.empty()) return best;
  const BoxView& last = track.back();
  const Ray ray = PixelRay(last.box.Centre(), last.T_cw, camera);
  // Distance along the ray per unit of depth (z) in the last view.
  const double range_per_depth = camera.Unproject(last.box.Centre()).norm();
  // The box an object of width x height (metres) centred at point shows in a view.
  const auto box_of = [&](const Eigen::Vector3d& point, double width, double height,
                          const SE3& T_cw) -> std::optional<Box2> {
    const Eigen::Vector3d in_camera = T_cw * point;
    if (in_camera.z() <= 1e-9) return std::nullopt;
    const Eigen::Vector2d centre = camera.ProjectUndistorted(in_camera);
    const double half_width = 0.5 * width * camera.fx / in_camera.z();
    const double half_height = 0.5 * height * camera.fy / in_camera.z();
    return Box2{centre.x() - half_width, centre.y() - half_height, centre.x() + half_width,
                centre.y() + half_height};
  };
  const double needed = min_share * static_cast<double>(track.size());
  for (double depth = 1e-3; depth <= 1e3; depth *= 1.02) {
    const Eigen::Vector3d point = ray.origin + depth * range_per_depth * ray.direction;
    const double width = last.box.Width() * depth / camera.fx;
    const double height = last.box.Height() * depth / camera.fy;
    // The new view first: it fits over a narrow range of depths only.
    const std::optional<Box2> predicted = box_of(point, width, height, view.T_cw);
    const double overlap = predicted ? IntersectionOverUnion(*predicted, view.box) : 0.0;
    if (overlap < min_iou || overlap <= best.iou) continue;
    int fitting = 0;
    for (const BoxView& seen : track) {
      const std::optional<Box2> expected = box_of(point, width, height, seen.T_cw);
      fitting += expected && IntersectionOverUnion(*expected, seen.box) >= min_iou ? 1 : 0;
    }
    if (fitting >= needed) best = {overlap, point};
  }
  return best;
}

double ParallaxDeg(const Eigen::Vector3d& point, const SE3& T_cw_a, const SE3& T_cw_b) {
  const Eigen::Vector3d to_a = T_cw_a.Inverse().translation() - point;
  const Eigen::Vector3d to_b = T_cw_b.Inverse().translation() - point;
  const double cosine = to_a.normalized().dot(to_b.normalized());
  return std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / kPi;
}

Cuboid EstimateCuboid(const Eigen::Vector3d& centre, const std::vector<BoxView>& views,
                      const PinholeCamera& camera, const Eigen::Matrix3d& R_wg,
                      std::optional<double> known_yaw) {
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
  // Least-squares sides at yaw psi and their squared error.
  const auto fit_sides = [&](double psi, double* error) {
    Eigen::MatrixXd design(static_cast<Eigen::Index>(widths.size()), 2);
    Eigen::VectorXd target(static_cast<Eigen::Index>(widths.size()));
    for (std::size_t i = 0; i < widths.size(); ++i) {
      const auto row = static_cast<Eigen::Index>(i);
      design(row, 0) = std::abs(std::sin(psi - azimuths[i]));
      design(row, 1) = std::abs(std::cos(psi - azimuths[i]));
      target(row) = widths[i];
    }
    const Eigen::Vector2d fit = design.colPivHouseholderQr().solve(target).cwiseMax(0.0);
    *error = (design * fit - target).squaredNorm();
    return fit;
  };
  double a = Median(widths), b = a, yaw = 0.0;
  if (spread > 30.0 * kPi / 180.0 && widths.size() >= 3) {
    double error = 0.0;
    if (known_yaw) {
      yaw = *known_yaw;
    } else {
      double best_error = std::numeric_limits<double>::infinity();
      for (int step = 0; step < 30; ++step) {  // yaw in [0, 90) degrees: a and b swap beyond
        const double psi = step * (kPi / 2) / 30;
        fit_sides(psi, &error);
        if (error < best_error) {
          best_error = error;
          yaw = psi;
        }
      }
    }
    const Eigen::Vector2d fit = fit_sides(yaw, &error);
    a = fit(0);
    b = fit(1);
    const double floor = 0.2 * std::max(a, b);  // a side fitted to ~0 is unobserved, not flat
    a = std::max(a, floor);
    b = std::max(b, floor);
  } else if (known_yaw) {
    // Too narrow a range of views for two sides: a square turned to the known yaw, whose
    // side each width gives.
    std::vector<double> sides;
    for (std::size_t i = 0; i < widths.size(); ++i) {
      sides.push_back(widths[i] / (std::abs(std::sin(*known_yaw - azimuths[i])) +
                                   std::abs(std::cos(*known_yaw - azimuths[i]))));
    }
    a = b = Median(sides);
    yaw = *known_yaw;
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

Rectangle2 MinAreaRectangle(const std::vector<Eigen::Vector2d>& points) {
  Rectangle2 best;
  if (points.size() < 3) return best;
  const std::vector<Eigen::Vector2d> hull = ConvexHull(points);
  if (hull.size() < 3) return best;
  // The smallest rectangle has a side on a hull edge: try each edge's direction.
  double best_area = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Eigen::Vector2d edge = hull[(i + 1) % hull.size()] - hull[i];
    if (edge.norm() < 1e-12) continue;
    const Eigen::Vector2d along = edge.normalized();
    const Eigen::Vector2d across(-along.y(), along.x());
    double low_u = 1e300, high_u = -1e300, low_v = 1e300, high_v = -1e300;
    for (const Eigen::Vector2d& p : hull) {
      low_u = std::min(low_u, p.dot(along));
      high_u = std::max(high_u, p.dot(along));
      low_v = std::min(low_v, p.dot(across));
      high_v = std::max(high_v, p.dot(across));
    }
    const double area = (high_u - low_u) * (high_v - low_v);
    if (area >= best_area) continue;
    best_area = area;
    best.valid = true;
    best.centre = 0.5 * (low_u + high_u) * along + 0.5 * (low_v + high_v) * across;
    // Yaw in [0, 90) degrees: a quarter turn swaps the sides.
    double yaw = std::atan2(along.y(), along.x());
    double length = high_u - low_u, width = high_v - low_v;
    yaw = std::fmod(yaw + 2 * kPi, kPi);
    if (yaw >= kPi / 2) {
      yaw -= kPi / 2;
      std::swap(length, width);
    }
    best.yaw = yaw;
    best.length = length;
    best.width = width;
  }
  return best;
}

}  // namespace ocg
