#pragma once
// A recorded sequence replayed as a live camera delivers it (`ocg_slam run --realtime`).
//
// A live camera does not wait for the system: it keeps only its newest image. When the
// system asks for its next image, every image that a newer one replaced meanwhile is lost.
// LiveFeed reproduces that: it sleeps until the next image is due, and skips (drops) an
// image once the one after it is due too. Whether a system keeps up with its camera is
// then measured by what it drops, not estimated from per-frame times.
//
// Threading: one thread (the one that feeds the system) calls everything but Replaced,
// which any thread may call (the image reader asks it before decoding an image).

#include <cstddef>
#include <functional>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "ocg/core/statistics.h"

namespace ocg {

class LiveFeed {
 public:
  // Seconds on a monotonic clock, from an arbitrary origin.
  using Clock = std::function<double()>;
  // Returns once the clock reads at least the given time.
  using SleepUntil = std::function<void(double)>;

  // timestamps: the images' capture times in seconds, not decreasing. Time 0 of the feed
  // is the first call of Next(). Clock and SleepUntil default to std::chrono::steady_clock
  // and std::this_thread::sleep_until. Throws std::invalid_argument when the timestamps
  // decrease.
  explicit LiveFeed(std::vector<double> timestamps, Clock clock = {}, SleepUntil sleep_until = {});

  // The index of the image to process next, after waiting until it is due; images whose
  // successor was due already are dropped on the way. nullopt once every image was
  // delivered or dropped.
  std::optional<std::size_t> Next();
  // Whether image index will never be delivered: the feed dropped it, or the image after
  // it is due already (a later Next() drops it). A live camera never hands such an image
  // over, so nobody needs to decode it. False before the first Next().
  bool Replaced(std::size_t index) const;

  std::size_t Delivered() const { return delivered_; }
  const std::vector<std::size_t>& Dropped() const { return dropped_; }

  // For run.json: frames delivered and dropped, the first dropped indices, and the lag
  // (how long after its capture time an image was handed over) median/p95/max in ms.
  nlohmann::json Report() const;

 private:
  double Due(std::size_t i) const;  // on the clock

  std::vector<double> timestamps_;
  Clock clock_;
  SleepUntil sleep_until_;
  mutable std::mutex mutex_;     // start_, next_ and dropped_, for Replaced()
  std::optional<double> start_;  // clock time of the first image
  std::size_t next_ = 0;
  std::size_t delivered_ = 0;
  std::vector<std::size_t> dropped_;
  DurationSummary lag_seconds_;  // a summary: a long live run keeps its memory flat
};

}  // namespace ocg
