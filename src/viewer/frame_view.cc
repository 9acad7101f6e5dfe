#include "ocg/viewer/frame_view.h"

#include <algorithm>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "drawing.h"
#include "ocg/core/coco.h"
#include "ocg/viewer/label_layout.h"

namespace ocg {
namespace {

cv::Point ToPoint(const Eigen::Vector2d& pixel) {
  return {static_cast<int>(std::lround(pixel.x())), static_cast<int>(std::lround(pixel.y()))};
}

// ORB-SLAM2's frame view colour of the keypoints matched to map points.
const cv::Scalar kKeypointColour(0, 255, 0);

}  // namespace

std::vector<FrameDetection> FrameDetectionsOf(const FrameAssociation& association) {
  std::vector<FrameDetection> detections;
  for (const ObjectDetection& detection : association.detections)
    detections.push_back({detection.box, detection.class_id, detection.confidence, 0});
  for (const auto& [index, id] : association.matched) {
    if (index >= 0) detections[static_cast<std::size_t>(index)].object_id = id;
  }
  return detections;
}

cv::Mat RenderFrameView(const cv::Mat& image, const std::vector<FrameDetection>& detections,
                        const std::vector<ObjectView>& objects, const SE3& T_cw,
                        const PinholeCamera& camera, const Eigen::Vector3d& up,
                        const std::vector<Eigen::Vector2d>& keypoints) {
  cv::Mat view;
  if (image.channels() == 1) {
    cv::cvtColor(image, view, cv::COLOR_GRAY2BGR);
  } else {
    view = image.clone();
  }
  // As ORB-SLAM2 draws them: a square of 5 pixels round the keypoint and a dot on it.
  for (const Eigen::Vector2d& keypoint : keypoints) {
    const cv::Point at = ToPoint(keypoint);
    cv::rectangle(view, cv::Point(at.x - 5, at.y - 5), cv::Point(at.x + 5, at.y + 5),
                  kKeypointColour, 1);
    cv::circle(view, at, 2, kKeypointColour, cv::FILLED);
  }
  const Eigen::Matrix3d R_wg = GravityFrame(up);
  bool drawn_state[5] = {};
  for (const ObjectView& object : objects) {
    if (object.removed) continue;
    const cv::Scalar colour = ToBgr(StateColour(object.state, false));
    for (const auto& [a, b] : CuboidEdges(object.cuboid, R_wg)) {
      const Eigen::Vector3d a_c = T_cw * a, b_c = T_cw * b;
      if (a_c.z() <= 0.05 || b_c.z() <= 0.05) continue;  // behind the camera
      const cv::Point pa = ToPoint(camera.ProjectUndistorted(a_c));
      const cv::Point pb = ToPoint(camera.ProjectUndistorted(b_c));
      cv::Point ca = pa, cb = pb;
      if (!cv::clipLine(view.size(), ca, cb)) continue;  // outside the image
      cv::line(view, pa, pb, colour, 2, cv::LINE_AA);
      if (object.state >= 0 && object.state < 5) drawn_state[object.state] = true;
    }
  }
  std::vector<std::pair<std::string, cv::Point>> labels;
  for (const FrameDetection& detection : detections) {
    const cv::Rect rect(
        cv::Point(static_cast<int>(detection.box.x0), static_cast<int>(detection.box.y0)),
        cv::Point(static_cast<int>(detection.box.x1), static_cast<int>(detection.box.y1)));
    cv::rectangle(view, rect, cv::Scalar(255, 255, 255), 3);
    cv::rectangle(view, rect, cv::Scalar(0, 0, 0), 1);
    char confidence[16];
    std::snprintf(confidence, sizeof confidence, " %.2f", detection.confidence);
    labels.emplace_back(
        (detection.object_id > 0 ? "#" + std::to_string(detection.object_id) + " " : "") +
            CocoClassName(detection.class_id) + confidence,
        cv::Point(rect.x - 2, rect.y));
  }
  std::vector<LegendEntry> legend;
  AddStateEntries(legend, drawn_state, LegendEntry::Mark::kLine,
                  [](int state) { return StateColour(state, false); });
  if (!detections.empty())
    legend.push_back({LegendEntry::Mark::kOutline, cv::Scalar(0, 0, 0), "detections"});
  if (!keypoints.empty())
    legend.push_back({LegendEntry::Mark::kPoint, kKeypointColour,
                      "tracked map points (" + std::to_string(keypoints.size()) + ")"});
  const cv::Rect legend_box = LegendBox(legend);
  if (legend_box.area() > 0) {
    // A light panel under the legend: it must read on any image.
    cv::Mat panel = view(legend_box & cv::Rect(0, 0, view.cols, view.rows));
    panel.convertTo(panel, -1, 0.35, 0.65 * 255);
  }
  std::vector<cv::Rect> obstacles;
  if (legend_box.area() > 0) obstacles.push_back(legend_box);
  DrawLabels(view, LayOutLabels(labels, view.size(), obstacles));
  DrawLegend(view, legend);
  return view;
}

}  // namespace ocg
