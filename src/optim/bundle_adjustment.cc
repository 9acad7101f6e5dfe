#include "ocg/optim/bundle_adjustment.h"

#include <ceres/ceres.h>

#include <array>
#include <cmath>
#include <deque>
#include <memory>
#include <stdexcept>
#include <vector>

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
  if (refine_iterations < 0)
    throw std::invalid_argument("bundle adjustment: refine_iterations < 0");
  if (!(refine_min_chi2_decrease >= 0.0))
    throw std::invalid_argument("bundle adjustment: refine_min_chi2_decrease < 0");
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

namespace {

// The problem's keyframes and points as Ceres parameter blocks.
struct BaParameters {
  std::vector<PoseParameters> poses;
  std::vector<std::array<double, 3>> points;
};

// The problem's own values, as the solver's parameter blocks.
BaParameters ProblemParameters(const BundleAdjustmentProblem& problem) {
  BaParameters parameters;
  for (const BaKeyframe& keyframe : problem.keyframes)
    parameters.poses.push_back(ToParameters(keyframe.T_cw));
  for (const BaPoint& point : problem.points) {
    parameters.points.push_back({point.position.x(), point.position.y(), point.position.z()});
  }
  return parameters;
}

// Ends a solve between iterations: when asked to (BundleAdjustmentOptions::stop), or once
// an accepted step lowered Ceres' cost (half the chi-square) by less than a bound.
class EndOfIteration : public ceres::IterationCallback {
 public:
  EndOfIteration(const std::function<bool(int)>* stop, double min_chi2_decrease)
      : stop_(stop), min_cost_decrease_(0.5 * min_chi2_decrease) {}

  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    if (*stop_ && (*stop_)(summary.iteration)) {
      stopped_ = true;
      return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    }
    if (min_cost_decrease_ > 0.0 && summary.iteration > 0 && summary.step_is_successful &&
        summary.cost_change < min_cost_decrease_) {
      return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    }
    return ceres::SOLVER_CONTINUE;
  }
  bool stopped() const { return stopped_; }

 private:
  const std::function<bool(int)>* stop_;
  double min_cost_decrease_;
  bool stopped_ = false;
};

// One Ceres solve over the observations marked used; loss null: plain squared loss.
// Eliminating the points first is what makes it a Schur problem: the ordering is given,
// not searched for (Ceres' independent-set search costs as much as a small solve).
ceres::Solver::Summary SolveOnce(const BundleAdjustmentProblem& problem,
                                 const std::vector<char>& used, ceres::LossFunction* loss,
                                 int iterations, SchurComplement schur, BaParameters* parameters,
                                 EndOfIteration* end, bool* any_free) {
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem ceres_problem(problem_options);
  PoseManifold manifold;
  for (std::size_t i = 0; i < problem.observations.size(); ++i) {
    if (!used[i]) continue;
    const BaObservation& o = problem.observations[i];
    auto* cost = new ReprojectionCost(problem.camera, o.pixel, std::sqrt(o.inverse_sigma2));
    ceres_problem.AddResidualBlock(cost, loss,
                                   parameters->poses[static_cast<std::size_t>(o.keyframe)].data(),
                                   parameters->points[static_cast<std::size_t>(o.point)].data());
  }
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  int free_keyframes = 0;
  bool free_points = false;
  for (std::size_t k = 0; k < parameters->poses.size(); ++k) {
    double* pose = parameters->poses[k].data();
    if (!ceres_problem.HasParameterBlock(pose)) continue;
    ceres_problem.SetManifold(pose, &manifold);
    if (problem.keyframes[k].fixed) {
      ceres_problem.SetParameterBlockConstant(pose);
    } else {
      ++free_keyframes;
      ordering->AddElementToGroup(pose, 1);
    }
  }
  for (std::size_t p = 0; p < parameters->points.size(); ++p) {
    double* point = parameters->points[p].data();
    if (!ceres_problem.HasParameterBlock(point)) continue;
    if (problem.points[p].fixed) {
      ceres_problem.SetParameterBlockConstant(point);
    } else {
      free_points = true;
      ordering->AddElementToGroup(point, 0);
    }
  }
  ceres::Solver::Summary summary;
  *any_free = free_keyframes > 0 || free_points;
  if (!*any_free || ceres_problem.NumResidualBlocks() == 0) return summary;
  const bool dense = schur == SchurComplement::kDense ||
                     (schur == SchurComplement::kAuto && free_keyframes <= kDenseSchurMaxKeyframes);
  ceres::Solver::Options options =
      SolverOptions(iterations, dense ? LinearSolver::kDenseSchur : LinearSolver::kSparseSchur);
  // Without free points or free keyframes there is nothing to eliminate: Ceres picks.
  if (free_points && free_keyframes > 0) options.linear_solver_ordering = ordering;
  options.callbacks.push_back(end);
  ceres::Solve(options, &ceres_problem, &summary);
  return summary;
}

}  // namespace

BundleAdjustmentReport BundleAdjust(BundleAdjustmentProblem* problem,
                                    const BundleAdjustmentOptions& options) {
  options.Check();
  BundleAdjustmentReport report;
  BaParameters parameters = ProblemParameters(*problem);
  const auto judge = [&](const BaParameters& at, std::size_t i, double* pixels2) {
    const BaObservation& o = problem->observations[i];
    const SE3 T_cw = FromParameters(at.poses[static_cast<std::size_t>(o.keyframe)].data());
    const auto& p = at.points[static_cast<std::size_t>(o.point)];
    bool in_front = false;
    *pixels2 =
        Chi2(problem->camera, T_cw, Eigen::Vector3d(p[0], p[1], p[2]), o.pixel, 1.0, &in_front);
    return in_front && *pixels2 * o.inverse_sigma2 <= options.outlier_chi2;
  };
  std::vector<char> used(problem->observations.size(), 0);
  double initial_sum = 0.0;
  for (std::size_t i = 0; i < problem->observations.size(); ++i) {
    double pixels2 = 0.0;
    judge(parameters, i, &pixels2);
    // A point behind its camera has no usable projection: it would only pull the solve
    // with a meaningless residual. It stays out and is judged an outlier afterwards
    // unless the other observations bring it in front.
    if (!std::isfinite(pixels2)) {
      ++report.behind_camera;
      continue;
    }
    used[i] = 1;
    initial_sum += pixels2;
  }
  const double count = std::max<std::size_t>(1, problem->observations.size());
  report.initial_rms_pixels = std::sqrt(initial_sum / count);
  ceres::HuberLoss huber(options.huber_threshold);
  bool any_free = false;
  EndOfIteration robust_end(&options.stop, 0.0);
  ceres::Solver::Summary summary = SolveOnce(*problem, used, &huber, options.max_iterations,
                                             options.schur, &parameters, &robust_end, &any_free);
  report.stopped = robust_end.stopped();
  if (!any_free || summary.num_residual_blocks == 0) {
    report.solved = true;
    report.message = "nothing to optimize";
  } else {
    report.solved = summary.IsSolutionUsable();
    report.message = summary.BriefReport();
    report.iterations = static_cast<int>(summary.iterations.size());
  }
  if (!report.solved) {
    parameters = ProblemParameters(*problem);  // for judging the outliers
  } else if (options.refine_iterations > 0 && any_free && !report.stopped) {
    BaParameters refined = parameters;
    for (std::size_t i = 0; i < problem->observations.size(); ++i) {
      double pixels2 = 0.0;
      used[i] = judge(parameters, i, &pixels2) ? 1 : 0;
    }
    EndOfIteration refine_end(&options.stop, options.refine_min_chi2_decrease);
    const ceres::Solver::Summary second =
        SolveOnce(*problem, used, nullptr, options.refine_iterations, options.schur, &refined,
                  &refine_end, &any_free);
    report.stopped = refine_end.stopped();
    if (any_free && second.IsSolutionUsable()) {
      parameters = std::move(refined);
      report.message = second.BriefReport();
      report.iterations += static_cast<int>(second.iterations.size());
    }
  }
  if (report.solved) {
    for (std::size_t k = 0; k < parameters.poses.size(); ++k) {
      if (!problem->keyframes[k].fixed)
        problem->keyframes[k].T_cw = FromParameters(parameters.poses[k].data());
    }
    for (std::size_t p = 0; p < parameters.points.size(); ++p) {
      if (!problem->points[p].fixed) {
        const auto& x = parameters.points[p];
        problem->points[p].position = {x[0], x[1], x[2]};
      }
    }
  }
  double final_sum = 0.0;
  // Stopped in the robust solve, the state may still be far from the optimum, where good
  // observations look off: they are judged by a later adjustment instead.
  const bool stopped_unconverged = robust_end.stopped();
  report.outlier.assign(problem->observations.size(), false);
  for (std::size_t i = 0; i < problem->observations.size(); ++i) {
    double pixels2 = 0.0;
    if (!judge(parameters, i, &pixels2) && !stopped_unconverged) {
      report.outlier[i] = true;
      ++report.outliers;
    }
    if (std::isfinite(pixels2)) final_sum += pixels2;
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
  // Tracking runs this twice per frame: the costs and the loss are made once for all
  // rounds (not one heap allocation each per observation and round), and the problem
  // skips Ceres' checks for repeated parameter blocks, which the one pose cannot have.
  std::deque<PoseOnlyReprojectionCost> costs;
  for (const PoseObservation& o : observations)
    costs.emplace_back(camera, o.point_world, o.pixel, std::sqrt(o.inverse_sigma2));
  ceres::HuberLoss huber(options.huber_threshold);
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.disable_all_safety_checks = true;
  for (int round = 0; round < options.rounds; ++round) {
    PoseParameters pose = ToParameters(result.T_cw);
    ceres::Problem problem(problem_options);
    int used = 0;
    for (std::size_t i = 0; i < observations.size(); ++i) {
      if (!result.inlier[i]) continue;
      problem.AddResidualBlock(&costs[i], &huber, pose.data());
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
