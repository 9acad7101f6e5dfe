#include <gtest/gtest.h>

#include <random>

#include "ocg/eval/trajectory_error.h"

namespace ocg {
namespace {

StampedPose At(double time, const Eigen::Vector3d& position,
               const Eigen::Quaterniond& rotation = Eigen::Quaterniond::Identity()) {
  StampedPose pose;
  pose.timestamp = time;
  pose.T_wc = SE3(rotation, position);
  return pose;
}

std::vector<StampedPose> RandomTrajectory(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> step(0.0, 0.05);
  std::vector<StampedPose> poses;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Vector6d xi = Vector6d::Zero();
  for (int i = 0; i < count; ++i) {
    position += Eigen::Vector3d(step(rng), step(rng), step(rng)) + Eigen::Vector3d(0.02, 0, 0);
    for (int k = 3; k < 6; ++k) xi[k] += step(rng);
    poses.push_back(At(100.0 + i / 30.0, position, SE3::Exp(xi).quaternion()));
  }
  return poses;
}

std::vector<StampedPose> Transformed(const std::vector<StampedPose>& poses, const Sim3& transform) {
  std::vector<StampedPose> result = poses;
  for (StampedPose& pose : result) {
    pose.T_wc =
        SE3(transform.quaternion() * pose.T_wc.quaternion(), transform * pose.T_wc.translation());
  }
  return result;
}

TEST(Ate, RecoversAKnownSimilarityExactly) {
  const auto reference = RandomTrajectory(300, 1);
  const Sim3 applied(
      0.37, Eigen::Quaterniond(Eigen::AngleAxisd(2.0, Eigen::Vector3d(1, -1, 2).normalized())),
      Eigen::Vector3d(4, -1, 0.5));
  const auto estimate = Transformed(reference, applied);
  const AteResult result = ComputeAte(reference, estimate, {});
  EXPECT_EQ(result.pairs.size(), 300u);
  EXPECT_NEAR(result.reference_from_estimate.scale(), 1.0 / 0.37, 1e-9);
  EXPECT_TRUE(result.reference_from_estimate.Matrix().isApprox(applied.Inverse().Matrix(), 1e-9));
  EXPECT_LT(result.translation.rmse, 1e-9);
  // Without scale the same estimate is far off; without alignment even farther.
  AteOptions rigid;
  rigid.alignment = AlignmentMode::kSE3;
  EXPECT_GT(ComputeAte(reference, estimate, rigid).translation.rmse, 0.05);
}

TEST(Ate, HandComputedCase) {
  // Estimate = reference shifted by (1, 0, 0) except the last point, 3 m farther.
  const std::vector<StampedPose> reference = {At(0, {0, 0, 0}), At(1, {1, 0, 0}), At(2, {0, 1, 0}),
                                              At(3, {0, 0, 1})};
  const std::vector<StampedPose> estimate = {At(0, {1, 0, 0}), At(1, {2, 0, 0}), At(2, {1, 1, 0}),
                                             At(3, {1, 0, 4})};
  AteOptions none;
  none.alignment = AlignmentMode::kNone;
  const AteResult result = ComputeAte(reference, estimate, none);
  // errors 1, 1, 1, sqrt(1 + 9)
  const double e4 = std::sqrt(10.0);
  EXPECT_NEAR(result.translation.rmse, std::sqrt((3 + 10) / 4.0), 1e-12);
  EXPECT_NEAR(result.translation.mean, (3 + e4) / 4.0, 1e-12);
  EXPECT_NEAR(result.translation.median, 1.0, 1e-12);
  EXPECT_NEAR(result.translation.min, 1.0, 1e-12);
  EXPECT_NEAR(result.translation.max, e4, 1e-12);
  const double mean = (3 + e4) / 4.0;
  EXPECT_NEAR(result.translation.std,
              std::sqrt((3 * (1 - mean) * (1 - mean) + (e4 - mean) * (e4 - mean)) / 4.0), 1e-12);
}

TEST(Association, GreedyNearestWithinMaxDtEachPoseOnce) {
  std::vector<StampedPose> reference;
  for (double t : {0.00, 0.10, 0.20, 0.30, 0.70}) reference.push_back(At(t, {t, 0, 0}));
  // 0.101 and 0.104 both want 0.10; 0.104 then falls back to nothing (0.20 is too far).
  // 0.5 is in a gap; 0.31 matches 0.30; a duplicate 0.31 finds nothing left.
  std::vector<StampedPose> estimate;
  for (double t : {0.104, 0.101, 0.5, 0.31, 0.31, -0.005}) estimate.push_back(At(t, {t, 0, 0}));
  const auto pairs = AssociateByTimestamp(reference, estimate, 0.02);
  ASSERT_EQ(pairs.size(), 3u);
  EXPECT_EQ(pairs[0].estimate_index, 5u);  // -0.005 -> 0.00, ordered by estimate time
  EXPECT_EQ(pairs[0].reference_index, 0u);
  EXPECT_EQ(pairs[1].estimate_index, 1u);  // 0.101 -> 0.10 (closer than 0.104)
  EXPECT_EQ(pairs[1].reference_index, 1u);
  EXPECT_EQ(pairs[2].reference_index, 3u);  // one of the duplicates -> 0.30
  EXPECT_TRUE(pairs[2].estimate_index == 3u || pairs[2].estimate_index == 4u);
}

TEST(Ate, TooFewPairsIsAClearError) {
  const std::vector<StampedPose> reference = {At(0, {0, 0, 0}), At(1, {1, 0, 0})};
  try {
    ComputeAte(reference, {At(5, {0, 0, 0})}, {});
    FAIL();
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("time base"), std::string::npos);
  }
}

TEST(Rpe, ZeroForAScaledCopyAndDetectsADrift) {
  const auto reference = RandomTrajectory(100, 3);
  const Sim3 applied(2.0, Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ())),
                     Eigen::Vector3d(1, 2, 3));
  const RpeResult exact = ComputeRpe(reference, Transformed(reference, applied), {});
  EXPECT_EQ(exact.translation.count, 99u);
  EXPECT_NEAR(exact.scale, 0.5, 1e-9);
  EXPECT_LT(exact.translation.rmse, 1e-9);
  EXPECT_LT(exact.rotation_deg.rmse, 1e-6);

  auto drifted = reference;
  for (std::size_t i = 50; i < drifted.size(); ++i) {
    drifted[i].T_wc = SE3(drifted[i].T_wc.quaternion(),
                          drifted[i].T_wc.translation() + Eigen::Vector3d(0.3, 0, 0));
  }
  RpeOptions options;
  options.alignment = AlignmentMode::kNone;
  const RpeResult jump = ComputeRpe(reference, drifted, options);
  EXPECT_NEAR(jump.translation.max, 0.3, 1e-9);  // one relative motion contains the jump
  EXPECT_NEAR(jump.translation.median, 0.0, 1e-9);
  options.delta = 0.49;
  options.delta_in_seconds = true;
  EXPECT_EQ(ComputeRpe(reference, reference, options).translation.count, 85u);  // 15 frames
}

}  // namespace
}  // namespace ocg
