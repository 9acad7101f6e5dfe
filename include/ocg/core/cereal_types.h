#pragma once
// cereal save/load of the Eigen and Lie types that map files hold (docs/sessions.md).
// Include only from the .cc files that serialize (the modules link cereal privately).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cereal/cereal.hpp>
#include <cmath>

#include "ocg/core/lie.h"

namespace cereal {

// Fixed-size Eigen matrices: their coefficients, column-major, as one block.
template <class Archive, int Rows, int Cols, int Options>
void save(Archive& archive, const Eigen::Matrix<double, Rows, Cols, Options, Rows, Cols>& matrix) {
  static_assert(Rows > 0 && Cols > 0, "fixed-size matrices only");
  archive(binary_data(matrix.data(), sizeof(double) * Rows * Cols));
}
template <class Archive, int Rows, int Cols, int Options>
void load(Archive& archive, Eigen::Matrix<double, Rows, Cols, Options, Rows, Cols>& matrix) {
  archive(binary_data(matrix.data(), sizeof(double) * Rows * Cols));
}

template <class Archive>
void save(Archive& archive, const Eigen::Quaterniond& rotation) {
  archive(binary_data(rotation.coeffs().data(), sizeof(double) * 4));
}
template <class Archive>
void load(Archive& archive, Eigen::Quaterniond& rotation) {
  archive(binary_data(rotation.coeffs().data(), sizeof(double) * 4));
}

}  // namespace cereal

namespace ocg {

// Throws cereal::Exception when the rotation read is not a unit quaternion.
template <class Archive>
void save(Archive& archive, const SE3& pose) {
  archive(pose.quaternion(), pose.translation());
}
template <class Archive>
void load(Archive& archive, SE3& pose) {
  Eigen::Quaterniond rotation;
  Eigen::Vector3d translation;
  archive(rotation, translation);
  if (std::abs(rotation.squaredNorm() - 1.0) > 1e-9) {
    throw cereal::Exception("a pose's rotation is not a unit quaternion");
  }
  pose = SE3::FromUnitQuaternion(rotation, translation);
}

}  // namespace ocg
