#include "ocg/ocg/observability.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ocg {
namespace {

// Closer than this (metres, along the optical axis) counts as behind the camera.
constexpr double kMinDepth = 1e-6;
// Undistorted projections farther than this share of the image size outside it are
// rejected before the distortion polynomial is evaluated.
constexpr double kFieldOfViewSlack = 0.5;
// Largest normalized-coordinate mismatch of project-then-unproject for a trusted pixel.
constexpr double kRoundTripTolerance = 1e-4;

}  // namespace

bool CentroidInImage(const Eigen::Vector3d& centroid_world, const SE3& T_cw,
                     const PinholeCamera& camera, double margin) {
  const Eigen::Vector3d point = T_cw * centroid_world;
  if (point.z() <= kMinDepth) return false;
  const Eigen::Vector2d ideal = camera.ProjectUndistorted(point);
  const double slack_x = kFieldOfViewSlack * camera.width;
  const double slack_y = kFieldOfViewSlack * camera.height;
  if (ideal.x() < -slack_x || ideal.x() > camera.width + slack_x || ideal.y() < -slack_y ||
      ideal.y() > camera.height + slack_y) {
    return false;
  }
  const Eigen::Vector2d pixel = camera.Project(point);
  if (!camera.IsInImage(pixel, margin)) return false;
  if (!camera.HasDistortion()) return true;
  // Past the point where the distortion polynomial turns back, a ray far outside the
  // field of view lands inside the image; undistorting the pixel then gives another ray.
  const Eigen::Vector3d ray = camera.Unproject(pixel);
  return (ray.head<2>() - point.head<2>() / point.z()).norm() < kRoundTripTolerance;
}

double BoxFractionInImage(const Eigen::Vector3d& centroid_world, const Eigen::Vector3d& size,
                          const SE3& T_cw, const PinholeCamera& camera) {
  if ((T_cw * centroid_world).z() <= kMinDepth) return 0.0;
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  double max_x = -min_x, max_y = -min_x;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d offset((corner & 1 ? 0.5 : -0.5) * size.x(),
                                 (corner & 2 ? 0.5 : -0.5) * size.y(),
                                 (corner & 4 ? 0.5 : -0.5) * size.z());
    const Eigen::Vector3d point = T_cw * (centroid_world + offset);
    // A corner behind the camera makes the rectangle unbounded: clip it to the near plane.
    const Eigen::Vector3d clipped(point.x(), point.y(), std::max(point.z(), 0.05));
    const Eigen::Vector2d pixel = camera.ProjectUndistorted(clipped);
    min_x = std::min(min_x, pixel.x());
    max_x = std::max(max_x, pixel.x());
    min_y = std::min(min_y, pixel.y());
    max_y = std::max(max_y, pixel.y());
  }
  const double area = (max_x - min_x) * (max_y - min_y);
  if (!(area > 0)) return CentroidInImage(centroid_world, T_cw, camera) ? 1.0 : 0.0;
  const double inside_x =
      std::max(0.0, std::min(max_x, double(camera.width)) - std::max(min_x, 0.0));
  const double inside_y =
      std::max(0.0, std::min(max_y, double(camera.height)) - std::max(min_y, 0.0));
  return std::clamp(inside_x * inside_y / area, 0.0, 1.0);
}

double DistanceFromCamera(const Eigen::Vector3d& point_world, const SE3& T_cw) {
  return (T_cw * point_world).norm();
}

}  // namespace ocg
