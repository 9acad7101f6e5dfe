#include "ocg/optim/reprojection_cost.h"

#include <Eigen/Geometry>

#include "ocg/optim/pose_parameters.h"

namespace ocg {
namespace {

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

// Residual and (optionally) the Jacobians with respect to the pose tangent and the
// point, for a point X in world coordinates. Always succeeds with finite values for
// finite parameters: a point at, near or behind the camera is projected as if it lay at
// kMinDepth, a large but finite residual whose depth derivative is zero. Returning false
// instead made Ceres abandon the whole solve ("Residual and Jacobian evaluation failed")
// whenever one of thousands of points started behind one camera; the observation is then
// judged an outlier after the solve, as every other bad one.
bool Residual(const PinholeCamera& camera, const Eigen::Vector2d& observed, double weight,
              const double* pose, const Eigen::Vector3d& X, double* residuals,
              double* pose_jacobian, double* point_jacobian) {
  const Eigen::Quaterniond q(pose[3], pose[0], pose[1], pose[2]);
  const Eigen::Matrix3d R = q.normalized().toRotationMatrix();
  const Eigen::Vector3d rotated = R * X;
  const Eigen::Vector3d Xc = rotated + Eigen::Vector3d(pose[4], pose[5], pose[6]);
  if (!Xc.allFinite()) return false;  // the solver's own step diverged: let it reject it
  const bool clamped = Xc.z() < kMinDepth;
  const Eigen::Vector3d projected(Xc.x(), Xc.y(), clamped ? kMinDepth : Xc.z());
  const double inverse_z = 1.0 / projected.z();
  residuals[0] = weight * (camera.fx * projected.x() * inverse_z + camera.cx - observed.x());
  residuals[1] = weight * (camera.fy * projected.y() * inverse_z + camera.cy - observed.y());
  if (pose_jacobian == nullptr && point_jacobian == nullptr) return true;
  Eigen::Matrix<double, 2, 3> J = weight * ProjectionJacobian(camera, projected);
  if (clamped) J.col(2).setZero();  // the residual does not change with depth there
  if (pose_jacobian != nullptr) {
    Eigen::Map<Eigen::Matrix<double, 2, 7, Eigen::RowMajor>> Jpose(pose_jacobian);
    Jpose.leftCols<3>() = J;                      // d / d rho: translation
    Jpose.middleCols<3>(3) = -J * Skew(rotated);  // d / d phi: Exp(phi) R X + t
    Jpose.col(6).setZero();
  }
  if (point_jacobian != nullptr) {
    Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> Jpoint(point_jacobian);
    Jpoint = J * R;
  }
  return true;
}

}  // namespace

Eigen::Matrix<double, 2, 3> ProjectionJacobian(const PinholeCamera& camera,
                                               const Eigen::Vector3d& p) {
  const double inverse_z = 1.0 / p.z();
  const double inverse_z2 = inverse_z * inverse_z;
  Eigen::Matrix<double, 2, 3> J;
  J << camera.fx * inverse_z, 0.0, -camera.fx * p.x() * inverse_z2, 0.0, camera.fy * inverse_z,
      -camera.fy * p.y() * inverse_z2;
  return J;
}

ReprojectionCost::ReprojectionCost(const PinholeCamera& camera, const Eigen::Vector2d& observed,
                                   double sqrt_information)
    : camera_(camera), observed_(observed), sqrt_information_(sqrt_information) {}

bool ReprojectionCost::Evaluate(double const* const* parameters, double* residuals,
                                double** jacobians) const {
  const Eigen::Vector3d X(parameters[1][0], parameters[1][1], parameters[1][2]);
  return Residual(camera_, observed_, sqrt_information_, parameters[0], X, residuals,
                  jacobians != nullptr ? jacobians[0] : nullptr,
                  jacobians != nullptr ? jacobians[1] : nullptr);
}

PoseOnlyReprojectionCost::PoseOnlyReprojectionCost(const PinholeCamera& camera,
                                                   const Eigen::Vector3d& point_world,
                                                   const Eigen::Vector2d& observed,
                                                   double sqrt_information)
    : camera_(camera),
      point_world_(point_world),
      observed_(observed),
      sqrt_information_(sqrt_information) {}

bool PoseOnlyReprojectionCost::Evaluate(double const* const* parameters, double* residuals,
                                        double** jacobians) const {
  return Residual(camera_, observed_, sqrt_information_, parameters[0], point_world_, residuals,
                  jacobians != nullptr ? jacobians[0] : nullptr, nullptr);
}

}  // namespace ocg
