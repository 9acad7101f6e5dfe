#pragma once
// The first map of a monocular run from two views: two-view reconstruction, bundle
// adjustment of both views and their points, then scaling so that the median depth of
// the points in the first view is 1. A free function on plain data.

#include <string>
#include <vector>

#include "ocg/core/option_fields.h"
#include "ocg/optim/bundle_adjustment.h"
#include "ocg/slam/two_view.h"

namespace ocg {

struct InitialMapOptions {
  TwoViewOptions two_view;
  BundleAdjustmentOptions bundle_adjustment;
  // Initializer.minMapPoints: fewer points after bundle adjustment is a weak map, and
  // tracking starts over with a new first view (ORB-SLAM2: 100).
  int min_map_points = 100;

  // The settings keys, once (ocg/core/option_fields.h).
  template <typename Self, typename Visitor>
  static void VisitFields(Self& self, Visitor&& visit) {
    TwoViewOptions::VisitFields(self.two_view, visit);
    visit("Initializer.minMapPoints", self.min_map_points, OptionBound::AtLeast(8),
          "fewer points after bundle adjustment: weak map, start over");
  }
  void Check() const;
};

// Initializer.* keys (the two-view ones and Initializer.minMapPoints).
void ReadSettings(const SettingsFile& file, InitialMapOptions* options);

struct InitialMap {
  bool success = false;
  std::string failure;
  TwoViewResult two_view;  // before bundle adjustment
  SE3 T_21;                // after bundle adjustment and scaling; camera 1 is the origin
  std::vector<Eigen::Vector3d> points;  // per correspondence, in camera 1's frame
  std::vector<bool> valid;              // triangulated and not an outlier after BA
  int point_count = 0;
  double median_depth_before_scaling = 0.0;
  BundleAdjustmentReport bundle_adjustment;
};

// pixels1/2: undistorted positions of the matches; sigma2_inverse (optional, one per
// match): 1 / scale^2 of the keypoint's pyramid level in view 2, for the BA weights.
InitialMap InitializeFromTwoViews(const std::vector<Eigen::Vector2d>& pixels1,
                                  const std::vector<Eigen::Vector2d>& pixels2,
                                  const PinholeCamera& camera, const InitialMapOptions& options,
                                  const std::vector<double>* inverse_sigma2 = nullptr);

}  // namespace ocg
