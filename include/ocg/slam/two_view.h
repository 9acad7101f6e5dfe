#pragma once
// Monocular initialization from two views: a homography and a fundamental matrix
// estimated by RANSAC on the same seeded samples, the model chosen by the ratio of their
// scores, and the relative pose recovered with parallax and cheirality checks.
// Free functions returning result structs; no state, callable from any thread.

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "ocg/core/camera.h"
#include "ocg/core/lie.h"
#include "ocg/core/option_fields.h"

namespace ocg {

class SettingsFile;

// Initializer.* settings. Defaults are ORB-SLAM2's.
struct TwoViewOptions {
  int ransac_iterations = 200;  // Initializer.ransacIterations: 8-point samples tried
  double sigma = 1.0;           // Initializer.sigma: keypoint position noise, pixels
  // Chi-square bounds at 95 %: one degree of freedom (distance to an epipolar line) and
  // two (transfer error of a homography); a point's score contribution is measured
  // against the two-dof bound for both models so that their scores compare.
  double chi2_one_dof = 3.841;  // Initializer.chi2OneDof
  double chi2_two_dof = 5.991;  // Initializer.chi2TwoDof
  // Initializer.homographyRatio: choose the homography when S_H / (S_H + S_F) exceeds it.
  double homography_ratio = 0.40;
  double min_parallax_degrees = 1.0;  // Initializer.minParallax: of the 50th largest parallax
  // Initializer.minParallaxTurning / turningDegrees: a hand-held camera turning fast has
  // little translation for its rotation, and a pose from views turned more than
  // turningDegrees apart needs this much parallax (with 1 degree fr1_rpy's first map came
  // from a centimetre of baseline and scaled the trajectory wrongly).
  double min_parallax_turning_degrees = 2.0;
  double turning_degrees = 5.0;
  int min_triangulated = 50;       // Initializer.minTriangulated
  double min_good_fraction = 0.9;  // Initializer.minGoodFraction: of the model's inliers
  // Initializer.maxAmbiguity: reject when the second best pose explains this share of the
  // points the best one does (the views cannot tell the two apart).
  double max_ambiguity = 0.7;
  double max_ambiguity_homography = 0.75;  // Initializer.maxAmbiguityHomography: same, for H
  std::uint64_t seed = 42;                 // Initializer.seed: RANSAC samples

  // The settings keys, once (ocg/core/option_fields.h).
  template <typename Self, typename Visitor>
  static void VisitFields(Self& self, Visitor&& visit) {
    visit("Initializer.ransacIterations", self.ransac_iterations, OptionBound::AtLeast(1),
          "8-point RANSAC samples, shared by the homography and the fundamental matrix");
    visit("Initializer.sigma", self.sigma, OptionBound::Positive(),
          "keypoint position noise in pixels");
    visit("Initializer.chi2OneDof", self.chi2_one_dof, OptionBound::Positive(),
          "95 % bound of the epipolar distance");
    visit("Initializer.chi2TwoDof", self.chi2_two_dof, OptionBound::Positive(),
          "95 % bound of the homography transfer (at least `chi2OneDof`)");
    visit("Initializer.homographyRatio", self.homography_ratio, OptionBound::Open(0, 1),
          "choose the homography when S_H / (S_H + S_F) exceeds it");
    visit("Initializer.minParallax", self.min_parallax_degrees, OptionBound::NonNegative(),
          "degrees, of the 50th smallest parallax");
    visit("Initializer.minParallaxTurning", self.min_parallax_turning_degrees,
          OptionBound::NonNegative(),
          "degrees: the parallax needed instead of `minParallax` when the two views are turned "
          "more than `turningDegrees` apart (a turn with little baseline gives a badly scaled "
          "first map)");
    visit("Initializer.turningDegrees", self.turning_degrees, OptionBound::NonNegative(),
          "rotation between the two views, degrees, above which `minParallaxTurning` applies");
    visit("Initializer.minTriangulated", self.min_triangulated, OptionBound::AtLeast(8),
          "points that must triangulate");
    visit("Initializer.minGoodFraction", self.min_good_fraction,
          OptionBound::Between(0, true, 1, false),
          "share of the model's inliers that must triangulate");
    visit("Initializer.maxAmbiguity", self.max_ambiguity, OptionBound::Between(0, true, 1, false),
          "reject when the second-best pose explains this share of the best one's points");
    visit("Initializer.maxAmbiguityHomography", self.max_ambiguity_homography,
          OptionBound::Between(0, true, 1, false), "the same, for the homography's poses");
    visit("Initializer.seed", self.seed, OptionBound::Any(), "RANSAC seed");
  }
  void Check() const;  // throws OptionError naming the key
};

void ReadSettings(const SettingsFile& file, TwoViewOptions* options);

enum class TwoViewModel { kNone, kHomography, kFundamental };

struct TwoViewResult {
  bool success = false;
  std::string failure;  // why not, in words, when !success
  TwoViewModel model = TwoViewModel::kNone;
  SE3 T_21;  // camera 2 from camera 1; |t| = 1
  // Per correspondence: triangulated in camera 1's frame (valid where triangulated[i]).
  std::vector<Eigen::Vector3d> points;
  std::vector<bool> triangulated;
  int triangulated_count = 0;
  double score_homography = 0.0;
  double score_fundamental = 0.0;
  double homography_ratio = 0.0;  // S_H / (S_H + S_F)
  int inliers = 0;                // of the chosen model
  double parallax_degrees = 0.0;  // the 50th largest (or the smallest) parallax
};

// pixels1[i] and pixels2[i] are the undistorted positions of match i in the two views,
// both taken with camera (its distortion is ignored: pass undistorted pixels).
TwoViewResult ReconstructTwoView(const std::vector<Eigen::Vector2d>& pixels1,
                                 const std::vector<Eigen::Vector2d>& pixels2,
                                 const PinholeCamera& camera, const TwoViewOptions& options);

// Building blocks, exposed for tests.
// Homography H with p2 ~ H p1 from at least 4 correspondences (direct linear transform).
Eigen::Matrix3d HomographyFromPoints(const std::vector<Eigen::Vector2d>& p1,
                                     const std::vector<Eigen::Vector2d>& p2);
// Fundamental matrix F with p2^T F p1 = 0 from at least 8 correspondences, rank 2.
Eigen::Matrix3d FundamentalFromPoints(const std::vector<Eigen::Vector2d>& p1,
                                      const std::vector<Eigen::Vector2d>& p2);
// Linear triangulation from two projection matrices (3x4), in the frame they share.
Eigen::Vector3d TriangulateLinear(const Eigen::Vector2d& p1, const Eigen::Vector2d& p2,
                                  const Eigen::Matrix<double, 3, 4>& P1,
                                  const Eigen::Matrix<double, 3, 4>& P2);

}  // namespace ocg
