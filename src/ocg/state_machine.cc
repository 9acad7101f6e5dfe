#include "ocg/ocg/state_machine.h"

#include <cassert>

namespace ocg {

std::string ToString(ObjectState state) {
  switch (state) {
    case ObjectState::kObserved:
      return "observed";
    case ObjectState::kRecentlyObserved:
      return "recently_observed";
    case ObjectState::kUnknown:
      return "unknown";
    case ObjectState::kSuspicious:
      return "suspicious";
    case ObjectState::kOutlier:
      return "outlier";
  }
  return "?";
}

double ActiveEdgeRate(std::uint64_t observed_weight, std::uint64_t total_weight) {
  assert(observed_weight <= total_weight);
  if (total_weight == 0) return 0.0;
  return static_cast<double>(observed_weight) / static_cast<double>(total_weight);
}

double DoubtIncrement(double rate, bool in_image, const OcgOptions& options) {
  if (!in_image) return 0.0;
  if (rate >= 1.0) return options.increment_full;
  if (rate >= options.rate_high) return options.increment_high;
  if (rate > options.tau_observable) return options.increment_low;
  return 0.0;
}

StateAndDoubt NextState(const StateAndDoubt& current, bool observed, double rate, double increment,
                        const OcgOptions& options) {
  assert(current.state != ObjectState::kOutlier);
  if (observed) return {ObjectState::kObserved, 0.0};
  const double tau = options.tau_observable;
  switch (current.state) {
    case ObjectState::kObserved:
    case ObjectState::kRecentlyObserved:
      // Below tau the camera has left the observable region; at exactly tau it has not.
      return {rate < tau ? ObjectState::kUnknown : ObjectState::kRecentlyObserved, 0.0};
    case ObjectState::kUnknown:
      if (rate > tau) return {ObjectState::kSuspicious, increment};
      return current;
    case ObjectState::kSuspicious:
      if (rate < tau) {
        if (current.doubt > options.tau_doubt) return {ObjectState::kOutlier, current.doubt};
        return {ObjectState::kUnknown, 0.0};
      }
      return {ObjectState::kSuspicious, current.doubt + increment};
    case ObjectState::kOutlier:
      break;
  }
  return current;
}

}  // namespace ocg
