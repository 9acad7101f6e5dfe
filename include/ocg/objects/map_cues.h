#pragma once
// What the object layer reads of a SLAM map: the map points tracked in a frame (cues for
// association and each object's point set) and the supporting plane that says which way
// is up. The pose-given mode has neither and does without.

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "ocg/objects/box.h"

namespace ocg {

struct PointObservation {
  std::uint64_t id = 0;                                // the SLAM map point's id
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();     // undistorted, in this frame
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // world
};

// The points whose pixel lies in the box shrunk by shrink_share of its width and height
// on every side (box edges hold background as often as object).
std::vector<const PointObservation*> PointsInBox(const std::vector<PointObservation>& points,
                                                 const Box2& box, double shrink_share);

// Per axis: median +- sigmas robust standard deviations (1.4826 MAD, at least
// min_spread), so a few background points caught in the boxes do not stretch the set.
struct RobustBounds {
  bool valid = false;  // at least 5 positions
  Eigen::Vector3d low = Eigen::Vector3d::Zero();
  Eigen::Vector3d high = Eigen::Vector3d::Zero();
  bool Contains(const Eigen::Vector3d& p) const {
    return valid && (p.array() >= low.array()).all() && (p.array() <= high.array()).all();
  }
};
RobustBounds RobustPointBounds(const std::vector<Eigen::Vector3d>& positions, double sigmas,
                               double min_spread = 0.0);

// Which way is up in a monocular map, whose world frame is the first camera's: cameras
// are carried upright (no roll), so up is roughly perpendicular to every camera's x axis
// and on the side of their -y axes.
Eigen::Vector3d CameraUpPrior(const std::vector<Eigen::Matrix3d>& camera_to_world_rotations);
// The same from the rotations' sums (kept up to date as keyframes come and go): the
// scatter of their x axes (sum of x x^T), the sum of their -y axes, and their count.
Eigen::Vector3d CameraUpPrior(const Eigen::Matrix3d& x_scatter, const Eigen::Vector3d& minus_y_sum,
                              std::size_t count);

struct SupportingPlane {
  bool valid = false;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit, on the prior's side
  double offset = 0.0;                                // normal . x + offset = 0
  int inliers = 0;
  Eigen::Matrix3d inlier_covariance = Eigen::Matrix3d::Zero();  // about their mean
};

// The plane holding most map points among those within max_tilt_deg of prior_up (floor or
// table top; walls are excluded by the tilt), by RANSAC with a threshold of
// inlier_share of the points' robust spread, refined by least squares on its inliers.
// Deterministic for a given seed. Invalid with fewer than 30 points or inliers.
SupportingPlane FindSupportingPlane(const std::vector<Eigen::Vector3d>& points,
                                    const Eigen::Vector3d& prior_up, double max_tilt_deg,
                                    double inlier_share, int iterations, std::uint64_t seed);

// Up refined by the objects standing on surfaces parallel to the plane (the floor, a
// table top, shelves): their bottoms are grouped into levels whose heights along the
// plane's normal agree within level_tolerance, and up is the direction of least spread of
// the plane's inliers and of every level of at least 3 bottoms, each about its own mean
// and weighing as much as the inliers (a few bottoms spread over a room say as much about
// the tilt as many points on a patch of floor). The plane's normal when no level has 3.
Eigen::Vector3d RefineUpWithBottoms(const SupportingPlane& plane,
                                    const std::vector<Eigen::Vector3d>& bottoms,
                                    double level_tolerance);

}  // namespace ocg
