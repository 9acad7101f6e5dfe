#pragma once
// The frame view: the current image with its detections, the map object each one was
// associated to, and the objects' cuboids projected into it, coloured by OCG state.
// Drawn with OpenCV (no GL context needed).

#include <vector>

#include <opencv2/core.hpp>

#include "ocg/viewer/map_view.h"

namespace ocg {

struct FrameDetection {
  Box2 box;
  int class_id = 0;
  double confidence = 0.0;
  std::int64_t object_id = 0;  // the associated map object; 0 when none (a candidate)
};

// image: 8-bit grey or BGR. Removed objects are not drawn (they are not there).
cv::Mat RenderFrameView(const cv::Mat& image, const std::vector<FrameDetection>& detections,
                        const std::vector<ObjectView>& objects, const SE3& T_cw,
                        const PinholeCamera& camera, const Eigen::Vector3d& up);

}  // namespace ocg
