#include "ocg/core/lie.h"

#include <cassert>
#include <cmath>

namespace ocg {
namespace {

// Below this angle or log-scale, series expansions replace the closed forms whose
// divisions would lose precision.
constexpr double kSmall = 1e-6;

Eigen::Quaterniond NormalizedRotation(const Eigen::Matrix3d& rotation) {
  return Eigen::Quaterniond(rotation).normalized();
}

}  // namespace

Eigen::Matrix3d Hat(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

Eigen::Matrix3d ExpSO3(const Eigen::Vector3d& phi) {
  const double angle = phi.norm();
  if (angle < kSmall) {
    const Eigen::Matrix3d hat = Hat(phi);
    return (Eigen::Matrix3d::Identity() + hat + 0.5 * hat * hat);
  }
  return Eigen::AngleAxisd(angle, phi / angle).toRotationMatrix();
}

Eigen::Vector3d LogSO3(const Eigen::Matrix3d& rotation) {
  const Eigen::AngleAxisd angle_axis(NormalizedRotation(rotation));
  double angle = angle_axis.angle();
  Eigen::Vector3d axis = angle_axis.axis();
  if (angle > M_PI) {  // Eigen may return an angle in (pi, 2 pi)
    angle = 2.0 * M_PI - angle;
    axis = -axis;
  }
  return angle * axis;
}

Eigen::Matrix3d Sim3TranslationJacobian(const Eigen::Vector3d& phi, double sigma) {
  // W = integral over s in [0, 1] of exp(sigma s) ExpSO3(s phi) ds = a I + b Phi + c Phi^2.
  const double theta = phi.norm();
  const Eigen::Matrix3d hat = Hat(phi);
  const Eigen::Matrix3d hat2 = hat * hat;
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
  if (std::abs(sigma) < kSmall) {
    if (theta < kSmall) return identity + 0.5 * hat + hat2 / 6.0;
    const double theta2 = theta * theta;
    return identity + (1.0 - std::cos(theta)) / theta2 * hat +
           (theta - std::sin(theta)) / (theta2 * theta) * hat2;
  }
  const double es = std::exp(sigma);
  const double a = (es - 1.0) / sigma;
  if (theta < kSmall) {
    const double s2 = sigma * sigma;
    const double b = ((sigma - 1.0) * es + 1.0) / s2;
    const double c = ((s2 - 2.0 * sigma + 2.0) * es - 2.0) / (2.0 * s2 * sigma);
    return a * identity + b * hat + c * hat2;
  }
  const double theta2 = theta * theta;
  const double sin_part = es * std::sin(theta);
  const double cos_part = es * std::cos(theta);
  const double denominator = sigma * sigma + theta2;
  const double b = (sin_part * sigma + (1.0 - cos_part) * theta) / (theta * denominator);
  const double c = (a - ((cos_part - 1.0) * sigma + sin_part * theta) / denominator) / theta2;
  return a * identity + b * hat + c * hat2;
}

SE3 LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
           const Eigen::Vector3d& world_up) {
  const Eigen::Vector3d z = (target - eye).normalized();
  Eigen::Vector3d x = z.cross(world_up);
  if (x.norm() < 1e-9) x = z.unitOrthogonal();  // looking straight along world_up
  x.normalize();
  Eigen::Matrix3d rotation_wc;
  rotation_wc << x, z.cross(x), z;
  return SE3(rotation_wc, eye).Inverse();
}

// ---------------------------------------------------------------- SE3

SE3::SE3(const Eigen::Quaterniond& rotation, const Eigen::Vector3d& translation)
    : rotation_(rotation.normalized()), translation_(translation) {}

SE3::SE3(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation)
    : rotation_(NormalizedRotation(rotation)), translation_(translation) {}

SE3 SE3::FromUnitQuaternion(const Eigen::Quaterniond& rotation,
                            const Eigen::Vector3d& translation) {
  assert(std::abs(rotation.squaredNorm() - 1.0) < 1e-9);
  SE3 pose;
  pose.rotation_ = rotation;
  pose.translation_ = translation;
  return pose;
}

SE3 SE3::FromMatrix(const Eigen::Matrix4d& matrix) {
  return SE3(Eigen::Matrix3d(matrix.topLeftCorner<3, 3>()), matrix.topRightCorner<3, 1>());
}

SE3 SE3::Exp(const Vector6d& xi) {
  const Eigen::Vector3d rho = xi.head<3>();
  const Eigen::Vector3d phi = xi.tail<3>();
  return SE3(ExpSO3(phi), Sim3TranslationJacobian(phi, 0.0) * rho);
}

Vector6d SE3::Log() const {
  const Eigen::Vector3d phi = LogSO3(rotation());
  Vector6d xi;
  xi.head<3>() = Sim3TranslationJacobian(phi, 0.0).inverse() * translation_;
  xi.tail<3>() = phi;
  return xi;
}

SE3 SE3::Inverse() const {
  const Eigen::Quaterniond inverse_rotation = rotation_.conjugate();
  return SE3(inverse_rotation, -(inverse_rotation * translation_));
}

SE3 SE3::operator*(const SE3& other) const {
  return SE3(rotation_ * other.rotation_, rotation_ * other.translation_ + translation_);
}

Eigen::Vector3d SE3::operator*(const Eigen::Vector3d& point) const {
  return rotation_ * point + translation_;
}

Eigen::Matrix4d SE3::Matrix() const {
  Eigen::Matrix4d matrix = Eigen::Matrix4d::Identity();
  matrix.topLeftCorner<3, 3>() = rotation();
  matrix.topRightCorner<3, 1>() = translation_;
  return matrix;
}

// ---------------------------------------------------------------- Sim3

Sim3::Sim3(double scale, const Eigen::Quaterniond& rotation, const Eigen::Vector3d& translation)
    : scale_(scale), rotation_(rotation.normalized()), translation_(translation) {}

Sim3 Sim3::FromMatrix(const Eigen::Matrix4d& matrix) {
  const Eigen::Matrix3d scaled_rotation = matrix.topLeftCorner<3, 3>();
  const double scale = std::cbrt(scaled_rotation.determinant());
  return Sim3(scale, NormalizedRotation(scaled_rotation / scale), matrix.topRightCorner<3, 1>());
}

Sim3 Sim3::Exp(const Vector7d& xi) {
  const Eigen::Vector3d rho = xi.head<3>();
  const Eigen::Vector3d phi = xi.segment<3>(3);
  const double sigma = xi(6);
  return Sim3(std::exp(sigma), Eigen::Quaterniond(ExpSO3(phi)),
              Sim3TranslationJacobian(phi, sigma) * rho);
}

Vector7d Sim3::Log() const {
  const Eigen::Vector3d phi = LogSO3(rotation());
  const double sigma = std::log(scale_);
  Vector7d xi;
  xi.head<3>() = Sim3TranslationJacobian(phi, sigma).inverse() * translation_;
  xi.segment<3>(3) = phi;
  xi(6) = sigma;
  return xi;
}

Sim3 Sim3::Inverse() const {
  const Eigen::Quaterniond inverse_rotation = rotation_.conjugate();
  const double inverse_scale = 1.0 / scale_;
  return Sim3(inverse_scale, inverse_rotation, -inverse_scale * (inverse_rotation * translation_));
}

Sim3 Sim3::operator*(const Sim3& other) const {
  return Sim3(scale_ * other.scale_, rotation_ * other.rotation_,
              scale_ * (rotation_ * other.translation_) + translation_);
}

Eigen::Vector3d Sim3::operator*(const Eigen::Vector3d& point) const {
  return scale_ * (rotation_ * point) + translation_;
}

Eigen::Matrix4d Sim3::Matrix() const {
  Eigen::Matrix4d matrix = Eigen::Matrix4d::Identity();
  matrix.topLeftCorner<3, 3>() = scale_ * rotation();
  matrix.topRightCorner<3, 1>() = translation_;
  return matrix;
}

}  // namespace ocg
