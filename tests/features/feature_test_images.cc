#include "feature_test_images.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "ocg/io/sequence.h"
#include "ocg/sim/texture.h"
#include "test_support.h"

namespace ocg::testing {

cv::Mat TexturedImage(std::uint64_t seed) {
  const cv::Mat texture = sim::MakeTexture(seed, 640, 1.5);
  cv::Mat gray;
  cv::cvtColor(texture(cv::Rect(0, 80, 640, 480)), gray, cv::COLOR_BGR2GRAY);
  return gray;
}

namespace {
cv::Mat WarpMatrix(const cv::Size& size, double degrees, double scale) {
  return cv::getRotationMatrix2D(cv::Point2f(size.width / 2.0f, size.height / 2.0f), degrees,
                                 scale);
}
}  // namespace

cv::Mat RotateAndScale(const cv::Mat& image, double degrees, double scale) {
  cv::Mat warped;
  cv::warpAffine(image, warped, WarpMatrix(image.size(), degrees, scale), image.size(),
                 cv::INTER_LINEAR, cv::BORDER_REFLECT_101);
  return warped;
}

cv::Point2f WarpPoint(const cv::Point2f& point, const cv::Size& size, double degrees,
                      double scale) {
  const cv::Mat m = WarpMatrix(size, degrees, scale);
  return {static_cast<float>(m.at<double>(0, 0) * point.x + m.at<double>(0, 1) * point.y +
                             m.at<double>(0, 2)),
          static_cast<float>(m.at<double>(1, 0) * point.x + m.at<double>(1, 1) * point.y +
                             m.at<double>(1, 2))};
}

std::vector<cv::Mat> TumFrames() {
  std::vector<cv::Mat> frames;
  const auto data = SharedDataDir();
  if (!data) return frames;
  for (const TimedImage& image : ReadTumSequence(*data + "/tum_fr3_long_office").images) {
    frames.push_back(cv::imread(image.path, cv::IMREAD_GRAYSCALE));
  }
  return frames;
}

std::vector<cv::Mat> EurocFrames(PinholeCamera* camera) {
  std::vector<cv::Mat> frames;
  const auto data = SharedDataDir();
  if (!data) return frames;
  const ImageSequence sequence = ReadEurocSequence(*data + "/euroc_v101_micro");
  *camera = *sequence.camera;
  for (const TimedImage& image : sequence.images) {
    frames.push_back(cv::imread(image.path, cv::IMREAD_GRAYSCALE));
  }
  return frames;
}

}  // namespace ocg::testing
