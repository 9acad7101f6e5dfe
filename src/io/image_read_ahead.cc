#include "ocg/io/image_read_ahead.h"

#include <stdexcept>

#include <opencv2/imgcodecs.hpp>

#include "ocg/core/file_io.h"
#include "ocg/core/thread_name.h"

namespace ocg {

ImageReadAhead::ImageReadAhead(std::vector<std::string> paths, int imread_flags, std::size_t depth)
    : paths_(std::move(paths)), imread_flags_(imread_flags), depth_(depth == 0 ? 1 : depth) {
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
  reader_.join();
}

void ImageReadAhead::Run() {
  for (const std::string& path : paths_) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [this] { return stopping_ || ready_.size() < depth_; });
      if (stopping_) return;
    }
    // cv::imread reports a missing or undecodable file by an empty image; an exception
    // from a broken codec must not end the thread, so it is turned into the same.
    Decoded decoded;
    try {
      decoded.image = cv::imread(path, imread_flags_);
    } catch (const cv::Exception&) {
      decoded.image.release();
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ready_.push_back(std::move(decoded));
    }
    changed_.notify_all();
  }
}

cv::Mat ImageReadAhead::Next() {
  if (!HasNext()) throw std::logic_error("ImageReadAhead::Next: every image was taken");
  Decoded decoded;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [this] { return !ready_.empty(); });
    decoded = std::move(ready_.front());
    ready_.pop_front();
  }
  changed_.notify_all();
  const std::string& path = paths_[taken_++];
  if (decoded.image.empty()) throw FileError("cannot read image '" + path + "'");
  return decoded.image;
}

}  // namespace ocg
