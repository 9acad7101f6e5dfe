#include "ocg/features/scale_pyramid.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace ocg {

ScalePyramid MakeScalePyramid(int levels, double scale_factor) {
  assert(levels >= 1 && scale_factor > 1.0);
  ScalePyramid pyramid;
  pyramid.scale_factor = scale_factor;
  double scale = 1.0;
  for (int level = 0; level < levels; ++level) {
    pyramid.scale.push_back(scale);
    pyramid.inverse_scale.push_back(1.0 / scale);
    pyramid.sigma2.push_back(scale * scale);
    pyramid.inverse_sigma2.push_back(1.0 / (scale * scale));
    scale *= scale_factor;
  }
  return pyramid;
}

int ScalePyramid::PredictLevel(double distance, double max_distance) const {
  if (!(distance > 0.0)) return levels() - 1;  // at the camera: as coarse as it gets
  if (!(max_distance > 0.0)) return 0;
  const double ratio = max_distance / distance;
  const int level = static_cast<int>(std::ceil(std::log(ratio) / std::log(scale_factor)));
  return std::clamp(level, 0, levels() - 1);
}

}  // namespace ocg
