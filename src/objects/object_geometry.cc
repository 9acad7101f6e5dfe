#include "ocg/objects/object_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <ceres/ceres.h>
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

namespace {

// log(2): the factor by which FitCuboidToBoxes may change an extent.
constexpr double kExtentFreedom = 0.6931471805599453;

// The residuals of one view's box for FitCuboidToBoxes: the bounding rectangle of the
// cuboid's corners projected with the camera's distortion (as CuboidImageBounds), minus the
// box, x edges over its width, y edges over its height. Parameters: the centre (world,
// metres) and the log of the extents (so they stay positive). Templated for Ceres's
// automatic derivatives.
class BoxEdgeResidual {
 public:
  BoxEdgeResidual(const BoxView& view, const PinholeCamera& camera, const Eigen::Matrix3d& R_wg,
                  double yaw)
      : box_(view.box),
        camera_(camera),
        R_cw_(view.T_cw.rotation()),
        t_cw_(view.T_cw.translation()),
        axes_(R_cw_ * R_wg * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix()) {}

  template <typename T>
  bool operator()(const T* centre, const T* log_size, T* residual) const {
    // In the camera: the centre, and the cuboid's three half axes (corners are the centre
    // plus or minus each), with the rotations' products taken in doubles once.
    T point_centre[3], half_axis[3][3];
    for (int row = 0; row < 3; ++row) {
      point_centre[row] = T(t_cw_[row]);
      for (int col = 0; col < 3; ++col) point_centre[row] += R_cw_(row, col) * centre[col];
    }
    for (int axis = 0; axis < 3; ++axis) {
      const T half_extent = 0.5 * exp(log_size[axis]);
      for (int row = 0; row < 3; ++row) half_axis[axis][row] = axes_(row, axis) * half_extent;
    }
    T x0(1e300), y0(1e300), x1(-1e300), y1(-1e300);
    for (int i = 0; i < 8; ++i) {
      T point[3] = {point_centre[0], point_centre[1], point_centre[2]};
      for (int axis = 0; axis < 3; ++axis) {
        const bool plus = (i >> axis) & 1;
        for (int row = 0; row < 3; ++row)
          point[row] += plus ? half_axis[axis][row] : -half_axis[axis][row];
      }
      if (point[2] <= T(1e-6)) return false;
      T u, v;
      ProjectNormalized(camera_, T(point[0] / point[2]), T(point[1] / point[2]), &u, &v);
      if (u < x0) x0 = u;
      if (u > x1) x1 = u;
      if (v < y0) y0 = v;
      if (v > y1) y1 = v;
    }
    const double width = std::max(box_.Width(), 1.0);
    const double height = std::max(box_.Height(), 1.0);
    residual[0] = (x0 - box_.x0) / width;
    residual[1] = (x1 - box_.x1) / width;
    residual[2] = (y0 - box_.y0) / height;
    residual[3] = (y1 - box_.y1) / height;
    return true;
  }

 private:
  Box2 box_;
  const PinholeCamera& camera_;
  Eigen::Matrix3d R_cw_;
  Eigen::Vector3d t_cw_;
  Eigen::Matrix3d axes_;  // the cuboid's axes (gravity frame and yaw) in the camera
};

}  // namespace

Cuboid FitCuboidToBoxes(const Cuboid& initial, const std::vector<BoxView>& views,
                        const PinholeCamera& camera, const Eigen::Matrix3d& R_wg,
                        double edge_loss_scale) {
  if (views.empty() || (initial.size.array() <= 0.0).any()) return initial;
  Eigen::Vector3d centre = initial.centre;
  Eigen::Vector3d log_size = initial.size.array().log();
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::CauchyLoss loss(edge_loss_scale);
  for (const BoxView& view : views) {
    auto* cost = new ceres::AutoDiffCostFunction<BoxEdgeResidual, 4, 3, 3>(
        new BoxEdgeResidual(view, camera, R_wg, initial.yaw));
    problem.AddResidualBlock(cost, &loss, centre.data(), log_size.data());
  }
  // Extents stay within a factor of those the boxes gave at the rays' point: a side seen
  // from too few directions is not fixed by the edges, and would shrink to nothing.
  for (int axis = 0; axis < 3; ++axis) {
    problem.SetParameterLowerBound(log_size.data(), axis, log_size[axis] - kExtentFreedom);
    problem.SetParameterUpperBound(log_size.data(), axis, log_size[axis] + kExtentFreedom);
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 15;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  if (!summary.IsSolutionUsable() || !(summary.final_cost < summary.initial_cost)) return initial;
  Cuboid fitted = initial;
  fitted.centre = centre;
  fitted.size = log_size.array().exp();
  // The robust loss may fit some boxes by giving up others: the fit is kept only when its
  // projections overlap the boxes at least as well, taken over all of them.
  double initial_overlap = 0.0, fitted_overlap = 0.0;
  for (const BoxView& view : views) {
    const std::optional<Box2> before = CuboidImageBounds(initial, R_wg, view.T_cw, camera, true);
    const std::optional<Box2> after = CuboidImageBounds(fitted, R_wg, view.T_cw, camera, true);
    if (before) initial_overlap += IntersectionOverUnion(*before, view.box);
    if (after) fitted_overlap += IntersectionOverUnion(*after, view.box);
  }
  return fitted_overlap >= initial_overlap ? fitted : initial;
}

}  // namespace ocg
