#pragma once
// What a long run shows of its growth (docs/slam.md, "Long runs"): the process's resident
// memory, and run.json's "progress", a short series of ObjectSlam::Status() over the run.

#include <cstddef>
#include <nlohmann/json.hpp>
#include <vector>

#include "ocg/app/object_slam.h"

namespace ocg::app_detail {

// The process's resident memory in bytes (Linux: /proc/self/statm); 0 where unknown.
std::size_t ResidentMemoryBytes();

// The bytes the allocator has handed out and not had back (glibc: mallinfo2, every arena
// and mmapped block); 0 where unknown. Resident memory above it is the allocator's: free
// pages it keeps, code, stacks.
std::size_t HeapInUseBytes();

// Gives the system back the free pages inside the allocator's heaps (glibc: malloc_trim),
// not only those at their tops, which is all free() gives back. A long run frees and
// allocates in a different order than it grew (culled keyframes, thinned sightings,
// growing vectors), so the free memory ends up in holes between live blocks: without
// this its resident memory keeps the heap's high-water mark and drifts up. Safe at any
// time from any thread; a no-op where unsupported.
void ReleaseFreeHeap();

// ReleaseFreeHeap() at most once every `interval_seconds` of a run's wall time.
class HeapRelease {
 public:
  explicit HeapRelease(double interval_seconds = 10.0) : interval_(interval_seconds) {}
  // Releases when due; true when it did.
  bool MaybeRelease(double seconds);

 private:
  double interval_;
  double next_ = 0.0;
};

// At most max_samples samples spread over the whole run, however long: one every
// interval; when the series is full every other sample is dropped and the interval
// doubles. The last sample (the run's end) is always kept.
class ProgressSeries {
 public:
  explicit ProgressSeries(double interval_seconds = 10.0, std::size_t max_samples = 32);
  // Whether a sample is due at this time (seconds since the run's first frame).
  bool Due(double seconds) const;
  void Add(const RunStatus& status);
  // [{"seconds", "frames", "keyframes", "map_points", "objects", "resident_mb"}, ...]
  nlohmann::json Json() const;
  double interval_seconds() const { return interval_; }

 private:
  double interval_;
  std::size_t max_samples_;
  double next_ = 0.0;
  std::vector<RunStatus> samples_;
};

}  // namespace ocg::app_detail
