#include "ocg/core/statistics.h"

#include <algorithm>

namespace ocg {

double Quantile(std::vector<double> values, double share) {
  if (values.empty()) return 0.0;
  const std::size_t index =
      std::min(values.size() - 1, static_cast<std::size_t>(share * (values.size() - 1) + 0.5));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(index),
                   values.end());
  return values[index];
}

}  // namespace ocg
