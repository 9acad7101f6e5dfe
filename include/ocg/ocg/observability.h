#pragma once
// Geometric tests of whether an object can be seen from a camera pose.

#include <optional>

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

// Distance from the camera centre to a world point.
double DistanceFromCamera(const Eigen::Vector3d& point_world, const SE3& T_cw);

}  // namespace ocg
