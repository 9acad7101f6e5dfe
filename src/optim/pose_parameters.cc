#include "ocg/optim/pose_parameters.h"

#include <algorithm>

namespace ocg {

PoseParameters ToParameters(const SE3& T_cw) {
  const Eigen::Quaterniond& q = T_cw.quaternion();
  const Eigen::Vector3d& t = T_cw.translation();
  return {q.x(), q.y(), q.z(), q.w(), t.x(), t.y(), t.z()};
}

SE3 FromParameters(const double* p) {
  return SE3(Eigen::Quaterniond(p[3], p[0], p[1], p[2]).normalized(),
             Eigen::Vector3d(p[4], p[5], p[6]));
}

bool PoseManifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  const Eigen::Quaterniond q(x[3], x[0], x[1], x[2]);
  const Eigen::Map<const Eigen::Vector3d> rho(delta);
  const Eigen::Map<const Eigen::Vector3d> phi(delta + 3);
  const Eigen::Quaterniond updated = (Eigen::Quaterniond(ExpSO3(phi)) * q).normalized();
  x_plus_delta[0] = updated.x();
  x_plus_delta[1] = updated.y();
  x_plus_delta[2] = updated.z();
  x_plus_delta[3] = updated.w();
  for (int i = 0; i < 3; ++i) x_plus_delta[4 + i] = x[4 + i] + rho[i];
  return true;
}

bool PoseManifold::PlusJacobian(const double* /*x*/, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, kPoseParameters, kPoseTangent, Eigen::RowMajor>> J(jacobian);
  J.setZero();
  J.topRows<kPoseTangent>().setIdentity();
  return true;
}

bool PoseManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  const Eigen::Quaterniond qx(x[3], x[0], x[1], x[2]);
  const Eigen::Quaterniond qy(y[3], y[0], y[1], y[2]);
  const Eigen::Vector3d phi = LogSO3((qy * qx.conjugate()).toRotationMatrix());
  for (int i = 0; i < 3; ++i) {
    y_minus_x[i] = y[4 + i] - x[4 + i];
    y_minus_x[3 + i] = phi[i];
  }
  return true;
}

bool PoseManifold::MinusJacobian(const double* /*x*/, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, kPoseTangent, kPoseParameters, Eigen::RowMajor>> J(jacobian);
  J.setZero();
  J.leftCols<kPoseTangent>().setIdentity();
  return true;
}

}  // namespace ocg
