#pragma once
// Bundle adjustment of keyframe poses and map points with Ceres (robust Huber loss,
// fixed keyframes and points held constant), and pose-only optimization with rounds of
// outlier rejection. Free functions on plain data: the SLAM map copies what it wants
// optimized in, and the results out, under its own locks.

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "ocg/core/camera.h"
#include "ocg/core/lie.h"

namespace ocg {

// How Ceres solves the reduced camera system (6 x 6 blocks, one per free keyframe, after
// the points are eliminated). kAuto: dense Cholesky up to kDenseSchurMaxKeyframes free
// keyframes (a local adjustment: the dense factorization of a few hundred unknowns costs
// less than the sparse one's symbolic analysis and bookkeeping), sparse above (a global
// adjustment of hundreds of keyframes, each seeing only its neighbours).
enum class SchurComplement { kAuto, kDense, kSparse };
constexpr int kDenseSchurMaxKeyframes = 60;

struct BundleAdjustmentOptions {
  int max_iterations = 50;  // of the solve with the robust (Huber) loss
  // After the robust solve, the observations then judged outliers are left out and the
  // rest solved again with the plain squared loss for this many iterations (0: no second
  // solve), as ORB-SLAM2's local bundle adjustment (5 robust iterations, then 10). Under
  // Huber's loss every gross outlier keeps pulling with a constant force, and inliers
  // beyond the threshold count less than they should: the second solve is the
  // least-squares estimate of the inliers alone.
  int refine_iterations = 0;
  // The second solve also ends after an iteration that lowers the chi-square (the sum of
  // squared information-weighted residuals, twice Ceres' cost) by less than this: the
  // step moved the estimate by less than this many standard deviations squared
  // (Mahalanobis), so further steps change nothing the measurements can tell. 0: only
  // Ceres' own (relative) tolerances and refine_iterations end it.
  double refine_min_chi2_decrease = 0.0;
  // Huber threshold on the (information-weighted) residual norm: sqrt(5.991), the
  // 95 % chi-square bound of a 2-D residual with unit variance.
  double huber_threshold = 2.447;
  double outlier_chi2 = 5.991;  // after optimizing: observations above it are outliers
  SchurComplement schur = SchurComplement::kAuto;
  // Asked after every iteration of either solve with the solve's iteration count (0: the
  // start): true ends the adjustment there, keeping the state reached (the solver only
  // accepts steps that lower the cost, so it is no worse than the start), and skips the
  // second solve if the first was stopped (no observation is then judged an outlier: the
  // state may be short of the optimum). Called on the solving thread; empty: never.
  // Local mapping stops its adjustment this way when a new keyframe arrives.
  std::function<bool(int iteration)> stop;
  void Check() const;
};

struct BaKeyframe {
  SE3 T_cw;
  bool fixed = false;
};

struct BaPoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  bool fixed = false;
};

struct BaObservation {
  int keyframe = 0;
  int point = 0;
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  // undistorted
  double inverse_sigma2 = 1.0;                      // 1 / scale^2 of the keypoint's level
};

struct BundleAdjustmentProblem {
  PinholeCamera camera;
  std::vector<BaKeyframe> keyframes;
  std::vector<BaPoint> points;
  std::vector<BaObservation> observations;
};

struct BundleAdjustmentReport {
  bool solved = false;
  std::string message;              // Ceres' summary line (of the last solve)
  int iterations = 0;               // of both solves, each counting its start as one
  bool stopped = false;             // options.stop ended it
  double initial_rms_pixels = 0.0;  // of the residuals before and after, outliers included
  double final_rms_pixels = 0.0;
  std::vector<bool> outlier;  // per observation, judged after the (last) optimization
  int outliers = 0;
  int behind_camera = 0;  // observations left out of the solve: point behind its camera
};

// Optimizes the free keyframes and points of problem in place. Single-threaded, so a run
// is reproducible. A problem without free parameters returns at once. solved is false
// when the robust solve gave no usable solution (problem unchanged); a failed second
// solve keeps the robust one's.
BundleAdjustmentReport BundleAdjust(BundleAdjustmentProblem* problem,
                                    const BundleAdjustmentOptions& options);

struct PoseObservation {
  Eigen::Vector3d point_world = Eigen::Vector3d::Zero();
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  double inverse_sigma2 = 1.0;
};

struct PoseOptimizationOptions {
  int rounds = 4;  // optimize, then reclassify outliers, this many times
  int iterations_per_round = 10;
  double outlier_chi2 = 5.991;     // 2-D residual, 95 %
  double huber_threshold = 2.447;  // sqrt(outlier_chi2)
  void Check() const;
};

struct PoseOptimizationResult {
  SE3 T_cw;
  std::vector<bool> inlier;
  int inliers = 0;
};

// Camera pose from 3-D to 2-D correspondences, starting at T_cw_initial: each round
// optimizes with the current inliers and then re-judges every observation (ORB-SLAM2's
// pose optimization).
PoseOptimizationResult OptimizePose(const PinholeCamera& camera, const SE3& T_cw_initial,
                                    const std::vector<PoseObservation>& observations,
                                    const PoseOptimizationOptions& options);

}  // namespace ocg
