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

// The image rectangle of a world-axis-aligned box: the bounding rectangle of its projected
// corners (undistorted pixels; corners behind the camera clipped to 5 cm in front), the
// depth of its centre and of its farthest corner along the optical axis (metres).
struct ImageRectangle {
  double min_x = 0.0, min_y = 0.0, max_x = 0.0, max_y = 0.0;
  double centre_depth = 0.0;
  double far_depth = 0.0;
};

// Empty when the centre is behind the camera.
std::optional<ImageRectangle> ProjectBox(const Eigen::Vector3d& centroid_world,
                                         const Eigen::Vector3d& size, const SE3& T_cw,
                                         const PinholeCamera& camera);

// "occlusion": the share in [0, 1] of the part of `object` inside the image that the
// rectangles of `others` cover, counting only those wholly in front of the object's centre
// (their farthest corner nearer than its centre). Sampled on a regular grid; 0 when no
// part of the object is inside the image.
double OccludedShare(const ImageRectangle& object, const std::vector<ImageRectangle>& others,
                     const PinholeCamera& camera);

// Distance from the camera centre to a world point.
double DistanceFromCamera(const Eigen::Vector3d& point_world, const SE3& T_cw);

}  // namespace ocg
