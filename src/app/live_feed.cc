#include "ocg/app/live_feed.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>

#include "ocg/core/statistics.h"

namespace ocg {
namespace {

double SteadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void SleepUntilSteady(double seconds) {
  const auto target = std::chrono::steady_clock::time_point(
      std::chrono::duration_cast<std::chrono::steady_clock::duration>(
          std::chrono::duration<double>(seconds)));
  std::this_thread::sleep_until(target);
}

}  // namespace

LiveFeed::LiveFeed(std::vector<double> timestamps, Clock clock, SleepUntil sleep_until)
    : timestamps_(std::move(timestamps)),
      clock_(clock ? std::move(clock) : Clock(SteadySeconds)),
      sleep_until_(sleep_until ? std::move(sleep_until) : SleepUntil(SleepUntilSteady)) {
  for (std::size_t i = 1; i < timestamps_.size(); ++i) {
    if (timestamps_[i] < timestamps_[i - 1])
      throw std::invalid_argument("LiveFeed: timestamp of image " + std::to_string(i) +
                                  " is earlier than the one before it");
  }
}

double LiveFeed::Due(std::size_t i) const { return *start_ + timestamps_[i] - timestamps_[0]; }

std::optional<std::size_t> LiveFeed::Next() {
  std::size_t index = 0;
  double now = 0.0;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (next_ >= timestamps_.size()) return std::nullopt;
    if (!start_) start_ = clock_();
    now = clock_();
    // The camera has replaced image next_ once its successor is due.
    while (next_ + 1 < timestamps_.size() && Due(next_ + 1) <= now) dropped_.push_back(next_++);
    index = next_++;
  }
  if (Due(index) > now) sleep_until_(Due(index));
  lag_seconds_.Add(std::max(0.0, clock_() - Due(index)));
  ++delivered_;
  return index;
}

bool LiveFeed::Replaced(std::size_t index) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (index < next_) return std::binary_search(dropped_.begin(), dropped_.end(), index);
  // The clock read here is no later than the one of any later Next(), which then drops it.
  return start_ && index + 1 < timestamps_.size() && Due(index + 1) <= clock_();
}

nlohmann::json LiveFeed::Report() const {
  nlohmann::json first_dropped = nlohmann::json::array();
  for (std::size_t i = 0; i < std::min<std::size_t>(dropped_.size(), 20); ++i)
    first_dropped.push_back(dropped_[i]);
  return {{"realtime", true},
          {"frames_delivered", delivered_},
          {"frames_dropped", dropped_.size()},
          {"first_dropped_frames", first_dropped},
          {"lag_ms",
           {{"median", 1e3 * lag_seconds_.Median()},
            {"p95", 1e3 * lag_seconds_.Quantile(0.95)},
            {"max", 1e3 * lag_seconds_.max()}}}};
}

}  // namespace ocg
