#include "ocg/slam/initialization_report.h"

#include <algorithm>

namespace ocg {
namespace {

// What a user can do about each reason the tracker and the two-view initializer give.
std::string Cause(const std::string& reason) {
  if (reason == "the model has no decomposition with a translation" ||
      reason == "too little parallax" || reason == "too few points triangulate well" ||
      reason == "two poses explain the views about equally well") {
    return "too little parallax: the camera stood still or only rotated; it must move "
           "sideways (translate) over the first frames";
  }
  if (reason == "too few features") {
    return "too few ORB features: the images are dark, blurred or without texture "
           "(Tracking.minInitFeatures)";
  }
  if (reason == "too few matches with the first view") {
    return "consecutive frames share too few features: the camera moves too fast or the "
           "images blur (Tracking.minInitMatches)";
  }
  if (reason == "weak initial map") {
    return "the two views give too few good points (Initializer.minMapPoints)";
  }
  return reason;
}

}  // namespace

std::string FailureReason(const std::string& failure) {
  const std::size_t end = std::min(failure.find(" ("), failure.find(": "));
  return failure.substr(0, end);
}

void InitializationAttempts::Record(const std::string& failure) {
  const std::string reason = FailureReason(failure);
  ++reasons[reason];
  last_failure[reason] = failure;
}

std::string InitializationAttempts::MostFrequentReason() const {
  std::string best;
  int count = 0;
  for (const auto& [reason, frames_failed] : reasons) {
    if (frames_failed > count) {
      best = reason;
      count = frames_failed;
    }
  }
  return best;
}

std::string NeverInitializedMessage(const InitializationAttempts& attempts) {
  std::string message = "never initialized in " + std::to_string(attempts.frames) + " frames: ";
  const std::string reason = attempts.MostFrequentReason();
  if (reason.empty()) {
    return message + "no second frame to initialize from (at least two frames with " +
           "enough features are needed)";
  }
  int failed = 0;
  for (const auto& entry : attempts.reasons) failed += entry.second;
  return message + Cause(reason) + "; the initializer said '" + reason + "' for " +
         std::to_string(attempts.reasons.at(reason)) + " of the " + std::to_string(failed) +
         " failed attempts (last: '" + attempts.last_failure.at(reason) + "')";
}

}  // namespace ocg
