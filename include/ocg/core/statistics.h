#pragma once
// Order statistics of a sample.

#include <vector>

namespace ocg {

// The value at rank round(share * (n - 1)) of the sorted values (share in [0, 1]); 0 for
// no values. Median(v) is Quantile(v, 0.5): the upper median for an even count.
double Quantile(std::vector<double> values, double share);
inline double Median(std::vector<double> values) { return Quantile(std::move(values), 0.5); }

}  // namespace ocg
