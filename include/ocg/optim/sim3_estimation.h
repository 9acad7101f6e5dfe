#pragma once
// The similarity between two keyframes from matched map points (loop closing): closed
// form on three matches (Umeyama/Horn) inside seeded RANSAC, inliers judged by
// reprojection in both images, then refined with Ceres. Scale is free (monocular maps
// drift in scale).

#include <cstdint>
#include <vector>

#include "ocg/core/camera.h"
#include "ocg/core/lie.h"
#include "ocg/core/option_fields.h"

namespace ocg {

// One match: a map point of keyframe 1 and one of keyframe 2 seen as the same place.
struct Sim3Match {
  Eigen::Vector3d point1 = Eigen::Vector3d::Zero();  // keyframe 1's point, its camera frame
  Eigen::Vector3d point2 = Eigen::Vector3d::Zero();  // keyframe 2's point, its camera frame
  Eigen::Vector2d pixel1 = Eigen::Vector2d::Zero();  // undistorted keypoint in image 1
  Eigen::Vector2d pixel2 = Eigen::Vector2d::Zero();  // undistorted keypoint in image 2
  double sigma2_1 = 1.0;                             // the keypoints' pyramid-level variances
  double sigma2_2 = 1.0;
};

struct Sim3EstimationOptions {
  int iterations = 300;  // LoopClosing.sim3Iterations: RANSAC hypotheses at most
  int min_inliers = 20;  // LoopClosing.sim3MinInliers: fewer is no similarity
  double chi2 = 9.210;   // 99 % of a 2-D residual: the inlier test in each image
  int refine_iterations = 10;
  std::uint64_t seed = 0;  // RANSAC's; derive it from System.seed

  // The settings keys, once (ocg/core/option_fields.h).
  template <typename Self, typename Visitor>
  static void VisitFields(Self& self, Visitor&& visit) {
    visit("LoopClosing.sim3Iterations", self.iterations, OptionBound::AtLeast(1),
          "Sim(3) RANSAC samples (seeded from `System.seed`)");
    visit("LoopClosing.sim3MinInliers", self.min_inliers, OptionBound::AtLeast(3),
          "Sim(3) inliers in both images");
    visit("LoopClosing.sim3Chi2", self.chi2, OptionBound::Positive(),
          "Sim(3) inlier bound on the squared reprojection error over the level's variance");
    visit("LoopClosing.sim3RefineIterations", self.refine_iterations, OptionBound::NonNegative(),
          "iterations refining the Sim(3) on its inliers");
  }
  void Check() const;  // throws OptionError naming the LoopClosing.* key
};

struct Sim3Estimate {
  bool found = false;
  Sim3 S12;  // point in camera 1 = S12 * point in camera 2
  std::vector<bool> inliers;
  int inlier_count = 0;
};

// RANSAC; the best hypothesis is re-fitted on all its inliers (closed form) and refined
// (Ceres, Huber, both images), then the inliers are judged again. Deterministic for a
// seed.
Sim3Estimate EstimateSim3(const std::vector<Sim3Match>& matches, const PinholeCamera& camera,
                          const Sim3EstimationOptions& options);

// Refines S12 on the given inliers and judges every match again.
Sim3Estimate RefineSim3(const std::vector<Sim3Match>& matches, const PinholeCamera& camera,
                        const Sim3& S12, const std::vector<bool>& inliers,
                        const Sim3EstimationOptions& options);

}  // namespace ocg
