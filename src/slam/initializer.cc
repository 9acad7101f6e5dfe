#include "ocg/slam/initializer.h"

#include <algorithm>

#include "ocg/core/options.h"
#include "ocg/core/settings_file.h"
#include "ocg/core/statistics.h"

namespace ocg {

void InitialMapOptions::Check() const {
  two_view.Check();
  bundle_adjustment.Check();
  CheckOptionFields(*this);
}

void ReadSettings(const SettingsFile& file, InitialMapOptions* options) {
  ReadOptionFields(file, options);
}

InitialMap InitializeFromTwoViews(const std::vector<Eigen::Vector2d>& pixels1,
                                  const std::vector<Eigen::Vector2d>& pixels2,
                                  const PinholeCamera& camera, const InitialMapOptions& options,
                                  const std::vector<double>* inverse_sigma2) {
  InitialMap map;
  map.two_view = ReconstructTwoView(pixels1, pixels2, camera, options.two_view);
  if (!map.two_view.success) {
    map.failure = map.two_view.failure;
    return map;
  }
  BundleAdjustmentProblem problem;
  problem.camera = camera;
  problem.keyframes = {{SE3::Identity(), true}, {map.two_view.T_21, false}};
  std::vector<int> point_of_match(pixels1.size(), -1);
  for (std::size_t i = 0; i < pixels1.size(); ++i) {
    if (!map.two_view.triangulated[i]) continue;
    point_of_match[i] = static_cast<int>(problem.points.size());
    problem.points.push_back({map.two_view.points[i], false});
    const double weight = inverse_sigma2 != nullptr ? (*inverse_sigma2)[i] : 1.0;
    problem.observations.push_back({0, point_of_match[i], pixels1[i], 1.0});
    problem.observations.push_back({1, point_of_match[i], pixels2[i], weight});
  }
  map.bundle_adjustment = BundleAdjust(&problem, options.bundle_adjustment);
  if (!map.bundle_adjustment.solved) {
    map.failure = "bundle adjustment failed: " + map.bundle_adjustment.message;
    return map;
  }
  // A point is kept when neither of its observations is an outlier after BA.
  map.points.assign(pixels1.size(), Eigen::Vector3d::Zero());
  map.valid.assign(pixels1.size(), false);
  std::vector<double> depths;
  for (std::size_t i = 0; i < pixels1.size(); ++i) {
    const int p = point_of_match[i];
    if (p < 0) continue;
    const std::size_t first = 2 * static_cast<std::size_t>(p);
    if (map.bundle_adjustment.outlier[first] || map.bundle_adjustment.outlier[first + 1]) continue;
    map.points[i] = problem.points[static_cast<std::size_t>(p)].position;
    map.valid[i] = true;
    depths.push_back(map.points[i].z());
  }
  map.point_count = static_cast<int>(depths.size());
  if (map.point_count < options.min_map_points) {
    map.failure = "weak initial map: " + std::to_string(map.point_count) +
                  " points after bundle adjustment (Initializer.minMapPoints = " +
                  std::to_string(options.min_map_points) + ")";
    return map;
  }
  map.median_depth_before_scaling = Median(std::move(depths));
  if (map.median_depth_before_scaling <= 0.0) {
    map.failure = "points behind the first camera after bundle adjustment";
    return map;
  }
  const double scale = 1.0 / map.median_depth_before_scaling;
  const SE3& T = problem.keyframes[1].T_cw;
  map.T_21 = SE3(T.quaternion(), T.translation() * scale);
  for (std::size_t i = 0; i < map.points.size(); ++i) {
    if (map.valid[i]) map.points[i] *= scale;
  }
  map.success = true;
  return map;
}

}  // namespace ocg
