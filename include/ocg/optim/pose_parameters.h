#pragma once
// Camera poses as Ceres parameter blocks: 7 numbers (quaternion x y z w of R_cw, then
// t_cw), updated on the manifold by a rotation increment on the left and an additive
// translation: R <- Exp(phi) R, t <- t + rho, with the tangent vector ordered (rho, phi).

#include <ceres/manifold.h>

#include <array>

#include "ocg/core/lie.h"

namespace ocg {

constexpr int kPoseParameters = 7;
constexpr int kPoseTangent = 6;
using PoseParameters = std::array<double, kPoseParameters>;

PoseParameters ToParameters(const SE3& T_cw);
SE3 FromParameters(const double* parameters);

// The hand-written cost functions give their Jacobians with respect to the tangent
// (rho, phi) in the first six columns of the pose block (the seventh is zero), so this
// manifold's PlusJacobian is [I; 0]: Ceres multiplies the two and gets the tangent
// Jacobian without a derivative through the quaternion.
class PoseManifold : public ceres::Manifold {
 public:
  int AmbientSize() const override { return kPoseParameters; }
  int TangentSize() const override { return kPoseTangent; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

}  // namespace ocg
