#include "keyframe_colours.h"

#include <spdlog/spdlog.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "ocg/core/cpu_time.h"

namespace ocg::app_detail {

const cv::Mat& FrameColourImage::Bgr() {
  if (given_.type() == CV_8UC3) return given_;
  if (!tried_ && !path_.empty()) {
    tried_ = true;
    const double start = ThreadCpuSeconds();
    if (std::filesystem::exists(path_)) read_ = cv::imread(path_, cv::IMREAD_COLOR);
    read_seconds_ = ThreadCpuSeconds() - start;
  }
  return read_;
}

cv::Mat KeyframeColours::ImageFor(FrameColourImage& image) {
  if (!image.HasSource()) return cv::Mat();
  const double read_before = image.read_seconds();
  cv::Mat bgr = image.Bgr();
  read_seconds_ += image.read_seconds() - read_before;  // a layer after the first reads none
  if (bgr.empty() && unreadable_++ == 0) first_unreadable_ = image.path();
  return bgr;
}

void KeyframeColours::WarnOfUnreadable() const {
  if (unreadable_ == 0) return;
  spdlog::warn(
      "{} keyframe image(s) could not be read (the first: '{}'): their sightings give the "
      "objects no colour, and moves are paired without it",
      unreadable_, first_unreadable_);
}

nlohmann::json KeyframeColours::Report(const ObjectLayerStats& stats) const {
  return {{"keyframe_images", stats.colour_images},
          {"sightings", stats.colour_sightings},
          {"unreadable_images", unreadable_}};
}

nlohmann::json KeyframeColours::Timing(const ObjectLayerStats& stats) const {
  const auto ms_per_image = [&](double seconds) {
    return stats.colour_images > 0 ? 1000.0 * seconds / static_cast<double>(stats.colour_images)
                                   : 0.0;
  };
  return {{"read_cpu_ms", ms_per_image(read_seconds_)},
          {"colour_cpu_ms", ms_per_image(stats.colour_cpu_seconds)}};
}

}  // namespace ocg::app_detail
