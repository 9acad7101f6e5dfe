#pragma once
// Why a monocular run has not initialized: every frame given while tracking waits for a
// first map, counted by the reason the initializer gave. A run that ends without a map
// says why at the end (and in run.json) instead of writing empty trajectories silently.

#include <map>
#include <string>

namespace ocg {

// The reason in a failure text: what precedes its figures (" (" or ": "), so that
// "too little parallax (0.12 degrees)" and "too little parallax (0.31 degrees)" count as one.
std::string FailureReason(const std::string& failure);

struct InitializationAttempts {
  int frames = 0;  // frames given while not initialized (map resets included)
  // Reason -> frames that failed for it. A frame that only became the first view of a
  // pair (nothing to fail yet) counts in frames but under no reason.
  std::map<std::string, int> reasons;
  std::map<std::string, std::string> last_failure;  // reason -> its latest full text

  void Record(const std::string& failure);
  // The reason given most often (ties: alphabetical order); empty when none was given.
  std::string MostFrequentReason() const;
};

// "never initialized in N frames: <cause>; the initializer said '<reason>' for K of the
// M failed attempts (last: '<full text>')", for a run that ended with no map.
std::string NeverInitializedMessage(const InitializationAttempts& attempts);

}  // namespace ocg
