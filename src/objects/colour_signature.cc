#include "ocg/objects/colour_signature.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace ocg {
namespace {

// OpenCV's 8-bit HSV: hue 0-179, saturation and value 0-255.
int BinOf(const cv::Vec3b& hsv, const ColourSignatureOptions& options) {
  const double saturation = hsv[1] / 255.0, value = hsv[2] / 255.0;
  if (saturation < options.min_saturation || value < options.min_value) {
    const int grey = std::min(kGreyBins - 1, static_cast<int>(value * kGreyBins));
    return kHueBins * kSaturationBins + grey;
  }
  const int hue = std::min(kHueBins - 1, hsv[0] * kHueBins / 180);
  const double span = (1.0 - options.min_saturation) / kSaturationBins;
  const int level =
      std::min(kSaturationBins - 1, static_cast<int>((saturation - options.min_saturation) / span));
  return hue * kSaturationBins + level;
}

}  // namespace

void ColourSignatureOptions::Check() const {
  if (!(centre_share > 0.0 && centre_share < 1.0))
    throw std::invalid_argument("colour_signature.centre_share must be in (0, 1)");
  if (!(min_saturation >= 0.0 && min_saturation < 1.0))
    throw std::invalid_argument("colour_signature.min_saturation must be in [0, 1)");
  if (!(min_value >= 0.0 && min_value < 1.0))
    throw std::invalid_argument("colour_signature.min_value must be in [0, 1)");
  if (min_box_side < 3) throw std::invalid_argument("colour_signature.min_box_side must be >= 3");
  if (!(min_object_mass > 0.0 && min_object_mass < 1.0))
    throw std::invalid_argument("colour_signature.min_object_mass must be in (0, 1)");
}

std::optional<ColourHistogram> BoxColourSignature(const cv::Mat& bgr, const Box2& box,
                                                  const ColourSignatureOptions& options) {
  if (bgr.type() != CV_8UC3)
    throw std::invalid_argument("BoxColourSignature needs an 8-bit BGR image");
  const int x0 = std::max(0, static_cast<int>(std::floor(box.x0)));
  const int y0 = std::max(0, static_cast<int>(std::floor(box.y0)));
  const int x1 = std::min(bgr.cols, static_cast<int>(std::ceil(box.x1)));
  const int y1 = std::min(bgr.rows, static_cast<int>(std::ceil(box.y1)));
  if (x1 - x0 < options.min_box_side || y1 - y0 < options.min_box_side) return std::nullopt;
  cv::Mat hsv;
  cv::cvtColor(bgr(cv::Rect(x0, y0, x1 - x0, y1 - y0)), hsv, cv::COLOR_BGR2HSV);
  // The centre: centre_share of each side, about the box's middle.
  const double margin = 0.5 * (1.0 - options.centre_share);
  const int cx0 = static_cast<int>(std::lround(margin * hsv.cols));
  const int cx1 = hsv.cols - cx0;
  const int cy0 = static_cast<int>(std::lround(margin * hsv.rows));
  const int cy1 = hsv.rows - cy0;
  std::array<double, kColourBins> centre{}, ring{};
  double centre_count = 0.0, ring_count = 0.0;
  for (int y = 0; y < hsv.rows; ++y) {
    const cv::Vec3b* row = hsv.ptr<cv::Vec3b>(y);
    for (int x = 0; x < hsv.cols; ++x) {
      const int bin = BinOf(row[x], options);
      if (y >= cy0 && y < cy1 && x >= cx0 && x < cx1) {
        centre[static_cast<std::size_t>(bin)] += 1.0;
        centre_count += 1.0;
      } else {
        ring[static_cast<std::size_t>(bin)] += 1.0;
        ring_count += 1.0;
      }
    }
  }
  if (centre_count == 0.0 || ring_count == 0.0) return std::nullopt;
  ColourHistogram signature{};
  double mass = 0.0;
  for (std::size_t b = 0; b < signature.size(); ++b) {
    const double excess = centre[b] / centre_count - ring[b] / ring_count;
    if (excess > 0.0) {
      signature[b] = static_cast<float>(excess);
      mass += excess;
    }
  }
  if (mass < options.min_object_mass) return std::nullopt;
  for (float& share : signature) share = static_cast<float>(share / mass);
  return signature;
}

std::optional<ColourHistogram> MeanColour(const std::vector<ColourHistogram>& signatures) {
  if (signatures.empty()) return std::nullopt;
  std::array<double, kColourBins> sum{};
  for (const ColourHistogram& signature : signatures) {
    for (std::size_t b = 0; b < sum.size(); ++b) sum[b] += signature[b];
  }
  double total = 0.0;
  for (const double share : sum) total += share;
  ColourHistogram mean{};
  if (total <= 0.0) return std::nullopt;
  for (std::size_t b = 0; b < mean.size(); ++b) mean[b] = static_cast<float>(sum[b] / total);
  return mean;
}

double ColourSimilarity(const ColourHistogram& a, const ColourHistogram& b) {
  double shared = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) shared += std::min(a[i], b[i]);
  return shared;
}

}  // namespace ocg
