#include "ocg/core/statistics.h"

#include <algorithm>
#include <cmath>

namespace ocg {

double Quantile(std::vector<double> values, double share) {
  if (values.empty()) return 0.0;
  const std::size_t index =
      std::min(values.size() - 1, static_cast<std::size_t>(share * (values.size() - 1) + 0.5));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(index),
                   values.end());
  return values[index];
}

namespace {
constexpr double kFirstBinSeconds = 1e-6;
constexpr double kBinRatio = 1.01;
constexpr std::size_t kMaxBins = 4096;  // 1 us * 1.01^4095: far beyond any run's duration
}  // namespace

void DurationSummary::Add(double seconds) {
  ++count_;
  if (std::isfinite(seconds)) {
    sum_ += seconds;
    max_ = std::max(max_, seconds);
  }
  if (!(seconds >= kFirstBinSeconds)) {  // zero, negative, NaN: the zero bin
    if (bins_.empty()) bins_.resize(1);
    ++bins_[0];
    return;
  }
  const double steps = std::log(seconds / kFirstBinSeconds) / std::log(kBinRatio);
  const std::size_t bin = std::min(kMaxBins - 1, 1 + static_cast<std::size_t>(steps));
  if (bins_.size() <= bin) bins_.resize(bin + 1);
  ++bins_[bin];
}

double DurationSummary::Quantile(double share) const {
  if (count_ == 0) return 0.0;
  const auto rank = std::min(count_ - 1, static_cast<std::size_t>(share * (count_ - 1) + 0.5));
  std::size_t below = 0;
  for (std::size_t bin = 0; bin < bins_.size(); ++bin) {
    below += bins_[bin];
    if (below <= rank) continue;
    if (bin == 0) return 0.0;
    // The bin's geometric middle, within 0.5 % of any value in it; never above the maximum.
    const double middle =
        kFirstBinSeconds * std::pow(kBinRatio, static_cast<double>(bin) - 1.0 + 0.5);
    return std::min(middle, max_);
  }
  return max_;
}

}  // namespace ocg
