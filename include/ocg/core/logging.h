#pragma once
// Logging setup (spdlog, to stderr so stdout stays free for results) and a one-line
// progress display for long runs.

#include <chrono>
#include <cstddef>
#include <functional>
#include <string>

namespace ocg {

// Level names: trace, debug, info, warn, error, off. Throws std::invalid_argument
// listing them when level is unknown.
void ConfigureLogging(const std::string& level);

// A single self-overwriting line "label 120/2585 (4.6%)  29.8 fps  ETA 1m22s".
// Off when stdout is not a terminal (batch scripts, CI, pipes), so logs stay clean.
// Use from one thread.
class ProgressLine {
 public:
  ProgressLine(std::string label, std::size_t total);
  ProgressLine(std::string label, std::size_t total, bool enabled);
  ~ProgressLine();
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  // Redraws at most every 100 ms, and always at done == total.
  void Update(std::size_t done);
  // The same, with detail after the rate ("45 keyframes, 3120 points"): detail is asked
  // for only when the line is redrawn.
  void Update(std::size_t done, const std::function<std::string()>& detail);
  // Ends the line so later output starts on a new one.
  void Finish();
  bool enabled() const { return enabled_; }
  // The text Update would print; exposed for tests.
  std::string Format(std::size_t done, double elapsed_seconds) const;

 private:
  using Clock = std::chrono::steady_clock;
  std::string label_;
  std::size_t total_;
  bool enabled_;
  bool drawn_ = false;
  Clock::time_point start_;
  Clock::time_point last_draw_;
};

}  // namespace ocg
