#pragma once
// Reprojection error of a map point in a keyframe, with hand-written Jacobians
// (tests/optim checks them against automatic differentiation). Residual:
//   sqrt_information * (project(R_cw X + t_cw) - observed pixel)
// Finite for every finite pose and point: depths below kMinDepth (behind the camera
// included) are projected at kMinDepth, with a zero depth derivative, so Ceres never
// sees a failed evaluation at the start of a solve.
// Pose blocks follow pose_parameters.h: Jacobians are with respect to the tangent
// (rho, phi) in the pose block's first six columns.

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "ocg/core/camera.h"

namespace ocg {

// Depth (in the point's units, metres for a metric map) below which a point is projected
// as if it lay at this depth: the residual stays finite at and behind the camera.
constexpr double kMinDepth = 1e-6;

// d(pixel) / d(point in camera coordinates) of an ideal pinhole camera.
Eigen::Matrix<double, 2, 3> ProjectionJacobian(const PinholeCamera& camera,
                                               const Eigen::Vector3d& point_camera);

// Parameters: pose (7), point (3).
class ReprojectionCost : public ceres::SizedCostFunction<2, 7, 3> {
 public:
  // sqrt_information: 1 / sigma of the observation (its pyramid level's scale).
  ReprojectionCost(const PinholeCamera& camera, const Eigen::Vector2d& observed,
                   double sqrt_information);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  PinholeCamera camera_;
  Eigen::Vector2d observed_;
  double sqrt_information_;
};

// Parameters: pose (7); the point is fixed (pose-only optimization in tracking).
class PoseOnlyReprojectionCost : public ceres::SizedCostFunction<2, 7> {
 public:
  PoseOnlyReprojectionCost(const PinholeCamera& camera, const Eigen::Vector3d& point_world,
                           const Eigen::Vector2d& observed, double sqrt_information);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  PinholeCamera camera_;
  Eigen::Vector3d point_world_;
  Eigen::Vector2d observed_;
  double sqrt_information_;
};

}  // namespace ocg
