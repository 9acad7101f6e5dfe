#include <gtest/gtest.h>

#include <random>

#include "ocg/core/alignment.h"

namespace ocg {
namespace {

std::vector<Eigen::Vector3d> RandomPoints(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-3.0, 3.0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < count; ++i) points.emplace_back(uniform(rng), uniform(rng), uniform(rng));
  return points;
}

TEST(Alignment, RecoversSimilarityExactly) {
  const Sim3 truth(
      2.7, Eigen::Quaterniond(Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, 2, 3).normalized())),
      Eigen::Vector3d(0.5, -4, 2));
  const auto source = RandomPoints(50, 3);
  std::vector<Eigen::Vector3d> target;
  for (const auto& point : source) target.push_back(truth * point);
  const AlignmentResult result = AlignPoints(source, target, true);
  EXPECT_NEAR(result.target_from_source.scale(), 2.7, 1e-10);
  EXPECT_TRUE(result.target_from_source.Matrix().isApprox(truth.Matrix(), 1e-10));
  EXPECT_LT(result.rmse, 1e-10);
}

TEST(Alignment, RigidAlignmentKeepsUnitScale) {
  const Sim3 truth(2.0, Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ())),
                   Eigen::Vector3d(1, 2, 3));
  const auto source = RandomPoints(30, 5);
  std::vector<Eigen::Vector3d> target;
  for (const auto& point : source) target.push_back(truth * point);
  const AlignmentResult rigid = AlignPoints(source, target, false);
  EXPECT_DOUBLE_EQ(rigid.target_from_source.scale(), 1.0);
  EXPECT_GT(rigid.rmse, 0.5);  // the scale difference cannot be absorbed
}

TEST(Alignment, RejectsTooFewOrDegeneratePoints) {
  const auto points = RandomPoints(2, 1);
  EXPECT_THROW(AlignPoints(points, points, true), std::invalid_argument);
  const std::vector<Eigen::Vector3d> same(5, Eigen::Vector3d(1, 1, 1));
  EXPECT_THROW(AlignPoints(same, same, true), std::invalid_argument);
  EXPECT_THROW(AlignPoints(RandomPoints(4, 1), RandomPoints(5, 1), true), std::invalid_argument);
}

}  // namespace
}  // namespace ocg
