#include <gtest/gtest.h>

#include <random>

#include "ocg/core/lie.h"

namespace ocg {
namespace {

Eigen::Matrix3d NumericalW(const Eigen::Vector3d& phi, double sigma) {
  // Midpoint rule on the defining integral of W: independent of the closed forms.
  const int steps = 20000;
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  for (int i = 0; i < steps; ++i) {
    const double s = (i + 0.5) / steps;
    sum += std::exp(sigma * s) * ExpSO3(s * phi);
  }
  return sum / steps;
}

TEST(Lie, ExpLogSO3RoundTripNearZeroAndPi) {
  for (const Eigen::Vector3d& phi :
       {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1e-9, -2e-9, 0), Eigen::Vector3d(0.3, -0.2, 0.1),
        Eigen::Vector3d(0, 0, M_PI - 1e-6)}) {
    EXPECT_LT((LogSO3(ExpSO3(phi)) - phi).norm(), 1e-6) << phi.transpose();
  }
}

TEST(Lie, Sim3TranslationJacobianMatchesIntegralInAllBranches) {
  const std::vector<std::pair<Eigen::Vector3d, double>> cases = {
      {{0, 0, 0}, 0.0},     {{0.4, -0.3, 0.8}, 0.0}, {{0, 0, 0}, 0.7},
      {{1e-8, 0, 0}, -0.5}, {{0.4, -0.3, 0.8}, 0.6}, {{-1.2, 0.5, 0.2}, -1.1}};
  for (const auto& [phi, sigma] : cases) {
    EXPECT_LT((Sim3TranslationJacobian(phi, sigma) - NumericalW(phi, sigma)).norm(), 1e-7)
        << "phi " << phi.transpose() << " sigma " << sigma;
  }
}

TEST(Lie, SE3ComposeInverseExpLog) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int trial = 0; trial < 100; ++trial) {
    Vector6d xi;
    for (int i = 0; i < 6; ++i) xi[i] = 2.0 * uniform(rng);
    const SE3 pose = SE3::Exp(xi);
    EXPECT_LT((pose.Log() - xi).norm(), 1e-9);
    EXPECT_TRUE((pose * pose.Inverse()).Matrix().isApprox(Eigen::Matrix4d::Identity(), 1e-12));
    const Eigen::Vector3d point(uniform(rng), uniform(rng), uniform(rng));
    EXPECT_LT(((pose * pose) * point - pose * (pose * point)).norm(), 1e-12);
    EXPECT_TRUE(SE3::FromMatrix(pose.Matrix()).Matrix().isApprox(pose.Matrix(), 1e-12));
  }
}

TEST(Lie, Sim3ComposeInverseExpLog) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int trial = 0; trial < 100; ++trial) {
    Vector7d xi;
    for (int i = 0; i < 7; ++i) xi[i] = uniform(rng);
    const Sim3 transform = Sim3::Exp(xi);
    EXPECT_NEAR(transform.scale(), std::exp(xi[6]), 1e-12);
    EXPECT_LT((transform.Log() - xi).norm(), 1e-9);
    const Eigen::Vector3d point(uniform(rng), uniform(rng), uniform(rng));
    EXPECT_LT((transform.Inverse() * (transform * point) - point).norm(), 1e-12);
    EXPECT_TRUE(transform.Matrix().isApprox(
        Eigen::Matrix4d(Sim3::FromMatrix(transform.Matrix()).Matrix()), 1e-12));
    // The matrix acts on homogeneous points as the transform does.
    const Eigen::Vector4d homogeneous = transform.Matrix() * point.homogeneous();
    EXPECT_LT((homogeneous.head<3>() - transform * point).norm(), 1e-12);
  }
}

TEST(Lie, Sim3OfRigidHasUnitScale) {
  const SE3 pose = SE3::Exp((Vector6d() << 0.1, 0.2, 0.3, 0.4, 0.5, 0.6).finished());
  const Sim3 similarity(pose);
  EXPECT_DOUBLE_EQ(similarity.scale(), 1.0);
  EXPECT_TRUE(similarity.Matrix().isApprox(pose.Matrix()));
}

}  // namespace
}  // namespace ocg

namespace ocg {
namespace {

TEST(LookAt, TargetOnTheOpticalAxisAndUpIsUp) {
  const SE3 T_cw = LookAt({1, 2, 3}, {4, 2, 3});
  EXPECT_LT(((T_cw * Eigen::Vector3d(4, 2, 3)).head<2>()).norm(), 1e-12);  // on the axis
  EXPECT_GT((T_cw * Eigen::Vector3d(4, 2, 3)).z(), 0);                     // in front
  EXPECT_LT((T_cw * Eigen::Vector3d(4, 2, 4)).y(), 0);  // world up is image up (y down)
  const SE3 down = LookAt({0, 0, 5}, {0, 0, 0});        // looking along -up: still valid
  EXPECT_NEAR((down * Eigen::Vector3d(0, 0, 0)).z(), 5.0, 1e-12);
}

}  // namespace
}  // namespace ocg
