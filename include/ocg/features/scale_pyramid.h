#pragma once
// The image pyramid's scales: level l is the image shrunk by scale_factor^l.

#include <vector>

namespace ocg {

struct ScalePyramid {
  double scale_factor = 1.2;
  std::vector<double> scale;          // scale_factor^l
  std::vector<double> inverse_scale;  // 1 / scale
  std::vector<double> sigma2;         // scale^2: variance of a keypoint's position at level l
  std::vector<double> inverse_sigma2;

  int levels() const { return static_cast<int>(scale.size()); }
  // The level on which a point is expected at distance, given the largest distance at
  // which it stays detectable on level 0 (max_distance), clamped to the pyramid.
  int PredictLevel(double distance, double max_distance) const;
};

ScalePyramid MakeScalePyramid(int levels, double scale_factor);

}  // namespace ocg
