#include "ocg/viewer/frame_view.h"

#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "drawing.h"
#include "ocg/core/coco.h"

namespace ocg {
namespace {

cv::Point ToPoint(const Eigen::Vector2d& pixel) {
  return {static_cast<int>(std::lround(pixel.x())), static_cast<int>(std::lround(pixel.y()))};
}

}  // namespace

cv::Mat RenderFrameView(const cv::Mat& image, const std::vector<FrameDetection>& detections,
                        const std::vector<ObjectView>& objects, const SE3& T_cw,
                        const PinholeCamera& camera, const Eigen::Vector3d& up) {
  cv::Mat view;
  if (image.channels() == 1) {
    cv::cvtColor(image, view, cv::COLOR_GRAY2BGR);
  } else {
    view = image.clone();
  }
  const Eigen::Matrix3d R_wg = GravityFrame(up);
  for (const ObjectView& object : objects) {
    if (object.removed) continue;
    const cv::Scalar colour = ToBgr(StateColour(object.state, false));
    for (const auto& [a, b] : CuboidEdges(object.cuboid, R_wg)) {
      const Eigen::Vector3d a_c = T_cw * a, b_c = T_cw * b;
      if (a_c.z() <= 0.05 || b_c.z() <= 0.05) continue;  // behind the camera
      cv::line(view, ToPoint(camera.ProjectUndistorted(a_c)),
               ToPoint(camera.ProjectUndistorted(b_c)), colour, 2, cv::LINE_AA);
    }
  }
  for (const FrameDetection& detection : detections) {
    const cv::Rect rect(
        cv::Point(static_cast<int>(detection.box.x0), static_cast<int>(detection.box.y0)),
        cv::Point(static_cast<int>(detection.box.x1), static_cast<int>(detection.box.y1)));
    cv::rectangle(view, rect, cv::Scalar(255, 255, 255), 3);
    cv::rectangle(view, rect, cv::Scalar(0, 0, 0), 1);
    char confidence[16];
    std::snprintf(confidence, sizeof confidence, " %.2f", detection.confidence);
    const std::string label =
        (detection.object_id > 0 ? "#" + std::to_string(detection.object_id) + " " : "") +
        CocoClassName(detection.class_id) + confidence;
    DrawLabel(view, label, cv::Point(rect.x + 2, std::max(12, rect.y - 4)));
  }
  return view;
}

}  // namespace ocg
