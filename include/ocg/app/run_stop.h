#pragma once
// Ending a long run early without losing it (docs/robustness.md, "Stopping a run"). The
// first request ends the frame loop after the frame in hand; the run then finishes as at
// the end of its frames (local mapping, loop closing and the OCG settle) and writes every
// output and its map, marked "interrupted": true in run.json. What a second request means
// is the caller's: `ocg_slam` exits at once.

#include <atomic>

namespace ocg {

class RunStop {
 public:
  // Async-signal-safe (one lock-free atomic), so a signal handler may call it. Returns the
  // number of requests so far, this one included.
  int Request() noexcept { return requests_.fetch_add(1) + 1; }
  bool Requested() const noexcept { return requests_.load() > 0; }
  void Reset() noexcept { requests_.store(0); }

 private:
  static_assert(std::atomic<int>::is_always_lock_free, "signal handlers need a lock-free flag");
  std::atomic<int> requests_{0};
};

// The process's stop request, the one signal handlers set (signals are per process).
RunStop& ProcessRunStop();

}  // namespace ocg
