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

// A frame's filtered detections with the map objects they were associated to.
std::vector<FrameDetection> FrameDetectionsOf(const FrameAssociation& association);

// image: 8-bit grey or BGR. Removed objects are not drawn (they are not there).
// keypoints: the tracked keypoints (pixels; the map points matched in the frame), drawn as
// ORB-SLAM's frame view draws them, green squares; empty for none (pose-given runs).
// A legend in the top-left corner lists what is drawn: the OCG states of the cuboids seen
// and the tracked points (with their count). Labels are placed so that none overlaps
// another (PlaceLabels).
cv::Mat RenderFrameView(const cv::Mat& image, const std::vector<FrameDetection>& detections,
                        const std::vector<ObjectView>& objects, const SE3& T_cw,
                        const PinholeCamera& camera, const Eigen::Vector3d& up,
                        const std::vector<Eigen::Vector2d>& keypoints = {});

}  // namespace ocg
