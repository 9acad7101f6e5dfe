#pragma once
// Images for the feature tests: procedural textures (always there) and the real frames
// of ../shared/data (when present).

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ocg/core/camera.h"

namespace ocg::testing {

// A 640x480 grayscale image of a procedural texture, different for every seed.
cv::Mat TexturedImage(std::uint64_t seed);

// The image warped by a rotation of degrees about its centre and a scale.
cv::Mat RotateAndScale(const cv::Mat& image, double degrees, double scale);
// Where the warp of RotateAndScale sends a pixel.
cv::Point2f WarpPoint(const cv::Point2f& point, const cv::Size& size, double degrees, double scale);

// The real TUM fr3 long_office frames (grayscale), or empty when ../shared/data is absent.
std::vector<cv::Mat> TumFrames();
// The real EuRoC V1_01 frames (grayscale) and their camera, or empty.
std::vector<cv::Mat> EurocFrames(PinholeCamera* camera);

}  // namespace ocg::testing
