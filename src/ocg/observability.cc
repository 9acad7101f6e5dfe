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

std::optional<ImageRectangle> ProjectBox(const Eigen::Vector3d& centroid_world,
                                         const Eigen::Vector3d& size, const SE3& T_cw,
                                         const PinholeCamera& camera) {
  const double centre_depth = (T_cw * centroid_world).z();
  if (centre_depth <= kMinDepth) return std::nullopt;
  ImageRectangle rectangle;
  rectangle.min_x = rectangle.min_y = std::numeric_limits<double>::infinity();
  rectangle.max_x = rectangle.max_y = -std::numeric_limits<double>::infinity();
  rectangle.centre_depth = centre_depth;
  rectangle.far_depth = centre_depth;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d offset((corner & 1 ? 0.5 : -0.5) * size.x(),
                                 (corner & 2 ? 0.5 : -0.5) * size.y(),
                                 (corner & 4 ? 0.5 : -0.5) * size.z());
    const Eigen::Vector3d point = T_cw * (centroid_world + offset);
    rectangle.far_depth = std::max(rectangle.far_depth, point.z());
    // A corner behind the camera makes the rectangle unbounded: clip it to the near plane.
    const Eigen::Vector3d clipped(point.x(), point.y(), std::max(point.z(), 0.05));
    const Eigen::Vector2d pixel = camera.ProjectUndistorted(clipped);
    rectangle.min_x = std::min(rectangle.min_x, pixel.x());
    rectangle.max_x = std::max(rectangle.max_x, pixel.x());
    rectangle.min_y = std::min(rectangle.min_y, pixel.y());
    rectangle.max_y = std::max(rectangle.max_y, pixel.y());
  }
  return rectangle;
}

double BoxFractionInImage(const Eigen::Vector3d& centroid_world, const Eigen::Vector3d& size,
                          const SE3& T_cw, const PinholeCamera& camera) {
  const std::optional<ImageRectangle> box = ProjectBox(centroid_world, size, T_cw, camera);
  if (!box) return 0.0;
  const double area = (box->max_x - box->min_x) * (box->max_y - box->min_y);
  if (!(area > 0)) return CentroidInImage(centroid_world, T_cw, camera) ? 1.0 : 0.0;
  const double inside_x =
      std::max(0.0, std::min(box->max_x, double(camera.width)) - std::max(box->min_x, 0.0));
  const double inside_y =
      std::max(0.0, std::min(box->max_y, double(camera.height)) - std::max(box->min_y, 0.0));
  return std::clamp(inside_x * inside_y / area, 0.0, 1.0);
}

double OccludedShare(const ImageRectangle& object, const std::vector<ImageRectangle>& others,
                     const PinholeCamera& camera) {
  // The object's part inside the image.
  const double min_x = std::max(object.min_x, 0.0);
  const double max_x = std::min(object.max_x, double(camera.width));
  const double min_y = std::max(object.min_y, 0.0);
  const double max_y = std::min(object.max_y, double(camera.height));
  if (!(max_x > min_x && max_y > min_y)) return 0.0;
  std::vector<const ImageRectangle*> in_front;
  for (const ImageRectangle& other : others) {
    if (other.far_depth < object.centre_depth) in_front.push_back(&other);
  }
  if (in_front.empty()) return 0.0;
  // The union of rectangles, sampled at cell centres: a share to a 1/kSamples^2 step.
  constexpr int kSamples = 12;
  int covered = 0;
  for (int i = 0; i < kSamples; ++i) {
    const double x = min_x + (i + 0.5) * (max_x - min_x) / kSamples;
    for (int j = 0; j < kSamples; ++j) {
      const double y = min_y + (j + 0.5) * (max_y - min_y) / kSamples;
      covered += std::any_of(in_front.begin(), in_front.end(), [x, y](const ImageRectangle* r) {
        return x >= r->min_x && x <= r->max_x && y >= r->min_y && y <= r->max_y;
      });
    }
  }
  return static_cast<double>(covered) / (kSamples * kSamples);
}

double DistanceFromCamera(const Eigen::Vector3d& point_world, const SE3& T_cw) {
  return (T_cw * point_world).norm();
}

}  // namespace ocg
