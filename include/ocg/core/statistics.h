#pragma once
// Order statistics of a sample.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ocg {

// The value at rank round(share * (n - 1)) of the sorted values (share in [0, 1]); 0 for
// no values. Median(v) is Quantile(v, 0.5): the upper median for an even count.
double Quantile(std::vector<double> values, double share);
inline double Median(std::vector<double> values) { return Quantile(std::move(values), 0.5); }

// Durations (seconds) summarised as they come, in bounded memory however long the run:
// count, sum and maximum exact; quantiles (same ranks as Quantile()) to within 1 % of the
// value, from a histogram of logarithmic bins 1 % wide starting at 1 microsecond (shorter
// durations, zero and negative ones count as 0). A run's timings need no more: keeping each
// frame's would grow with the run (issue 33).
class DurationSummary {
 public:
  void Add(double seconds);
  std::size_t count() const { return count_; }
  double sum() const { return sum_; }
  double max() const { return max_; }  // 0 when empty
  double Quantile(double share) const;
  double Median() const { return Quantile(0.5); }

 private:
  std::vector<std::uint32_t> bins_;  // grown to the highest bin used (at most ~2,500)
  std::size_t count_ = 0;
  double sum_ = 0.0;
  double max_ = 0.0;
};

}  // namespace ocg
