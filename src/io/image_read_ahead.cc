#include "ocg/io/image_read_ahead.h"

#include <stdexcept>

#if defined(__linux__)
#include <sched.h>
#endif

#include <opencv2/imgcodecs.hpp>

#include "ocg/core/file_io.h"
#include "ocg/core/thread_name.h"

namespace ocg {

ImageReadAhead::ImageReadAhead(std::vector<std::string> paths, int imread_flags, std::size_t depth,
                               Prepare prepare, Skip skip)
    : paths_(std::move(paths)),
      imread_flags_(imread_flags),
      depth_(depth),
      prepare_(std::move(prepare)),
      skip_(std::move(skip)) {
  if (depth_ == 0) return;  // read in Next(), on the caller's thread
  reader_ = std::thread([this] {
    NameThisThread("image_reader");
    Run();
  });
}

ImageReadAhead::~ImageReadAhead() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  if (reader_.joinable()) reader_.join();
}

ImageReadAhead::Decoded ImageReadAhead::Decode(std::size_t index) const {
  Decoded decoded;
  if (skip_ && skip_(index)) {
    decoded.skipped = true;
    return decoded;
  }
  // cv::imread reports a missing or undecodable file by an empty image; an exception
  // from a broken codec must not end the reader thread, so it is turned into the same.
  try {
    decoded.image = cv::imread(paths_[index], imread_flags_);
  } catch (const cv::Exception&) {
    decoded.image.release();
  }
  if (prepare_ && !decoded.image.empty()) {
    try {
      decoded.prepared = prepare_(index, decoded.image);
    } catch (...) {
      decoded.failure = std::current_exception();
    }
  }
  return decoded;
}

void ImageReadAhead::Run() {
  for (std::size_t index = 0; index < paths_.size(); ++index) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [this] { return stopping_ || ready_.size() < depth_; });
      if (stopping_) return;
    }
    Decoded decoded = Decode(index);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ready_.push_back(std::move(decoded));
    }
    changed_.notify_all();
  }
}

std::size_t ImageReadAhead::AutomaticDepth() {
  constexpr std::size_t kDepth = 4;
#if defined(__linux__)
  cpu_set_t cores;
  CPU_ZERO(&cores);
  if (sched_getaffinity(0, sizeof(cores), &cores) == 0) return CPU_COUNT(&cores) >= 2 ? kDepth : 0;
#endif
  return std::thread::hardware_concurrency() >= 2 ? kDepth : 0;
}

void ImageReadAhead::WaitForNext() {
  if (depth_ == 0 || !HasNext()) return;
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [this] { return !ready_.empty(); });
}

cv::Mat ImageReadAhead::Next() { return NextFrame().image; }

ImageReadAhead::Frame ImageReadAhead::NextFrame() {
  if (!HasNext()) throw std::logic_error("ImageReadAhead::Next: every image was taken");
  Decoded decoded;
  if (depth_ == 0) {
    decoded = Decode(taken_);
  } else {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [this] { return !ready_.empty(); });
    decoded = std::move(ready_.front());
    ready_.pop_front();
    lock.unlock();
    changed_.notify_all();
  }
  const std::string& path = paths_[taken_++];
  if (decoded.skipped) return {};
  if (decoded.image.empty()) throw FileError("cannot read image '" + path + "'");
  if (decoded.failure) std::rethrow_exception(decoded.failure);
  return {std::move(decoded.image), std::move(decoded.prepared)};
}

}  // namespace ocg
