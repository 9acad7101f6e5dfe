#pragma once
// Geometric tests of whether an object can be seen from a camera pose.

#include <optional>
#include <vector>

#include "ocg/core/camera.h"
#include "ocg/core/lie.h"

namespace ocg {

// SPEC 3.3, the paper's P: the centroid is in front of the camera and projects inside
// the image (shrunk by margin pixels). Points outside the field of view that strong
// radial distortion folds back into the image are rejected (project-unproject check).
bool CentroidInImage(const Eigen::Vector3d& centroid_world, const SE3& T_cw,
                     const PinholeCamera& camera, double margin = 0.0);

// Fraction in [0, 1] of the image rectangle of a world-axis-aligned box (the bounding
// rectangle of its projected corners) that lies inside the image. 0 when the centroid is
// behind the camera.
double BoxFractionInImage(const Eigen::Vector3d& centroid_world, const Eigen::Vector3d& size,
                          const SE3& T_cw, const PinholeCamera& camera);

// Where a world-axis-aligned box lies in the image: the outline of its projection (the
// convex hull of its projected corners, undistorted pixels, counter-clockwise; corners
// behind the camera clipped to 5 cm in front), that outline's bounding rectangle, and the
// depth of its nearest and of its farthest corner along the optical axis (metres).
struct ImageFootprint {
  std::vector<Eigen::Vector2d> outline;
  double min_x = 0.0, min_y = 0.0, max_x = 0.0, max_y = 0.0;
  double near_depth = 0.0;
  double far_depth = 0.0;
  // Inside or on the outline; false for an outline of fewer than 3 corners.
  bool Contains(const Eigen::Vector2d& pixel) const;
};

// The footprint of the convex hull of `points`.
ImageFootprint FootprintOf(const std::vector<Eigen::Vector2d>& points, double near_depth,
                           double far_depth);

// Empty when the centre is behind the camera.
std::optional<ImageFootprint> ProjectBox(const Eigen::Vector3d& centroid_world,
                                         const Eigen::Vector3d& size, const SE3& T_cw,
                                         const PinholeCamera& camera);

// "occlusion": the share in [0, 1] of the part of `object`'s outline inside the image that
// the outlines of `others` cover, counting only those wholly in front of the object (their
// farthest corner nearer than its nearest: boxes that overlap in depth, such as a table
// under it or a neighbour beside it, do not hide it). Sampled on a regular grid; 0 when no
// part of the object is inside the image.
double OccludedShare(const ImageFootprint& object, const std::vector<ImageFootprint>& others,
                     const PinholeCamera& camera);

// Distance from the camera centre to a world point.
double DistanceFromCamera(const Eigen::Vector3d& point_world, const SE3& T_cw);

}  // namespace ocg
