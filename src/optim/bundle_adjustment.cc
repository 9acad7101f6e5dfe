#include "ocg/optim/bundle_adjustment.h"

#include <ceres/ceres.h>

#include <cmath>
#include <memory>
#include <stdexcept>

#include "ocg/optim/pose_parameters.h"
#include "ocg/optim/reprojection_cost.h"
#include "solver_options.h"

namespace ocg {
namespace {

double Chi2(const PinholeCamera& camera, const SE3& T_cw, const Eigen::Vector3d& X,
            const Eigen::Vector2d& pixel, double inverse_sigma2, bool* in_front) {
  const Eigen::Vector3d Xc = T_cw * X;
  *in_front = Xc.z() > kMinDepth;
  if (!*in_front) return std::numeric_limits<double>::infinity();
  return (camera.ProjectUndistorted(Xc) - pixel).squaredNorm() * inverse_sigma2;
}

}  // namespace

void BundleAdjustmentOptions::Check() const {
  if (max_iterations < 1) throw std::invalid_argument("bundle adjustment: max_iterations < 1");
  if (huber_threshold <= 0.0 || outlier_chi2 <= 0.0) {
    throw std::invalid_argument("bundle adjustment: thresholds must be positive");
  }
}

void PoseOptimizationOptions::Check() const {
  if (rounds < 1 || iterations_per_round < 1) {
    throw std::invalid_argument("pose optimization: rounds and iterations must be positive");
  }
  if (huber_threshold <= 0.0 || outlier_chi2 <= 0.0) {
    throw std::invalid_argument("pose optimization: thresholds must be positive");
  }
}

BundleAdjustmentReport BundleAdjust(BundleAdjustmentProblem* problem,
                                    const BundleAdjustmentOptions& options) {
  options.Check();
  BundleAdjustmentReport report;
  std::vector<PoseParameters> poses;
  for (const BaKeyframe& keyframe : problem->keyframes)
    poses.push_back(ToParameters(keyframe.T_cw));
  std::vector<std::array<double, 3>> points;
  for (const BaPoint& point : problem->points) {
    points.push_back({point.position.x(), point.position.y(), point.position.z()});
  }
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem ceres_problem(problem_options);
  PoseManifold manifold;
  double initial_sum = 0.0;
  for (const BaObservation& o : problem->observations) {
    bool in_front = false;
    const double chi2 =
        Chi2(problem->camera, problem->keyframes[static_cast<std::size_t>(o.keyframe)].T_cw,
             problem->points[static_cast<std::size_t>(o.point)].position, o.pixel, 1.0, &in_front);
    // A point behind its camera has no usable projection: it would only pull the solve
    // with a meaningless residual. It stays out and is judged an outlier afterwards
    // unless the other observations bring it in front.
    if (!in_front) {
      ++report.behind_camera;
      continue;
    }
    initial_sum += chi2;
    const double sqrt_information = std::sqrt(o.inverse_sigma2);
    auto* cost = new ReprojectionCost(problem->camera, o.pixel, sqrt_information);
    double* pose = poses[static_cast<std::size_t>(o.keyframe)].data();
    double* point = points[static_cast<std::size_t>(o.point)].data();
    ceres_problem.AddResidualBlock(cost, new ceres::HuberLoss(options.huber_threshold), pose,
                                   point);
  }
  bool any_free = false;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    if (!ceres_problem.HasParameterBlock(poses[k].data())) continue;
    ceres_problem.SetManifold(poses[k].data(), &manifold);
    if (problem->keyframes[k].fixed) {
      ceres_problem.SetParameterBlockConstant(poses[k].data());
    } else {
      any_free = true;
    }
  }
  for (std::size_t p = 0; p < points.size(); ++p) {
    if (!ceres_problem.HasParameterBlock(points[p].data())) continue;
    if (problem->points[p].fixed) {
      ceres_problem.SetParameterBlockConstant(points[p].data());
    } else {
      any_free = true;
    }
  }
  const double count = std::max<std::size_t>(1, problem->observations.size());
  report.initial_rms_pixels = std::sqrt(initial_sum / count);
  if (any_free && ceres_problem.NumResidualBlocks() > 0) {
    ceres::Solver::Summary summary;
    ceres::Solve(SolverOptions(options.max_iterations, LinearSolver::kSchur), &ceres_problem,
                 &summary);
    report.solved = summary.IsSolutionUsable();
    report.message = summary.BriefReport();
    report.iterations = static_cast<int>(summary.iterations.size());
    if (report.solved) {
      for (std::size_t k = 0; k < poses.size(); ++k) {
        if (!problem->keyframes[k].fixed)
          problem->keyframes[k].T_cw = FromParameters(poses[k].data());
      }
      for (std::size_t p = 0; p < points.size(); ++p) {
        if (!problem->points[p].fixed) {
          problem->points[p].position = {points[p][0], points[p][1], points[p][2]};
        }
      }
    }
  } else {
    report.solved = true;
    report.message = "nothing to optimize";
  }
  double final_sum = 0.0;
  report.outlier.assign(problem->observations.size(), false);
  for (std::size_t i = 0; i < problem->observations.size(); ++i) {
    const BaObservation& o = problem->observations[i];
    bool in_front = false;
    const SE3& T_cw = problem->keyframes[static_cast<std::size_t>(o.keyframe)].T_cw;
    const Eigen::Vector3d& X = problem->points[static_cast<std::size_t>(o.point)].position;
    const double chi2 = Chi2(problem->camera, T_cw, X, o.pixel, o.inverse_sigma2, &in_front);
    const double pixels2 = Chi2(problem->camera, T_cw, X, o.pixel, 1.0, &in_front);
    if (in_front) final_sum += pixels2;
    if (!in_front || chi2 > options.outlier_chi2) {
      report.outlier[i] = true;
      ++report.outliers;
    }
  }
  report.final_rms_pixels = std::sqrt(final_sum / count);
  return report;
}

PoseOptimizationResult OptimizePose(const PinholeCamera& camera, const SE3& T_cw_initial,
                                    const std::vector<PoseObservation>& observations,
                                    const PoseOptimizationOptions& options) {
  options.Check();
  PoseOptimizationResult result;
  result.T_cw = T_cw_initial;
  result.inlier.assign(observations.size(), true);
  for (std::size_t i = 0; i < observations.size(); ++i) {
    // Behind the initial pose: no usable residual until a round brings it in front.
    result.inlier[i] = (T_cw_initial * observations[i].point_world).z() > kMinDepth;
  }
  PoseManifold manifold;
  for (int round = 0; round < options.rounds; ++round) {
    PoseParameters pose = ToParameters(result.T_cw);
    ceres::Problem::Options problem_options;
    problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(problem_options);
    int used = 0;
    for (std::size_t i = 0; i < observations.size(); ++i) {
      if (!result.inlier[i]) continue;
      const PoseObservation& o = observations[i];
      problem.AddResidualBlock(
          new PoseOnlyReprojectionCost(camera, o.point_world, o.pixel, std::sqrt(o.inverse_sigma2)),
          new ceres::HuberLoss(options.huber_threshold), pose.data());
      ++used;
    }
    if (used < 3) break;  // too few to constrain a pose: keep the last estimate
    problem.SetManifold(pose.data(), &manifold);
    ceres::Solver::Summary summary;
    ceres::Solve(SolverOptions(options.iterations_per_round, LinearSolver::kDense), &problem,
                 &summary);
    if (summary.IsSolutionUsable()) result.T_cw = FromParameters(pose.data());
    // Re-judge every observation, the excluded ones too: a good pose brings some back.
    for (std::size_t i = 0; i < observations.size(); ++i) {
      bool in_front = false;
      const double chi2 = Chi2(camera, result.T_cw, observations[i].point_world,
                               observations[i].pixel, observations[i].inverse_sigma2, &in_front);
      result.inlier[i] = in_front && chi2 <= options.outlier_chi2;
    }
  }
  result.inliers = static_cast<int>(std::count(result.inlier.begin(), result.inlier.end(), true));
  return result;
}

}  // namespace ocg
