#include "ocg/optim/sim3_estimation.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <random>

#include "ocg/core/alignment.h"
#include "ocg/core/options.h"
#include "sim3_parameters.h"
#include "solver_options.h"

namespace ocg {
namespace {

// Reprojection errors of a match under S12, in both images (squared, in sigmas).
struct MatchErrors {
  double chi2_1 = 0.0, chi2_2 = 0.0;
  bool in_front = false;
};

MatchErrors Errors(const Sim3Match& match, const PinholeCamera& camera, const Sim3& S12,
                   const Sim3& S21) {
  MatchErrors errors;
  const Eigen::Vector3d in_1 = S12 * match.point2;
  const Eigen::Vector3d in_2 = S21 * match.point1;
  errors.in_front = in_1.z() > 0 && in_2.z() > 0;
  if (!errors.in_front) return errors;
  errors.chi2_1 = (camera.ProjectUndistorted(in_1) - match.pixel1).squaredNorm() / match.sigma2_1;
  errors.chi2_2 = (camera.ProjectUndistorted(in_2) - match.pixel2).squaredNorm() / match.sigma2_2;
  return errors;
}

int JudgeInliers(const std::vector<Sim3Match>& matches, const PinholeCamera& camera,
                 const Sim3& S12, double chi2, std::vector<bool>* inliers) {
  const Sim3 S21 = S12.Inverse();
  inliers->assign(matches.size(), false);
  int count = 0;
  for (std::size_t i = 0; i < matches.size(); ++i) {
    const MatchErrors errors = Errors(matches[i], camera, S12, S21);
    (*inliers)[i] = errors.in_front && errors.chi2_1 < chi2 && errors.chi2_2 < chi2;
    count += (*inliers)[i] ? 1 : 0;
  }
  return count;
}

// Both reprojections of one match as a function of S12's seven parameters.
struct Sim3ReprojectionCost {
  Sim3ReprojectionCost(const Sim3Match& match, const PinholeCamera& camera)
      : match_(match), camera_(camera) {}

  template <typename T>
  bool operator()(const T* parameters, T* residuals) const {
    const Sim3Of<T> S12 = Sim3Of<T>::FromParameters(parameters);
    const Eigen::Matrix<T, 3, 1> in_1 = S12 * match_.point2.cast<T>();
    const Eigen::Matrix<T, 3, 1> in_2 = S12.Inverse() * match_.point1.cast<T>();
    const T inverse_sigma_1 = T(1.0 / std::sqrt(match_.sigma2_1));
    const T inverse_sigma_2 = T(1.0 / std::sqrt(match_.sigma2_2));
    residuals[0] =
        (camera_.fx * in_1.x() / in_1.z() + camera_.cx - match_.pixel1.x()) * inverse_sigma_1;
    residuals[1] =
        (camera_.fy * in_1.y() / in_1.z() + camera_.cy - match_.pixel1.y()) * inverse_sigma_1;
    residuals[2] =
        (camera_.fx * in_2.x() / in_2.z() + camera_.cx - match_.pixel2.x()) * inverse_sigma_2;
    residuals[3] =
        (camera_.fy * in_2.y() / in_2.z() + camera_.cy - match_.pixel2.y()) * inverse_sigma_2;
    return true;
  }

  Sim3Match match_;
  PinholeCamera camera_;
};

}  // namespace

void Sim3EstimationOptions::Check() const { CheckOptionFields(*this); }

Sim3Estimate RefineSim3(const std::vector<Sim3Match>& matches, const PinholeCamera& camera,
                        const Sim3& S12, const std::vector<bool>& inliers,
                        const Sim3EstimationOptions& options) {
  Sim3Parameters parameters = ToParameters(S12);
  ceres::Problem problem;
  for (std::size_t i = 0; i < matches.size(); ++i) {
    if (!inliers[i]) continue;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<Sim3ReprojectionCost, 4, 7>(
                                 new Sim3ReprojectionCost(matches[i], camera)),
                             new ceres::HuberLoss(std::sqrt(options.chi2)), parameters.data());
  }
  if (problem.NumResidualBlocks() > 0 && options.refine_iterations > 0) {
    ceres::Solver::Summary summary;
    ceres::Solve(SolverOptions(options.refine_iterations, LinearSolver::kDense), &problem,
                 &summary);
  }
  Sim3Estimate estimate;
  estimate.S12 = FromParameters(parameters);
  estimate.inlier_count =
      JudgeInliers(matches, camera, estimate.S12, options.chi2, &estimate.inliers);
  estimate.found = estimate.inlier_count >= options.min_inliers;
  return estimate;
}

Sim3Estimate EstimateSim3(const std::vector<Sim3Match>& matches, const PinholeCamera& camera,
                          const Sim3EstimationOptions& options) {
  options.Check();
  Sim3Estimate best;
  best.inliers.assign(matches.size(), false);
  if (static_cast<int>(matches.size()) < std::max(3, options.min_inliers)) return best;
  std::mt19937_64 random(options.seed);
  std::uniform_int_distribution<std::size_t> pick(0, matches.size() - 1);
  std::vector<bool> inliers;
  for (int iteration = 0; iteration < options.iterations; ++iteration) {
    std::size_t a = pick(random), b = pick(random), c = pick(random);
    if (a == b || b == c || a == c) continue;
    Sim3 S12;
    try {
      S12 = AlignPoints({matches[b].point2, matches[a].point2, matches[c].point2},
                        {matches[b].point1, matches[a].point1, matches[c].point1}, true)
                .target_from_source;
    } catch (const std::invalid_argument&) {
      continue;  // three points on a line
    }
    const int count = JudgeInliers(matches, camera, S12, options.chi2, &inliers);
    if (count > best.inlier_count) {
      best.inlier_count = count;
      best.S12 = S12;
      best.inliers = inliers;
    }
  }
  if (best.inlier_count < std::max(3, options.min_inliers)) return best;
  // All the inliers in closed form, then the reprojection errors with Ceres.
  std::vector<Eigen::Vector3d> source, target;
  for (std::size_t i = 0; i < matches.size(); ++i) {
    if (!best.inliers[i]) continue;
    source.push_back(matches[i].point2);
    target.push_back(matches[i].point1);
  }
  Sim3 S12 = AlignPoints(source, target, true).target_from_source;
  if (JudgeInliers(matches, camera, S12, options.chi2, &inliers) < best.inlier_count) {
    S12 = best.S12;  // the least-squares fit in 3-D can be worse in the images
    inliers = best.inliers;
  }
  return RefineSim3(matches, camera, S12, inliers, options);
}

}  // namespace ocg
