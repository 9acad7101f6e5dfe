#include "ocg/optim/pose_graph.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <cmath>
#include <stdexcept>

#include "sim3_parameters.h"
#include "solver_options.h"

namespace ocg {
namespace {

struct Sim3EdgeCost {
  Sim3EdgeCost(const Sim3& measured, double weight)
      : measured_(measured), sqrt_weight_(std::sqrt(weight)) {}

  template <typename T>
  bool operator()(const T* pose_i, const T* pose_j, T* residuals) const {
    const Sim3Of<T> S_iw = Sim3Of<T>::FromParameters(pose_i);
    const Sim3Of<T> S_jw = Sim3Of<T>::FromParameters(pose_j);
    const Sim3Of<T> error = Sim3Of<T>::FromSim3(measured_) * S_jw * S_iw.Inverse();
    ceres::RotationMatrixToAngleAxis(error.R.data(), residuals);
    for (int k = 0; k < 3; ++k) {
      residuals[k] *= T(sqrt_weight_);
      residuals[3 + k] = error.t[k] * T(sqrt_weight_);
    }
    residuals[6] = log(error.s) * T(sqrt_weight_);
    return true;
  }

  Sim3 measured_;
  double sqrt_weight_;
};

}  // namespace

PoseGraphReport OptimizePoseGraph(PoseGraphProblem* problem, const PoseGraphOptions& options) {
  PoseGraphReport report;
  const int count = static_cast<int>(problem->poses.size());
  if (problem->fixed.size() != problem->poses.size()) {
    throw std::invalid_argument("pose graph: " + std::to_string(problem->fixed.size()) +
                                " fixed flags for " + std::to_string(count) + " poses");
  }
  std::vector<Sim3Parameters> parameters;
  parameters.reserve(problem->poses.size());
  for (const Sim3& pose : problem->poses) parameters.push_back(ToParameters(pose));
  ceres::Problem ceres_problem;
  for (const PoseGraphEdge& edge : problem->edges) {
    if (edge.i < 0 || edge.j < 0 || edge.i >= count || edge.j >= count || edge.i == edge.j) {
      throw std::invalid_argument("pose graph: edge (" + std::to_string(edge.i) + ", " +
                                  std::to_string(edge.j) + ") with " + std::to_string(count) +
                                  " poses");
    }
    ceres_problem.AddResidualBlock(new ceres::AutoDiffCostFunction<Sim3EdgeCost, 7, 7, 7>(
                                       new Sim3EdgeCost(edge.S_ij, edge.weight)),
                                   nullptr, parameters[static_cast<std::size_t>(edge.i)].data(),
                                   parameters[static_cast<std::size_t>(edge.j)].data());
  }
  bool any_free = false;
  for (int k = 0; k < count; ++k) {
    double* block = parameters[static_cast<std::size_t>(k)].data();
    if (!ceres_problem.HasParameterBlock(block)) continue;
    if (problem->fixed[static_cast<std::size_t>(k)]) {
      ceres_problem.SetParameterBlockConstant(block);
    } else {
      any_free = true;
    }
  }
  if (!any_free) {
    report.solved = true;
    report.message = "nothing to optimize";
    return report;
  }
  ceres::Solver::Summary summary;
  ceres::Solve(SolverOptions(options.max_iterations, LinearSolver::kSparse), &ceres_problem,
               &summary);
  report.solved = summary.IsSolutionUsable();
  report.message = summary.BriefReport();
  report.iterations = static_cast<int>(summary.iterations.size());
  report.initial_cost = summary.initial_cost;
  report.final_cost = summary.final_cost;
  for (int k = 0; k < count; ++k) {
    if (!problem->fixed[static_cast<std::size_t>(k)])
      problem->poses[static_cast<std::size_t>(k)] =
          FromParameters(parameters[static_cast<std::size_t>(k)]);
  }
  return report;
}

}  // namespace ocg
