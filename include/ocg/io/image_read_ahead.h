#pragma once
// Decodes the images of a sequence on a thread of its own, a few images ahead of the
// consumer. Decoding a 640x480 PNG costs about as much as tracking the frame (a quarter
// of the CPU samples of a run on a generated sequence, bench/slam_speed.py --profile);
// read ahead, it runs while the consumer tracks the previous frame instead of between
// frames. The images and their order are exactly those of reading one after the other.
// An optional prepare function runs on each decoded image on the same thread (ocg_slam:
// the ORB extraction, so that it too runs while the previous frame is tracked).
//
// Threading: the constructor starts the reader thread ("image_reader") unless depth is 0;
// HasNext and Next
// are called from one consumer thread; the destructor stops and joins the reader (images
// read ahead and never taken are dropped).

#include <any>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <opencv2/core.hpp>

namespace ocg {

class ImageReadAhead {
 public:
  // Work on a decoded image (index: its place in paths), done where it is decoded (the
  // reader thread, or Next() when depth is 0); its result comes with the image.
  using Prepare = std::function<std::any(std::size_t index, const cv::Mat&)>;
  using Skip = std::function<bool(std::size_t index)>;
  struct Frame {
    cv::Mat image;
    std::any prepared;  // prepare's result; empty without a prepare function
  };

  // paths: image files, read in this order. imread_flags: cv::IMREAD_* (e.g. GRAYSCALE).
  // depth: at most this many decoded images wait for the consumer; 0 starts no thread and
  // decodes each image in Next() (on one core a reader thread only competes with the
  // consumer: bench/slam_speed.py --cores 1 measured it).
  // prepare: optional; an exception from it is rethrown by the Next/NextFrame call that
  // takes that image.
  // skip: optional, asked (on the reader thread) before image index is decoded; true: it
  // is neither read nor prepared, and Next/NextFrame give an empty image for it (ocg_slam
  // --realtime: an image the live camera replaced is never decoded, as with a real camera,
  // so that a dropped frame costs no work that would make the next one late too).
  ImageReadAhead(std::vector<std::string> paths, int imread_flags, std::size_t depth = 4,
                 Prepare prepare = nullptr, Skip skip = nullptr);
  ~ImageReadAhead();
  ImageReadAhead(const ImageReadAhead&) = delete;
  ImageReadAhead& operator=(const ImageReadAhead&) = delete;

  // The depth to use by default: 4 when this process may run on two cores or more, else
  // 0 (Linux: the CPU affinity mask, so taskset and cgroup pinning count).
  static std::size_t AutomaticDepth();

  bool HasNext() const { return taken_ < paths_.size(); }
  // Waits until the next image is decoded and prepared (at once when depth is 0, where
  // Next() does that work). ocg_slam --realtime starts the camera's clock after it: the
  // reader's cold start (the first decoding and extraction, several times a frame's) is
  // the system's start-up, not a frame the camera waits for.
  void WaitForNext();

  // The next image in path order, waiting for it if it is not decoded yet. Throws
  // FileError naming the file when it cannot be read or decoded, and std::logic_error when
  // every image was taken.
  cv::Mat Next();
  // The same, with what prepare made of it.
  Frame NextFrame();

 private:
  struct Decoded {
    bool skipped = false;
    cv::Mat image;  // empty when the file could not be read or was skipped
    std::any prepared;
    std::exception_ptr failure;  // from prepare
  };
  void Run();
  Decoded Decode(std::size_t index) const;

  const std::vector<std::string> paths_;
  const int imread_flags_;
  const std::size_t depth_;
  const Prepare prepare_;
  const Skip skip_;
  std::size_t taken_ = 0;  // consumer thread only

  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<Decoded> ready_;
  bool stopping_ = false;
  std::thread reader_;
};

}  // namespace ocg
