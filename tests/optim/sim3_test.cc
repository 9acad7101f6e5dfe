// Loop closing's geometry: Sim(3) from matched points, and the Sim(3) pose graph.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "ocg/optim/pose_graph.h"
#include "ocg/optim/sim3_estimation.h"
#include "test_support.h"

namespace ocg {
namespace {

constexpr double kPi = 3.14159265358979323846;

PinholeCamera Camera() { return testing::TestCamera(525.0, 319.5, 239.5); }

double RotationDegrees(const Sim3& a, const Sim3& b) {
  return a.quaternion().angularDistance(b.quaternion()) * 180.0 / kPi;
}

// Points before camera 2; camera 1 sees them through a known similarity (the map's scale
// drifted by 1.7 between the two visits). 30 % of the matches are wrong.
std::vector<Sim3Match> LoopMatches(const Sim3& S12, int count, double outlier_share,
                                   std::uint32_t seed, std::vector<bool>* truly_inlier) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> lateral(-1.5, 1.5), depth(2.0, 6.0), unit(0.0, 1.0);
  std::normal_distribution<double> pixel_noise(0.0, 0.7), point_noise(0.0, 1.0);
  const PinholeCamera camera = Camera();
  std::vector<Sim3Match> matches;
  truly_inlier->clear();
  while (static_cast<int>(matches.size()) < count) {
    Sim3Match match;
    const Eigen::Vector3d point2(lateral(random), lateral(random), depth(random));
    Eigen::Vector3d point1 = S12 * point2;
    if (point1.z() < 0.5) continue;
    const bool outlier = unit(random) < outlier_share;
    if (outlier) point1 = S12 * Eigen::Vector3d(lateral(random), lateral(random), depth(random));
    match.pixel1 = camera.ProjectUndistorted(point1) +
                   Eigen::Vector2d(pixel_noise(random), pixel_noise(random));
    match.pixel2 = camera.ProjectUndistorted(point2) +
                   Eigen::Vector2d(pixel_noise(random), pixel_noise(random));
    // Each map triangulated its point with an error of about 0.1 % of the depth.
    match.point1 =
        point1 + 0.001 * point1.z() *
                     Eigen::Vector3d(point_noise(random), point_noise(random), point_noise(random));
    match.point2 =
        point2 + 0.001 * point2.z() *
                     Eigen::Vector3d(point_noise(random), point_noise(random), point_noise(random));
    matches.push_back(match);
    truly_inlier->push_back(!outlier);
  }
  return matches;
}

TEST(Sim3Estimation, RecoversAKnownSimilarityDespiteOutliers) {
  const Sim3 truth(
      1.7, Eigen::Quaterniond(Eigen::AngleAxisd(0.35, Eigen::Vector3d(0.2, 1, 0.1).normalized())),
      Eigen::Vector3d(0.4, -0.1, 0.6));
  std::vector<bool> truly_inlier;
  const std::vector<Sim3Match> matches = LoopMatches(truth, 200, 0.3, 5, &truly_inlier);
  Sim3EstimationOptions options;
  options.seed = 11;
  const Sim3Estimate estimate = EstimateSim3(matches, Camera(), options);
  ASSERT_TRUE(estimate.found);
  EXPECT_NEAR(estimate.S12.scale(), 1.7, 0.02);
  EXPECT_LT(RotationDegrees(estimate.S12, truth), 0.5);
  EXPECT_LT((estimate.S12.translation() - truth.translation()).norm(), 0.03);
  int true_inliers = 0, found_true = 0, found_false = 0;
  for (std::size_t i = 0; i < matches.size(); ++i) {
    true_inliers += truly_inlier[i];
    found_true += estimate.inliers[i] && truly_inlier[i];
    found_false += estimate.inliers[i] && !truly_inlier[i];
  }
  EXPECT_GE(found_true, 0.9 * true_inliers);
  EXPECT_LE(found_false, 2);
  // Seeded: the same answer again.
  const Sim3Estimate again = EstimateSim3(matches, Camera(), options);
  EXPECT_EQ(again.inliers, estimate.inliers);
  EXPECT_EQ(again.S12.translation(), estimate.S12.translation());
}

TEST(Sim3Estimation, UnrelatedPointsGiveNoSimilarity) {
  std::vector<bool> unused;
  std::vector<Sim3Match> matches = LoopMatches(Sim3(), 200, 1.0, 9, &unused);  // all wrong
  Sim3EstimationOptions options;
  options.seed = 3;
  EXPECT_FALSE(EstimateSim3(matches, Camera(), options).found);
  matches.resize(10);  // too few to try
  EXPECT_FALSE(EstimateSim3(matches, Camera(), options).found);
}

// A camera going round a circle: 24 keyframes, odometry edges between neighbours and one
// loop edge from the last back to the first. The initial poses integrate odometry that
// drifts (rotation, translation and scale): the optimization must spread the loop error
// over the whole chain.
TEST(PoseGraph, SpreadsAKnownLoopErrorOverTheLoop) {
  const int count = 24;
  std::vector<Sim3> truth;
  for (int k = 0; k < count; ++k) {
    const double angle = 2 * kPi * k / count;
    const Eigen::Vector3d eye(2 * std::cos(angle), 2 * std::sin(angle), 1.0);
    truth.push_back(Sim3(LookAt(eye, Eigen::Vector3d(0, 0, 0.5))));
  }
  PoseGraphProblem problem;
  problem.poses.push_back(truth[0]);
  const Sim3 drift(1.01, Eigen::Quaterniond(Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitY())),
                   Eigen::Vector3d(0.01, 0.0, 0.0));
  for (int k = 1; k < count; ++k) {
    const Sim3 step =
        truth[static_cast<std::size_t>(k)] * truth[static_cast<std::size_t>(k - 1)].Inverse();
    // S_kw = S_k,k-1 * S_k-1,w, with every step a little off.
    problem.poses.push_back(drift * step * problem.poses.back());
  }
  problem.fixed.assign(count, false);
  problem.fixed[0] = true;
  for (int k = 1; k < count; ++k) {
    // Odometry edges as the drifting map measured them (its current relative poses).
    problem.edges.push_back({k, k - 1,
                             problem.poses[static_cast<std::size_t>(k)] *
                                 problem.poses[static_cast<std::size_t>(k - 1)].Inverse(),
                             1.0});
  }
  // The loop: the true relation of the last keyframe to the first.
  problem.edges.push_back({0, count - 1, truth[0] * truth[count - 1].Inverse(), 1.0});
  const auto centre = [](const Sim3& S_iw) { return S_iw.Inverse().translation(); };
  std::vector<Eigen::Vector3d> initial;
  for (const Sim3& pose : problem.poses) initial.push_back(centre(pose));
  std::vector<double> before;
  for (int k = 0; k < count; ++k)
    before.push_back((centre(problem.poses[static_cast<std::size_t>(k)]) -
                      centre(truth[static_cast<std::size_t>(k)]))
                         .norm());
  const PoseGraphReport report = OptimizePoseGraph(&problem, {});
  ASSERT_TRUE(report.solved) << report.message;
  EXPECT_LT(report.final_cost, 0.01 * report.initial_cost);
  std::vector<double> after;
  for (int k = 0; k < count; ++k)
    after.push_back((centre(problem.poses[static_cast<std::size_t>(k)]) -
                     centre(truth[static_cast<std::size_t>(k)]))
                        .norm());
  // The last keyframe, far off before, is back near its place; no keyframe ends far off.
  EXPECT_GT(before.back(), 0.3);
  EXPECT_LT(after.back(), 0.2 * before.back());
  EXPECT_LT(*std::max_element(after.begin(), after.end()),
            0.35 * *std::max_element(before.begin(), before.end()));
  // Spread: the keyframe half-way round was corrected too, by a good share of the last
  // one's correction, not only those next to the loop edge.
  const auto moved = [&](int k) {
    return (centre(problem.poses[static_cast<std::size_t>(k)]) -
            initial[static_cast<std::size_t>(k)])
        .norm();
  };
  EXPECT_GT(moved(count / 2), 0.2 * moved(count - 1));
  EXPECT_LT(moved(1), moved(count / 2));  // next to the fixed keyframe, little changes
  EXPECT_EQ(problem.poses[0].translation(), truth[0].translation());  // fixed stays
}

TEST(PoseGraph, RejectsEdgesToMissingPoses) {
  PoseGraphProblem problem;
  problem.poses = {Sim3(), Sim3()};
  problem.fixed = {true, false};
  problem.edges.push_back({0, 5, Sim3(), 1.0});
  EXPECT_THROW(OptimizePoseGraph(&problem, {}), std::invalid_argument);
}

}  // namespace
}  // namespace ocg
