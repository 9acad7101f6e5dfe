#pragma once
// The objects' colour signatures, one path for both run kinds (`ocg_slam objects` and
// `ocg_slam run`): at each OCG keyframe (every Objects.keyframe_interval-th frame with a
// pose) with detections, the frame's colour image goes with its detections to
// ObjectMapper::AddFrame, which gives the sightings the frame made their signatures before
// the OCG can remove their objects. Nothing is kept for later: memory does not grow with
// the run, and a removed object keeps the colours of this session's sightings
// (SightingHistory::ForgetSightings), which the change log's pairing of moves weighs
// (ChangeLogContext::colour). For the caller's (tracking) thread.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <opencv2/core/mat.hpp>
#include <string>
#include <utility>

#include "ocg/objects/object_mapper.h"

namespace ocg::app_detail {

// One frame's colour pixels: the BGR image the caller gave (ObjectSlam::Track with colour
// pixels), else its image file read in colour, read at most once however many object
// layers ask for it (ocg_slam run --modes).
class FrameColourImage {
 public:
  FrameColourImage(std::string path, cv::Mat given)
      : path_(std::move(path)), given_(std::move(given)) {}
  // Empty when the frame has neither colour pixels nor a file, or the file is unreadable.
  const cv::Mat& Bgr();
  bool HasSource() const { return given_.type() == CV_8UC3 || !path_.empty(); }
  const std::string& path() const { return path_; }
  // Bgr()'s CPU time reading the file, seconds (0 before, or when given or cached).
  double read_seconds() const { return read_seconds_; }

 private:
  std::string path_;
  cv::Mat given_;
  cv::Mat read_;
  bool tried_ = false;
  double read_seconds_ = 0.0;
};

// A run's keyframe colours: the images for AddFrame and what run.json reports of them.
class KeyframeColours {
 public:
  // The image to give AddFrame for a keyframe with detections (empty when there is none);
  // an unreadable file is counted.
  cv::Mat ImageFor(FrameColourImage& image);
  // At the end of the run: one warning for every unreadable image, not one per keyframe
  // (a frame list of a sequence whose images were left out lists thousands).
  void WarnOfUnreadable() const;
  // run.json's "colour_signatures": keyframe_images and sightings (the mapper's counts,
  // ObjectLayerStats) and the images that could not be read.
  nlohmann::json Report(const ObjectLayerStats& stats) const;
  // run.json's timing entry "colour_per_keyframe_image": the mean CPU milliseconds of
  // reading a keyframe's image (when this layer read it: with --modes the first layer
  // does) and of colouring its sightings.
  nlohmann::json Timing(const ObjectLayerStats& stats) const;

 private:
  std::int64_t unreadable_ = 0;
  std::string first_unreadable_;
  double read_seconds_ = 0.0;
};

}  // namespace ocg::app_detail
