#include "run_progress.h"

#include <unistd.h>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <cmath>
#include <cstdio>

#include "ocg/app/run_stop.h"

namespace ocg {

RunStop& ProcessRunStop() {
  static RunStop stop;
  return stop;
}

namespace app_detail {

std::size_t ResidentMemoryBytes() {
  std::FILE* file = std::fopen("/proc/self/statm", "r");
  if (file == nullptr) return 0;
  unsigned long long size = 0, resident = 0;
  const int read = std::fscanf(file, "%llu %llu", &size, &resident);
  std::fclose(file);
  const long page = ::sysconf(_SC_PAGESIZE);
  if (read != 2 || page <= 0) return 0;
  return static_cast<std::size_t>(resident) * static_cast<std::size_t>(page);
}

std::size_t HeapInUseBytes() {
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  const struct mallinfo2 info = ::mallinfo2();
  return info.uordblks + info.hblkhd;
#else
  return 0;
#endif
}

void ReleaseFreeHeap() {
#if defined(__GLIBC__)
  ::malloc_trim(0);
#endif
}

bool HeapRelease::MaybeRelease(double seconds) {
  if (seconds < next_) return false;
  ReleaseFreeHeap();
  next_ = (std::floor(seconds / interval_) + 1.0) * interval_;
  return true;
}

ProgressSeries::ProgressSeries(double interval_seconds, std::size_t max_samples)
    : interval_(interval_seconds), max_samples_(std::max<std::size_t>(max_samples, 2)) {}

bool ProgressSeries::Due(double seconds) const { return seconds >= next_; }

void ProgressSeries::Add(const RunStatus& status) {
  // A sample taken at the end replaces one taken within the same interval.
  if (!samples_.empty() && status.seconds < next_) samples_.pop_back();
  samples_.push_back(status);
  if (samples_.size() >= max_samples_) {
    std::vector<RunStatus> kept;
    for (std::size_t i = 0; i < samples_.size(); i += 2) kept.push_back(samples_[i]);
    if (kept.back().seconds != samples_.back().seconds) kept.push_back(samples_.back());
    samples_ = std::move(kept);
    interval_ *= 2.0;
  }
  next_ = (std::floor(status.seconds / interval_) + 1.0) * interval_;
}

nlohmann::json ProgressSeries::Json() const {
  nlohmann::json series = nlohmann::json::array();
  for (const RunStatus& sample : samples_) {
    series.push_back(
        {{"seconds", std::round(sample.seconds * 10.0) / 10.0},
         {"frames", sample.frames},
         {"keyframes", sample.keyframes},
         {"map_points", sample.map_points},
         {"objects", sample.objects},
         {"resident_mb", std::round(static_cast<double>(sample.resident_bytes) / 1e5) / 10.0},
         {"heap_mb", std::round(static_cast<double>(sample.heap_bytes) / 1e5) / 10.0}});
  }
  return series;
}

}  // namespace app_detail
}  // namespace ocg
