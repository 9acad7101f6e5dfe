#pragma once
// Descriptor matching as ORB-SLAM2 does it: Hamming distances with thresholds, a ratio
// test against the second best, and a rotation-consistency histogram; candidates come
// from a window (initialization), from projections (tracking) or from shared vocabulary
// nodes (BoW). Every function returns, for each query feature, the index of its match or
// kNoMatch, and never matches one feature twice.

#include <Eigen/Core>
#include <opencv2/core/types.hpp>
#include <vector>

#include "ocg/core/option_fields.h"
#include "ocg/features/descriptor.h"
#include "ocg/features/orb_extractor.h"
#include "ocg/features/vocabulary.h"

namespace ocg {

class SettingsFile;

constexpr int kNoMatch = -1;

// Matcher.* settings. Defaults are ORB-SLAM2's.
struct MatcherOptions {
  int strict_distance = 50;           // Matcher.strictDistance: accept for BoW and initialization
  int loose_distance = 100;           // Matcher.looseDistance: accept for projection search
  bool check_orientation = true;      // Matcher.checkOrientation: rotation histogram filter
  int orientation_bins = 30;          // Matcher.orientationBins: histogram bins over 360 degrees
  double initialization_ratio = 0.9;  // Matcher.initializationRatio: best / second best
  double projection_ratio = 0.8;      // Matcher.projectionRatio: map points onto a frame
  double bow_ratio = 0.7;             // Matcher.bowRatio: keyframe to frame through BoW
  int initialization_window = 100;    // Matcher.initializationWindow: search radius, pixels
  // Matcher.initializationAllLevels: match features of every pyramid level (each with
  // its neighbouring levels) when initializing; false: level 0 only (ORB-SLAM2).
  bool initialization_all_levels = true;

  // The settings keys, once (ocg/core/option_fields.h).
  template <typename Self, typename Visitor>
  static void VisitFields(Self& self, Visitor&& visit) {
    visit("Matcher.strictDistance", self.strict_distance, OptionBound::Closed(0, 256),
          "largest Hamming distance accepted by BoW and initialization matching");
    visit("Matcher.looseDistance", self.loose_distance, OptionBound::Closed(0, 256),
          "largest Hamming distance accepted by projection search (at least `strictDistance`)");
    visit("Matcher.checkOrientation", self.check_orientation, OptionBound::Any(),
          "keep only matches in the three most popular rotation bins");
    visit("Matcher.orientationBins", self.orientation_bins, OptionBound::Closed(1, 360),
          "rotation histogram bins over 360 degrees");
    visit("Matcher.initializationRatio", self.initialization_ratio,
          OptionBound::Between(0, true, 1, false),
          "best / second-best distance ratio, initialization");
    visit("Matcher.projectionRatio", self.projection_ratio, OptionBound::Between(0, true, 1, false),
          "ratio for map points projected onto a frame (same pyramid level)");
    visit("Matcher.bowRatio", self.bow_ratio, OptionBound::Between(0, true, 1, false),
          "ratio for keyframe-to-frame BoW matching");
    visit("Matcher.initializationWindow", self.initialization_window, OptionBound::Positive(),
          "search radius in pixels at initialization");
    visit("Matcher.initializationAllLevels", self.initialization_all_levels, OptionBound::Any(),
          "initialization matches every pyramid level against its neighbouring levels (false: "
          "level 0 alone, as ORB-SLAM2): a blurred view under a fast turn keeps its matches "
          "long enough to build parallax");
  }
  void Check() const;  // throws OptionError naming the key
};

void ReadSettings(const SettingsFile& file, MatcherOptions* options);

// Keeps the matches whose rotation (angle_b - angle_a) falls in the three most popular
// histogram bins (the second and third only when they hold at least a tenth as many as
// the first), as a rigid image motion rotates all keypoints alike.
void FilterByRotationConsistency(const std::vector<cv::KeyPoint>& keypoints_a,
                                 const std::vector<cv::KeyPoint>& keypoints_b, int bins,
                                 std::vector<int>* matches_a_to_b);

// Exhaustive matching with a ratio test; max_distance bounds the best distance.
std::vector<int> MatchBruteForce(const std::vector<Descriptor>& a, const std::vector<Descriptor>& b,
                                 double ratio, int max_distance);

// Monocular initialization: features of a searched in b within the window around
// predicted[i] (usually the position a's feature had when last matched), on the same
// pyramid level or a neighbouring one (level 0 only unless initialization_all_levels).
std::vector<int> MatchInWindow(const ExtractedFeatures& a, const ExtractedFeatures& b,
                               const std::vector<Eigen::Vector2d>& predicted,
                               const MatcherOptions& options);

// A point projected into the image searched: its predicted undistorted position, the
// window's radius in level-0 pixels, the levels allowed, the descriptor to match and
// (optionally) the angle of the keypoint it came from for the rotation check.
struct ProjectedPoint {
  Eigen::Vector2d pixel;
  double radius = 4.0;
  int min_level = 0;
  int max_level = -1;  // < 0: any level from min_level up
  Descriptor descriptor{};
  float source_angle = -1.0f;  // < 0: no rotation check for this point
};

// Matches every projected point to a feature of frame. taken (optional, one per frame
// feature) marks features that must not be matched again. ratio <= 0 turns the ratio test
// off. A feature wanted by several points keeps the closest one.
std::vector<int> SearchByProjection(const ExtractedFeatures& frame,
                                    const std::vector<ProjectedPoint>& points,
                                    const std::vector<bool>* taken, double ratio, int max_distance,
                                    const MatcherOptions& options);

// Features of one image as the BoW matcher sees them. usable (optional) masks features
// that may take part (for a keyframe: the ones with a map point).
struct BowFeatures {
  const FeatureVector* feature_vector = nullptr;
  const std::vector<Descriptor>* descriptors = nullptr;
  const std::vector<cv::KeyPoint>* keypoints = nullptr;
  const std::vector<bool>* usable = nullptr;
};

// Matches features of a to features of b that fall under the same vocabulary node.
std::vector<int> SearchByBow(const BowFeatures& a, const BowFeatures& b,
                             const MatcherOptions& options);

}  // namespace ocg
