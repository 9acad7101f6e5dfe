#pragma once
// Sim(3) as seven parameters for Ceres (internal to optim): angle-axis (3), translation
// (3), log scale (1), meaning x -> exp(log_scale) * R * x + t. Angle-axis keeps the
// problem free of manifolds; corrections stay far from the rotation of pi where it is
// singular.

#include <ceres/rotation.h>

#include <Eigen/Core>
#include <array>
#include <cmath>

#include "ocg/core/lie.h"

namespace ocg {

using Sim3Parameters = std::array<double, 7>;

inline Sim3Parameters ToParameters(const Sim3& sim3) {
  const Eigen::AngleAxisd angle_axis(sim3.quaternion());
  const Eigen::Vector3d rotation = angle_axis.angle() * angle_axis.axis();
  return {rotation.x(),           rotation.y(),           rotation.z(),
          sim3.translation().x(), sim3.translation().y(), sim3.translation().z(),
          std::log(sim3.scale())};
}

inline Sim3 FromParameters(const Sim3Parameters& p) {
  const Eigen::Vector3d rotation(p[0], p[1], p[2]);
  const double angle = rotation.norm();
  const Eigen::Quaterniond quaternion =
      angle < 1e-12 ? Eigen::Quaterniond::Identity()
                    : Eigen::Quaterniond(Eigen::AngleAxisd(angle, rotation / angle));
  return Sim3(std::exp(p[6]), quaternion, Eigen::Vector3d(p[3], p[4], p[5]));
}

// A similarity in Jet-friendly form.
template <typename T>
struct Sim3Of {
  Eigen::Matrix<T, 3, 3> R;
  Eigen::Matrix<T, 3, 1> t;
  T s;

  static Sim3Of FromParameters(const T* p) {
    Sim3Of result;
    ceres::AngleAxisToRotationMatrix(p, result.R.data());  // column-major, as Eigen
    result.t << p[3], p[4], p[5];
    result.s = exp(p[6]);
    return result;
  }
  static Sim3Of FromSim3(const Sim3& sim3) {
    Sim3Of result;
    result.R = sim3.rotation().cast<T>();
    result.t = sim3.translation().cast<T>();
    result.s = T(sim3.scale());
    return result;
  }
  Eigen::Matrix<T, 3, 1> operator*(const Eigen::Matrix<T, 3, 1>& x) const {
    return s * (R * x) + t;
  }
  Sim3Of operator*(const Sim3Of& other) const {
    Sim3Of result;
    result.R = R * other.R;
    result.t = s * (R * other.t) + t;
    result.s = s * other.s;
    return result;
  }
  Sim3Of Inverse() const {
    Sim3Of result;
    result.R = R.transpose();
    result.s = T(1) / s;
    result.t = -(result.s * (result.R * t));
    return result;
  }
};

}  // namespace ocg
