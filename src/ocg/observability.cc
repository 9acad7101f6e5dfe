#include "ocg/ocg/observability.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ocg/core/convex_hull.h"

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

bool ImageFootprint::Contains(const Eigen::Vector2d& pixel) const {
  if (outline.size() < 3) return false;
  if (pixel.x() < min_x || pixel.x() > max_x || pixel.y() < min_y || pixel.y() > max_y)
    return false;
  for (std::size_t i = 0; i < outline.size(); ++i) {
    if (Turn(outline[i], outline[(i + 1) % outline.size()], pixel) < 0) return false;
  }
  return true;
}

namespace {

// A world-axis box's corners in the image (undistorted pixels; corners behind the camera
// clipped to 5 cm in front) and its nearest and farthest corner depth.
struct ProjectedCorners {
  std::vector<Eigen::Vector2d> pixels;
  double near_depth = 0.0;
  double far_depth = 0.0;
};

// Empty when the centre is behind the camera.
std::optional<ProjectedCorners> ProjectCorners(const Eigen::Vector3d& centroid_world,
                                               const Eigen::Vector3d& size, const SE3& T_cw,
                                               const PinholeCamera& camera) {
  const double centre_depth = (T_cw * centroid_world).z();
  if (centre_depth <= kMinDepth) return std::nullopt;
  ProjectedCorners corners;
  corners.near_depth = corners.far_depth = centre_depth;
  corners.pixels.reserve(8);
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d offset((corner & 1 ? 0.5 : -0.5) * size.x(),
                                 (corner & 2 ? 0.5 : -0.5) * size.y(),
                                 (corner & 4 ? 0.5 : -0.5) * size.z());
    const Eigen::Vector3d point = T_cw * (centroid_world + offset);
    corners.near_depth = std::min(corners.near_depth, point.z());
    corners.far_depth = std::max(corners.far_depth, point.z());
    // A corner behind the camera makes the projection unbounded: clip it to the near plane.
    const Eigen::Vector3d clipped(point.x(), point.y(), std::max(point.z(), 0.05));
    corners.pixels.push_back(camera.ProjectUndistorted(clipped));
  }
  return corners;
}

// The bounding rectangle of points, as min x, min y, max x, max y.
Eigen::Vector4d BoundsOf(const std::vector<Eigen::Vector2d>& points) {
  Eigen::Vector4d bounds(
      std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
      -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity());
  for (const Eigen::Vector2d& point : points) {
    bounds.head<2>() = bounds.head<2>().cwiseMin(point);
    bounds.tail<2>() = bounds.tail<2>().cwiseMax(point);
  }
  return bounds;
}

}  // namespace

ImageFootprint FootprintOf(const std::vector<Eigen::Vector2d>& points, double near_depth,
                           double far_depth) {
  ImageFootprint footprint;
  footprint.outline = ConvexHull(points);
  const Eigen::Vector4d bounds = BoundsOf(points);
  footprint.min_x = bounds[0];
  footprint.min_y = bounds[1];
  footprint.max_x = bounds[2];
  footprint.max_y = bounds[3];
  footprint.near_depth = near_depth;
  footprint.far_depth = far_depth;
  return footprint;
}

std::optional<ImageFootprint> ProjectBox(const Eigen::Vector3d& centroid_world,
                                         const Eigen::Vector3d& size, const SE3& T_cw,
                                         const PinholeCamera& camera) {
  const std::optional<ProjectedCorners> corners =
      ProjectCorners(centroid_world, size, T_cw, camera);
  if (!corners) return std::nullopt;
  return FootprintOf(corners->pixels, corners->near_depth, corners->far_depth);
}

double BoxFractionInImage(const Eigen::Vector3d& centroid_world, const Eigen::Vector3d& size,
                          const SE3& T_cw, const PinholeCamera& camera) {
  // Called for every object that could take an increment ("in_image"): the rectangle
  // alone, no outline.
  const std::optional<ProjectedCorners> corners =
      ProjectCorners(centroid_world, size, T_cw, camera);
  if (!corners) return 0.0;
  const Eigen::Vector4d box = BoundsOf(corners->pixels);
  const double area = (box[2] - box[0]) * (box[3] - box[1]);
  if (!(area > 0)) return CentroidInImage(centroid_world, T_cw, camera) ? 1.0 : 0.0;
  const double inside_x =
      std::max(0.0, std::min(box[2], double(camera.width)) - std::max(box[0], 0.0));
  const double inside_y =
      std::max(0.0, std::min(box[3], double(camera.height)) - std::max(box[1], 0.0));
  return std::clamp(inside_x * inside_y / area, 0.0, 1.0);
}

double OccludedShare(const ImageFootprint& object, const std::vector<ImageFootprint>& others,
                     const PinholeCamera& camera) {
  std::vector<const ImageFootprint*> in_front;
  for (const ImageFootprint& other : others) {
    if (other.far_depth < object.near_depth) in_front.push_back(&other);
  }
  if (in_front.empty()) return 0.0;
  // The outline's bounding rectangle inside the image, sampled at cell centres; only the
  // samples inside the outline count.
  const double min_x = std::max(object.min_x, 0.0);
  const double max_x = std::min(object.max_x, double(camera.width));
  const double min_y = std::max(object.min_y, 0.0);
  const double max_y = std::min(object.max_y, double(camera.height));
  if (!(max_x > min_x && max_y > min_y)) return 0.0;
  constexpr int kSamples = 16;
  int inside = 0;
  int covered = 0;
  for (int i = 0; i < kSamples; ++i) {
    for (int j = 0; j < kSamples; ++j) {
      const Eigen::Vector2d sample(min_x + (i + 0.5) * (max_x - min_x) / kSamples,
                                   min_y + (j + 0.5) * (max_y - min_y) / kSamples);
      if (!object.Contains(sample)) continue;
      ++inside;
      covered +=
          std::any_of(in_front.begin(), in_front.end(),
                      [&sample](const ImageFootprint* other) { return other->Contains(sample); });
    }
  }
  return inside > 0 ? static_cast<double>(covered) / inside : 0.0;
}

double DistanceFromCamera(const Eigen::Vector3d& point_world, const SE3& T_cw) {
  return (T_cw * point_world).norm();
}

}  // namespace ocg
