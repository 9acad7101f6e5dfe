#pragma once
// Rigid (SE(3)) and similarity (Sim(3)) transforms on Eigen.
//
// Frame convention, used the same way everywhere in OCG-SLAM: a transform named
// T_ab maps coordinates in frame b to coordinates in frame a, x_a = T_ab * x_b.
// T_cw is world-to-camera (what tracking estimates), T_wc its inverse
// (what TUM trajectory files store).
//
// Tangent vectors put translation first: SE(3) xi = [rho; phi],
// Sim(3) xi = [rho; phi; sigma] with scale = exp(sigma).

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ocg {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Vector7d = Eigen::Matrix<double, 7, 1>;

// Skew-symmetric matrix [v]x such that [v]x * w = v.cross(w).
Eigen::Matrix3d Hat(const Eigen::Vector3d& v);
// Rotation matrix of the rotation vector phi (Rodrigues).
Eigen::Matrix3d ExpSO3(const Eigen::Vector3d& phi);
// Rotation vector of R, with angle in [0, pi].
Eigen::Vector3d LogSO3(const Eigen::Matrix3d& rotation);

class SE3 {
 public:
  SE3() = default;
  SE3(const Eigen::Quaterniond& rotation, const Eigen::Vector3d& translation);
  SE3(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation);
  // From a homogeneous 4x4 matrix; the rotation block is re-orthonormalised.
  static SE3 FromMatrix(const Eigen::Matrix4d& matrix);
  static SE3 Identity() { return SE3(); }
  static SE3 Exp(const Vector6d& xi);
  // From a quaternion of unit norm already (map files): kept bit for bit, where the
  // constructors normalize again and may move its last bits.
  static SE3 FromUnitQuaternion(const Eigen::Quaterniond& rotation,
                                const Eigen::Vector3d& translation);

  Vector6d Log() const;
  SE3 Inverse() const;
  SE3 operator*(const SE3& other) const;
  Eigen::Vector3d operator*(const Eigen::Vector3d& point) const;

  const Eigen::Quaterniond& quaternion() const { return rotation_; }
  Eigen::Matrix3d rotation() const { return rotation_.toRotationMatrix(); }
  const Eigen::Vector3d& translation() const { return translation_; }
  Eigen::Matrix4d Matrix() const;

 private:
  Eigen::Quaterniond rotation_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation_ = Eigen::Vector3d::Zero();
};

// x -> scale * R * x + t.
class Sim3 {
 public:
  Sim3() = default;
  Sim3(double scale, const Eigen::Quaterniond& rotation, const Eigen::Vector3d& translation);
  explicit Sim3(const SE3& rigid) : Sim3(1.0, rigid.quaternion(), rigid.translation()) {}
  static Sim3 FromMatrix(const Eigen::Matrix4d& matrix);
  static Sim3 Identity() { return Sim3(); }
  static Sim3 Exp(const Vector7d& xi);

  Vector7d Log() const;
  Sim3 Inverse() const;
  Sim3 operator*(const Sim3& other) const;
  Eigen::Vector3d operator*(const Eigen::Vector3d& point) const;

  double scale() const { return scale_; }
  const Eigen::Quaterniond& quaternion() const { return rotation_; }
  Eigen::Matrix3d rotation() const { return rotation_.toRotationMatrix(); }
  const Eigen::Vector3d& translation() const { return translation_; }
  Eigen::Matrix4d Matrix() const;

 private:
  double scale_ = 1.0;
  Eigen::Quaterniond rotation_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation_ = Eigen::Vector3d::Zero();
};

// World-to-camera pose T_cw of a camera at eye looking at target, with the image's "up"
// towards world_up (camera axes: x right, y down, z forward). eye != target.
SE3 LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
           const Eigen::Vector3d& world_up = Eigen::Vector3d::UnitZ());

// The matrix W of the Sim(3) exponential, t = W(phi, sigma) * rho. With sigma = 0 it is
// the left Jacobian of SO(3) used by the SE(3) exponential. Exposed for tests.
Eigen::Matrix3d Sim3TranslationJacobian(const Eigen::Vector3d& phi, double sigma);

}  // namespace ocg
