#pragma once
// Decodes the images of a sequence on a thread of its own, a few images ahead of the
// consumer. Decoding a 640x480 PNG costs about as much as tracking the frame (a quarter
// of the CPU samples of a run on a generated sequence, bench/slam_speed.py --profile);
// read ahead, it runs while the consumer tracks the previous frame instead of between
// frames. The images and their order are exactly those of reading one after the other.
//
// Threading: the constructor starts the reader thread ("image_reader") unless depth is 0;
// HasNext and Next
// are called from one consumer thread; the destructor stops and joins the reader (images
// read ahead and never taken are dropped).

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <opencv2/core.hpp>

namespace ocg {

class ImageReadAhead {
 public:
  // paths: image files, read in this order. imread_flags: cv::IMREAD_* (e.g. GRAYSCALE).
  // depth: at most this many decoded images wait for the consumer; 0 starts no thread and
  // decodes each image in Next() (on one core a reader thread only competes with the
  // consumer: bench/slam_speed.py --cores 1 measured it).
  ImageReadAhead(std::vector<std::string> paths, int imread_flags, std::size_t depth = 4);
  ~ImageReadAhead();
  ImageReadAhead(const ImageReadAhead&) = delete;
  ImageReadAhead& operator=(const ImageReadAhead&) = delete;

  // The depth to use by default: 4 when this process may run on two cores or more, else
  // 0 (Linux: the CPU affinity mask, so taskset and cgroup pinning count).
  static std::size_t AutomaticDepth();

  bool HasNext() const { return taken_ < paths_.size(); }

  // The next image in path order, waiting for it if it is not decoded yet. Throws
  // FileError naming the file when it cannot be read or decoded, and std::logic_error when
  // every image was taken.
  cv::Mat Next();

 private:
  struct Decoded {
    cv::Mat image;  // empty when the file could not be read
  };
  void Run();
  Decoded Decode(const std::string& path) const;

  const std::vector<std::string> paths_;
  const int imread_flags_;
  const std::size_t depth_;
  std::size_t taken_ = 0;  // consumer thread only

  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<Decoded> ready_;
  bool stopping_ = false;
  std::thread reader_;
};

}  // namespace ocg
