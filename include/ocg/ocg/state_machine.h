#pragma once
// The paper's Eq. (1), Eq. (2) and the five-state object machine (SPEC 3, items 2-4),
// as pure functions shared by the incremental detector and the test reference.

#include <cstdint>
#include <string>

#include "ocg/ocg/options.h"

namespace ocg {

enum class ObjectState : std::uint8_t {
  kObserved = 1,
  kRecentlyObserved = 2,
  kUnknown = 3,
  kSuspicious = 4,
  kOutlier = 5,
};

std::string ToString(ObjectState state);

// Eq. (1): the share of an object's covisibility weight whose neighbours are observed now.
// An object without neighbours has no rate; 0 is returned (SPEC: treat as 0).
double ActiveEdgeRate(std::uint64_t observed_weight, std::uint64_t total_weight);

// Eq. (2) increment for rate r and in-image condition P.
double DoubtIncrement(double rate, bool in_image, const OcgOptions& options);

struct StateAndDoubt {
  ObjectState state = ObjectState::kObserved;
  double doubt = 0.0;
};

// One keyframe's transition of one object (SPEC 3.4). increment is what Eq. (2) grants
// this keyframe (possibly reduced by an improved mode); it is only used in states 3 and 4.
StateAndDoubt NextState(const StateAndDoubt& current, bool observed, double rate, double increment,
                        const OcgOptions& options);

}  // namespace ocg
