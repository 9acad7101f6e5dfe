#pragma once
// 2-D drawing shared by the map and frame views (internal to viewer).

#include <Eigen/Core>
#include <opencv2/imgproc.hpp>
#include <string>

namespace ocg {

// An RGB colour in [0, 1] as OpenCV's BGR in [0, 255].
inline cv::Scalar ToBgr(const Eigen::Vector3f& rgb) {
  return cv::Scalar(255.0 * rgb.z(), 255.0 * rgb.y(), 255.0 * rgb.x());
}

// Black text with a white outline: readable on any background.
inline void DrawLabel(cv::Mat& image, const std::string& text, const cv::Point& at) {
  const int font = cv::FONT_HERSHEY_SIMPLEX;
  const double scale = 0.45;
  cv::putText(image, text, at, font, scale, cv::Scalar(255, 255, 255), 3, cv::LINE_AA);
  cv::putText(image, text, at, font, scale, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
}

}  // namespace ocg
