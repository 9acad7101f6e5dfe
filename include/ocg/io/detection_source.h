#pragma once
// Where a run's 2-D detections come from: files written beforehand by any detector, or a
// detector run on the frame itself (ocg/detect/detection_model.h). The SLAM loop asks
// one source per frame and does not care which.

#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

#include "ocg/io/detections.h"

namespace ocg {

class DetectionSource {
 public:
  virtual ~DetectionSource() = default;
  // The detections of one frame, boxes in the frame's pixels (x y the top-left corner),
  // COCO-80 class ids. timestamp_text: the frame's time exactly as in rgb.txt (the name of
  // its detection file). image: the frame as read from disk (8-bit, 1 or 3 channels BGR);
  // sources that read files may ignore it. Not safe to call from two threads at once
  // unless the implementation says so.
  virtual std::vector<Detection> DetectionsFor(const std::string& timestamp_text,
                                               const cv::Mat& image) = 0;
};

// Detection files read beforehand (EaoDetectionFolder checks them all at start).
class FolderDetectionSource : public DetectionSource {
 public:
  explicit FolderDetectionSource(const EaoDetectionFolder& folder) : folder_(folder) {}
  std::vector<Detection> DetectionsFor(const std::string& timestamp_text,
                                       const cv::Mat& /*image*/) override {
    return folder_.ForFrame(timestamp_text);
  }

 private:
  const EaoDetectionFolder& folder_;
};

}  // namespace ocg
