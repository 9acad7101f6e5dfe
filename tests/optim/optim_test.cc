#include <ceres/autodiff_cost_function.h>
#include <ceres/rotation.h>
#include <glog/logging.h>
#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <Eigen/Geometry>
#include <random>
#include <sstream>

#include "ocg/core/alignment.h"
#include "ocg/optim/bundle_adjustment.h"
#include "ocg/optim/pose_parameters.h"
#include "ocg/optim/reprojection_cost.h"
#include "ocg/optim/solver_logging.h"

namespace ocg {
namespace {

// The same residual as ReprojectionCost, written for automatic differentiation with
// respect to the tangent (rho, phi) at a fixed pose, and the point.
struct AutodiffReprojection {
  AutodiffReprojection(const PinholeCamera& camera, const SE3& T_cw, const Eigen::Vector2d& pixel,
                       double weight)
      : camera(camera), R(T_cw.rotation()), t(T_cw.translation()), pixel(pixel), weight(weight) {}

  template <typename T>
  bool operator()(const T* delta, const T* point, T* residual) const {
    T rotated[3];
    for (int r = 0; r < 3; ++r) {
      rotated[r] = T(R(r, 0)) * point[0] + T(R(r, 1)) * point[1] + T(R(r, 2)) * point[2];
    }
    T turned[3];
    ceres::AngleAxisRotatePoint(delta + 3, rotated, turned);
    T Xc[3];
    for (int r = 0; r < 3; ++r) Xc[r] = turned[r] + T(t[r]) + delta[r];
    residual[0] = T(weight) * (T(camera.fx) * Xc[0] / Xc[2] + T(camera.cx) - T(pixel.x()));
    residual[1] = T(weight) * (T(camera.fy) * Xc[1] / Xc[2] + T(camera.cy) - T(pixel.y()));
    return true;
  }

  PinholeCamera camera;
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  Eigen::Vector2d pixel;
  double weight;
};

SE3 RandomPose(std::mt19937_64& rng, double angle, double distance) {
  std::normal_distribution<double> normal(0.0, 1.0);
  const Eigen::Vector3d axis = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
  const Eigen::Vector3d t = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
  return SE3(Eigen::AngleAxisd(angle, axis).toRotationMatrix(), distance * t);
}

TEST(ReprojectionCost, JacobiansMatchAutomaticDifferentiation) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  PinholeCamera camera;
  camera.fx = 517.3;
  camera.fy = 516.5;
  for (int trial = 0; trial < 50; ++trial) {
    const SE3 T_cw = RandomPose(rng, 0.5 * unit(rng), 0.5);
    const Eigen::Vector3d X =
        T_cw.Inverse() * Eigen::Vector3d(unit(rng), unit(rng), 3.0 + unit(rng));
    const Eigen::Vector2d pixel(300 + 50 * unit(rng), 200 + 50 * unit(rng));
    const double weight = 1.0 / (1.0 + trial % 3);
    // Hand-written.
    const ReprojectionCost cost(camera, pixel, weight);
    const PoseParameters pose = ToParameters(T_cw);
    const double* parameters[2] = {pose.data(), X.data()};
    double residual[2];
    double pose_jacobian[2 * 7];
    double point_jacobian[2 * 3];
    double* jacobians[2] = {pose_jacobian, point_jacobian};
    ASSERT_TRUE(cost.Evaluate(parameters, residual, jacobians));
    // Automatic.
    ceres::AutoDiffCostFunction<AutodiffReprojection, 2, 6, 3> automatic(
        new AutodiffReprojection(camera, T_cw, pixel, weight));
    const double zero[6] = {0, 0, 0, 0, 0, 0};
    const double* auto_parameters[2] = {zero, X.data()};
    double auto_residual[2];
    double auto_pose[2 * 6];
    double auto_point[2 * 3];
    double* auto_jacobians[2] = {auto_pose, auto_point};
    ASSERT_TRUE(automatic.Evaluate(auto_parameters, auto_residual, auto_jacobians));
    for (int r = 0; r < 2; ++r) {
      EXPECT_NEAR(residual[r], auto_residual[r], 1e-9);
      for (int c = 0; c < 6; ++c) EXPECT_NEAR(pose_jacobian[r * 7 + c], auto_pose[r * 6 + c], 1e-6);
      EXPECT_EQ(pose_jacobian[r * 7 + 6], 0.0);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(point_jacobian[r * 3 + c], auto_point[r * 3 + c], 1e-6);
    }
    // The pose-only cost agrees with the full one.
    const PoseOnlyReprojectionCost pose_only(camera, X, pixel, weight);
    const double* pose_parameters[1] = {pose.data()};
    double pose_only_residual[2];
    double pose_only_jacobian[2 * 7];
    double* pose_only_jacobians[1] = {pose_only_jacobian};
    ASSERT_TRUE(pose_only.Evaluate(pose_parameters, pose_only_residual, pose_only_jacobians));
    for (int i = 0; i < 14; ++i) EXPECT_EQ(pose_only_jacobian[i], pose_jacobian[i]);
  }
}

TEST(PoseManifold, PlusTurnsOnTheLeftAndMinusUndoesIt) {
  std::mt19937_64 rng(2);
  const SE3 T = RandomPose(rng, 0.7, 1.0);
  const PoseParameters x = ToParameters(T);
  const double delta[6] = {0.1, -0.2, 0.05, 0.02, -0.01, 0.03};
  PoseParameters y;
  PoseManifold manifold;
  ASSERT_TRUE(manifold.Plus(x.data(), delta, y.data()));
  const SE3 moved = FromParameters(y.data());
  const Eigen::Matrix3d expected = ExpSO3(Eigen::Vector3d(0.02, -0.01, 0.03)) * T.rotation();
  EXPECT_LT((moved.rotation() - expected).norm(), 1e-12);
  EXPECT_LT((moved.translation() - T.translation() - Eigen::Vector3d(0.1, -0.2, 0.05)).norm(),
            1e-12);
  double back[6];
  ASSERT_TRUE(manifold.Minus(y.data(), x.data(), back));
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(back[i], delta[i], 1e-12);
}

// Five keyframes along a short path looking at 300 points; noisy observations.
BundleAdjustmentProblem MakeScene(std::mt19937_64& rng, std::vector<SE3>* true_poses,
                                  std::vector<Eigen::Vector3d>* true_points) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.5);
  BundleAdjustmentProblem problem;
  for (int k = 0; k < 5; ++k) {
    const SE3 T_wc(Eigen::AngleAxisd(0.05 * k, Eigen::Vector3d::UnitY()).toRotationMatrix(),
                   Eigen::Vector3d(0.15 * k, 0.02 * k, 0.0));
    true_poses->push_back(T_wc.Inverse());
  }
  for (int p = 0; p < 300; ++p) {
    true_points->emplace_back(2.0 * unit(rng), 1.5 * unit(rng), 4.0 + 1.5 * unit(rng));
  }
  for (std::size_t k = 0; k < true_poses->size(); ++k) {
    problem.keyframes.push_back({(*true_poses)[k], k == 0});
  }
  for (std::size_t p = 0; p < true_points->size(); ++p) {
    problem.points.push_back({(*true_points)[p], false});
    for (std::size_t k = 0; k < true_poses->size(); ++k) {
      const Eigen::Vector3d Xc = (*true_poses)[k] * (*true_points)[p];
      const Eigen::Vector2d pixel = problem.camera.ProjectUndistorted(Xc);
      if (!problem.camera.IsInImage(pixel)) continue;
      problem.observations.push_back({static_cast<int>(k), static_cast<int>(p),
                                      pixel + Eigen::Vector2d(noise(rng), noise(rng)), 1.0});
    }
  }
  return problem;
}

TEST(BundleAdjustment, LowersReprojectionErrorAndRecoversStructureUpToScale) {
  std::mt19937_64 rng(3);
  std::vector<SE3> true_poses;
  std::vector<Eigen::Vector3d> true_points;
  BundleAdjustmentProblem problem = MakeScene(rng, &true_poses, &true_points);
  // Perturb every free pose and every point.
  std::normal_distribution<double> normal(0.0, 1.0);
  for (std::size_t k = 1; k < problem.keyframes.size(); ++k) {
    problem.keyframes[k].T_cw = RandomPose(rng, 0.02, 0.05) * problem.keyframes[k].T_cw;
  }
  for (BaPoint& point : problem.points) {
    point.position += 0.1 * Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
  }
  // A few gross outliers.
  for (std::size_t i = 0; i < problem.observations.size(); i += 97) {
    problem.observations[i].pixel += Eigen::Vector2d(40.0, -30.0);
  }
  const BundleAdjustmentReport report = BundleAdjust(&problem, BundleAdjustmentOptions());
  ASSERT_TRUE(report.solved) << report.message;
  EXPECT_LT(report.final_rms_pixels, 0.25 * report.initial_rms_pixels);
  // Every planted outlier is flagged, and few others are.
  int planted = 0;
  for (std::size_t i = 0; i < problem.observations.size(); i += 97) {
    EXPECT_TRUE(report.outlier[i]) << i;
    ++planted;
  }
  EXPECT_LE(report.outliers, planted + static_cast<int>(problem.observations.size() / 50));
  // Structure: equal to the truth after a similarity (monocular scale is free).
  // Points seen from at least three keyframes are well constrained.
  std::vector<int> views(problem.points.size(), 0);
  for (std::size_t i = 0; i < problem.observations.size(); ++i) {
    if (!report.outlier[i]) ++views[static_cast<std::size_t>(problem.observations[i].point)];
  }
  std::vector<Eigen::Vector3d> estimated, truth;
  for (std::size_t p = 0; p < problem.points.size(); ++p) {
    if (views[p] < 3) continue;
    estimated.push_back(problem.points[p].position);
    truth.push_back(true_points[p]);
  }
  ASSERT_GE(estimated.size(), 200u);
  const Sim3 alignment = AlignPoints(estimated, truth, true).target_from_source;
  std::vector<double> errors;
  for (std::size_t p = 0; p < estimated.size(); ++p) {
    errors.push_back((alignment * estimated[p] - truth[p]).norm());
  }
  std::sort(errors.begin(), errors.end());
  // Depth noise for 0.5 px at 4 m over baselines of 0.15-0.6 m is a few centimetres.
  EXPECT_LT(errors[errors.size() / 2], 0.04);  // metres, for points 2.5-5.5 m away
  EXPECT_LT(errors[errors.size() * 95 / 100], 0.15);
  // The fixed keyframe did not move.
  EXPECT_EQ(problem.keyframes[0].T_cw.Matrix(), true_poses[0].Matrix());
}

TEST(BundleAdjustment, IsReproducible) {
  std::mt19937_64 rng_a(4), rng_b(4);
  std::vector<SE3> poses_a, poses_b;
  std::vector<Eigen::Vector3d> points_a, points_b;
  BundleAdjustmentProblem a = MakeScene(rng_a, &poses_a, &points_a);
  BundleAdjustmentProblem b = MakeScene(rng_b, &poses_b, &points_b);
  for (auto* problem : {&a, &b}) {
    problem->keyframes[2].T_cw = SE3(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.1, 0, 0)) *
                                 problem->keyframes[2].T_cw;
  }
  BundleAdjust(&a, BundleAdjustmentOptions());
  BundleAdjust(&b, BundleAdjustmentOptions());
  for (std::size_t k = 0; k < a.keyframes.size(); ++k) {
    EXPECT_EQ(a.keyframes[k].T_cw.Matrix(), b.keyframes[k].T_cw.Matrix());
  }
}

// ORB-SLAM2's local adjustment: a few robust iterations, then the observations judged
// outliers are left out and the rest solved with the squared loss. The second solve must
// find every gross outlier and land on the least-squares estimate of the inliers alone,
// where the robust iterations by themselves are not yet.
TEST(BundleAdjustment, SecondSolveWithoutOutliersIsTheInliersLeastSquaresEstimate) {
  std::mt19937_64 rng(8);
  std::vector<SE3> true_poses;
  std::vector<Eigen::Vector3d> true_points;
  BundleAdjustmentProblem start = MakeScene(rng, &true_poses, &true_points);
  start.keyframes[1].fixed = true;  // with keyframe 0, fixes the scale: one optimum to compare
  std::vector<bool> planted(start.observations.size(), false);
  // A tenth of the last keyframe's observations, where their points are seen by all five
  // keyframes (the other four hold the points, so the outliers pull on that pose).
  std::vector<int> views(start.points.size(), 0);
  for (const BaObservation& o : start.observations) ++views[static_cast<std::size_t>(o.point)];
  int last_keyframe_observations = 0;
  for (std::size_t i = 0; i < start.observations.size(); ++i) {
    const BaObservation& o = start.observations[i];
    if (o.keyframe != 4 || views[static_cast<std::size_t>(o.point)] < 5) continue;
    if (last_keyframe_observations++ % 10 != 0) continue;
    start.observations[i].pixel += Eigen::Vector2d(12.0, 9.0);
    planted[i] = true;
  }
  for (std::size_t k = 2; k < start.keyframes.size(); ++k) {
    start.keyframes[k].T_cw = RandomPose(rng, 0.01, 0.02) * start.keyframes[k].T_cw;
  }
  // Reference: the squared loss (a Huber threshold no residual reaches) on the inliers.
  BundleAdjustmentProblem reference = start;
  reference.observations.clear();
  for (std::size_t i = 0; i < start.observations.size(); ++i) {
    if (!planted[i]) reference.observations.push_back(start.observations[i]);
  }
  BundleAdjustmentOptions least_squares;
  least_squares.huber_threshold = 1e6;
  least_squares.max_iterations = 100;
  ASSERT_TRUE(BundleAdjust(&reference, least_squares).solved);

  BundleAdjustmentProblem robust = start;
  BundleAdjustmentOptions robust_only;
  robust_only.max_iterations = 5;  // the first solve alone
  ASSERT_TRUE(BundleAdjust(&robust, robust_only).solved);
  BundleAdjustmentProblem refined = start;
  BundleAdjustmentOptions two_solves;
  two_solves.max_iterations = 5;
  two_solves.refine_iterations = 10;
  const BundleAdjustmentReport report = BundleAdjust(&refined, two_solves);
  ASSERT_TRUE(report.solved) << report.message;

  const auto largest_offset = [&](const BundleAdjustmentProblem& problem) {
    double offset = 0.0;
    for (std::size_t k = 0; k < problem.keyframes.size(); ++k) {
      offset = std::max(offset, (problem.keyframes[k].T_cw.Inverse().translation() -
                                 reference.keyframes[k].T_cw.Inverse().translation())
                                    .norm());
    }
    return offset;  // metres, cameras 0.15-0.6 m apart
  };
  // Ceres stops at a relative cost change of 1e-6: a few hundredths of a millimetre here.
  EXPECT_LT(largest_offset(refined), 2e-4);
  EXPECT_GT(largest_offset(robust), 10.0 * largest_offset(refined));
  for (std::size_t i = 0; i < planted.size(); ++i) EXPECT_EQ(report.outlier[i], planted[i]) << i;
}

// A perturbed MakeScene without outliers: every free pose and point moved.
BundleAdjustmentProblem PerturbedScene(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<SE3> true_poses;
  std::vector<Eigen::Vector3d> true_points;
  BundleAdjustmentProblem problem = MakeScene(rng, &true_poses, &true_points);
  problem.keyframes[1].fixed = true;  // with keyframe 0, fixes the scale
  std::normal_distribution<double> normal(0.0, 1.0);
  for (std::size_t k = 2; k < problem.keyframes.size(); ++k) {
    problem.keyframes[k].T_cw = RandomPose(rng, 0.02, 0.05) * problem.keyframes[k].T_cw;
  }
  for (BaPoint& point : problem.points) {
    point.position += 0.1 * Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
  }
  return problem;
}

// Local mapping stops its adjustment when a keyframe arrives: the solve must end right
// after the iteration during which it was asked to, skip the second solve, and write back
// the state it had reached, which is no worse than the start.
TEST(BundleAdjustment, AStopRequestEndsTheSolveAfterTheCurrentIterationKeepingItsProgress) {
  const BundleAdjustmentProblem start = PerturbedScene(11);
  BundleAdjustmentOptions options;
  options.max_iterations = 5;
  options.refine_iterations = 10;
  std::vector<int> asked;
  options.stop = [&](int iteration) {
    asked.push_back(iteration);
    return iteration >= 1;  // requested during the first iteration
  };
  BundleAdjustmentProblem stopped = start;
  const BundleAdjustmentReport report = BundleAdjust(&stopped, options);
  ASSERT_TRUE(report.solved) << report.message;
  EXPECT_TRUE(report.stopped);
  EXPECT_EQ(report.iterations, 2);  // the start and one iteration
  EXPECT_EQ(asked, (std::vector<int>{0, 1})) << "the solve went on, or the second solve ran";
  EXPECT_EQ(report.outliers, 0) << "judged on a state short of the optimum";
  // The state of that one iteration was written back: lower error than the start, moved.
  EXPECT_LT(report.final_rms_pixels, report.initial_rms_pixels);
  EXPECT_GT(
      (stopped.keyframes[4].T_cw.translation() - start.keyframes[4].T_cw.translation()).norm(),
      1e-4);
  // An unstopped solve goes further.
  BundleAdjustmentProblem full = start;
  options.stop = nullptr;
  const BundleAdjustmentReport full_report = BundleAdjust(&full, options);
  EXPECT_FALSE(full_report.stopped);
  EXPECT_GT(full_report.iterations, 4);
  EXPECT_LT(full_report.final_rms_pixels, report.final_rms_pixels);

  // Asked before the first iteration: nothing changes.
  BundleAdjustmentProblem at_once = start;
  options.stop = [](int) { return true; };
  const BundleAdjustmentReport at_once_report = BundleAdjust(&at_once, options);
  EXPECT_TRUE(at_once_report.solved);
  EXPECT_TRUE(at_once_report.stopped);
  for (std::size_t k = 0; k < start.keyframes.size(); ++k) {  // to the parameters' rounding
    EXPECT_TRUE(
        at_once.keyframes[k].T_cw.Matrix().isApprox(start.keyframes[k].T_cw.Matrix(), 1e-12))
        << k;
  }
  for (std::size_t p = 0; p < start.points.size(); ++p)
    EXPECT_EQ(at_once.points[p].position, start.points[p].position) << p;
}

// The refining solve may end once an iteration lowers the chi-square by less than one
// (a step smaller than one standard deviation of the estimate): fewer iterations, and the
// poses within a small fraction of their uncertainty of the fully converged solve.
TEST(BundleAdjustment, RefineToleranceEndsTheSecondSolveWithoutMovingTheEstimate) {
  BundleAdjustmentProblem start = PerturbedScene(12);
  // Gross outliers, which the robust solve only down-weights: the second one has work.
  for (std::size_t i = 0; i < start.observations.size(); i += 23)
    start.observations[i].pixel += Eigen::Vector2d(12.0, 9.0);
  BundleAdjustmentOptions converged;
  converged.max_iterations = 5;
  converged.refine_iterations = 50;  // Ceres' relative tolerance (1e-6) ends it
  BundleAdjustmentProblem reference = start;
  const BundleAdjustmentReport reference_report = BundleAdjust(&reference, converged);
  ASSERT_TRUE(reference_report.solved);
  BundleAdjustmentOptions tolerant = converged;
  tolerant.refine_min_chi2_decrease = 1.0;
  BundleAdjustmentProblem ended = start;
  const BundleAdjustmentReport report = BundleAdjust(&ended, tolerant);
  ASSERT_TRUE(report.solved);
  EXPECT_LT(report.iterations, reference_report.iterations);
  // Noise 0.5 px at 4 m over 0.15-0.6 m baselines: the cameras are known to millimetres.
  for (std::size_t k = 0; k < start.keyframes.size(); ++k) {
    EXPECT_LT((ended.keyframes[k].T_cw.Inverse().translation() -
               reference.keyframes[k].T_cw.Inverse().translation())
                  .norm(),
              1e-4)
        << k;
  }
  EXPECT_NEAR(report.final_rms_pixels, reference_report.final_rms_pixels, 1e-3);
}

// The dense Schur complement (local adjustments) is a faster way to the same solution.
TEST(BundleAdjustment, DenseAndSparseSchurComplementsAgree) {
  std::mt19937_64 rng(9);
  std::vector<SE3> true_poses;
  std::vector<Eigen::Vector3d> true_points;
  BundleAdjustmentProblem dense = MakeScene(rng, &true_poses, &true_points);
  for (std::size_t k = 1; k < dense.keyframes.size(); ++k) {
    dense.keyframes[k].T_cw = RandomPose(rng, 0.01, 0.02) * dense.keyframes[k].T_cw;
  }
  BundleAdjustmentProblem sparse = dense;
  BundleAdjustmentOptions options;
  options.schur = SchurComplement::kDense;
  ASSERT_TRUE(BundleAdjust(&dense, options).solved);
  options.schur = SchurComplement::kSparse;
  ASSERT_TRUE(BundleAdjust(&sparse, options).solved);
  for (std::size_t k = 0; k < dense.keyframes.size(); ++k) {
    EXPECT_LT(
        (dense.keyframes[k].T_cw.translation() - sparse.keyframes[k].T_cw.translation()).norm(),
        1e-9);
  }
  for (std::size_t p = 0; p < dense.points.size(); ++p) {
    EXPECT_LT((dense.points[p].position - sparse.points[p].position).norm(), 1e-9);
  }
}

TEST(ReprojectionCost, StaysFiniteAtAndBehindTheCamera) {
  const PinholeCamera camera;
  const PoseParameters pose = ToParameters(SE3());
  for (const double depth : {0.0, 1e-9, -2.0}) {
    const double point[3] = {0.3, -0.2, depth};
    const double* parameters[2] = {pose.data(), point};
    double residuals[2], pose_jacobian[14], point_jacobian[6];
    double* jacobians[2] = {pose_jacobian, point_jacobian};
    const ReprojectionCost cost(camera, Eigen::Vector2d(320.0, 240.0), 1.0);
    ASSERT_TRUE(cost.Evaluate(parameters, residuals, jacobians)) << "depth " << depth;
    for (const double r : residuals) EXPECT_TRUE(std::isfinite(r)) << "depth " << depth;
    for (const double j : pose_jacobian) EXPECT_TRUE(std::isfinite(j)) << "depth " << depth;
    for (const double j : point_jacobian) EXPECT_TRUE(std::isfinite(j)) << "depth " << depth;
    const PoseOnlyReprojectionCost pose_only(camera, Eigen::Vector3d(0.3, -0.2, depth),
                                             Eigen::Vector2d(320.0, 240.0), 1.0);
    const double* pose_parameters[1] = {pose.data()};
    ASSERT_TRUE(pose_only.Evaluate(pose_parameters, residuals, nullptr)) << "depth " << depth;
    for (const double r : residuals) EXPECT_TRUE(std::isfinite(r)) << "depth " << depth;
  }
}

// A map point that drifted behind the keyframes observing it (a wrong match, or
// a keyframe moved by an earlier adjustment) must not stop the adjustment of the rest:
// it used to fail the whole solve at Ceres' first evaluation.
TEST(BundleAdjustment, SolvesWithAPointBehindItsCameras) {
  std::mt19937_64 rng(6);
  std::vector<SE3> true_poses;
  std::vector<Eigen::Vector3d> true_points;
  BundleAdjustmentProblem problem = MakeScene(rng, &true_poses, &true_points);
  problem.keyframes[2].T_cw =
      SE3(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.05, 0, 0)) * problem.keyframes[2].T_cw;
  const int behind = problem.observations[0].point;
  problem.points[static_cast<std::size_t>(behind)].position.z() = -3.0;
  const BundleAdjustmentReport report = BundleAdjust(&problem, BundleAdjustmentOptions());
  ASSERT_TRUE(report.solved) << report.message;
  EXPECT_GT(report.behind_camera, 0);
  EXPECT_TRUE(report.outlier[0]);
  // The perturbed keyframe went back to where it was.
  EXPECT_LT((problem.keyframes[2].T_cw.translation() - true_poses[2].translation()).norm(), 0.01);
}

TEST(SolverLogging, GlogReachesOurLoggerAndNotStderr) {
  std::ostringstream captured;
  const auto previous = spdlog::default_logger();
  auto logger = std::make_shared<spdlog::logger>(
      "capture", std::make_shared<spdlog::sinks::ostream_sink_mt>(captured));
  spdlog::set_default_logger(logger);
  RouteSolverLogging();
  ::testing::internal::CaptureStderr();
  LOG(WARNING) << "probe from glog 4711";
  const std::string on_stderr = ::testing::internal::GetCapturedStderr();
  spdlog::set_default_logger(previous);
  EXPECT_EQ(on_stderr, "");
  EXPECT_NE(captured.str().find("probe from glog 4711"), std::string::npos) << captured.str();
  EXPECT_NE(captured.str().find("warning"), std::string::npos) << captured.str();
}

TEST(PoseOptimization, RecoversAPerturbedPoseAndFlagsOutliers) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.5);
  const PinholeCamera camera;
  const SE3 truth = RandomPose(rng, 0.3, 0.5);
  std::vector<PoseObservation> observations;
  std::vector<bool> planted;
  while (observations.size() < 200) {
    const Eigen::Vector3d Xc(2.0 * unit(rng), 1.5 * unit(rng), 3.0 + unit(rng));
    const Eigen::Vector2d pixel = camera.ProjectUndistorted(Xc);
    if (!camera.IsInImage(pixel)) continue;
    const bool outlier = observations.size() % 5 == 0;  // 20 %
    PoseObservation o;
    o.point_world = truth.Inverse() * Xc;
    o.pixel = pixel + (outlier ? Eigen::Vector2d(25.0 * unit(rng) + 30.0, 25.0 * unit(rng))
                               : Eigen::Vector2d(noise(rng), noise(rng)));
    observations.push_back(o);
    planted.push_back(outlier);
  }
  const SE3 start = RandomPose(rng, 0.05, 0.1) * truth;  // about 3 degrees and 10 cm off
  const PoseOptimizationResult result =
      OptimizePose(camera, start, observations, PoseOptimizationOptions());
  EXPECT_LT((result.T_cw.translation() - truth.translation()).norm(), 0.01);
  EXPECT_LT(LogSO3(result.T_cw.rotation() * truth.rotation().transpose()).norm() * 180.0 / M_PI,
            0.1);
  int caught = 0, wrongly = 0;
  for (std::size_t i = 0; i < planted.size(); ++i) {
    if (planted[i] && !result.inlier[i]) ++caught;
    if (!planted[i] && !result.inlier[i]) ++wrongly;
  }
  EXPECT_EQ(caught, 40);
  EXPECT_LE(wrongly, 8);  // 5 % of the good ones may exceed the 95 % bound
}

}  // namespace
}  // namespace ocg
