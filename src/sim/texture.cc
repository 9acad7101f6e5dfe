#include "ocg/sim/texture.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

namespace ocg::sim {

cv::Mat MakeTexture(std::uint64_t seed, int size, double span_metres) {
  cv::RNG rng(seed * 0x9e3779b97f4a7c15ULL + 1);
  const cv::Scalar base(rng.uniform(40, 215), rng.uniform(40, 215), rng.uniform(40, 215));
  cv::Mat texture(size, size, CV_32FC3, base);
  // Value noise at several scales: no period, so no repeated pattern.
  for (int cells : {4, 9, 23, 61}) {
    cv::Mat coarse(cells, cells, CV_32FC3);
    rng.fill(coarse, cv::RNG::UNIFORM, cv::Scalar::all(-1), cv::Scalar::all(1));
    cv::Mat fine;
    cv::resize(coarse, fine, texture.size(), 0, 0, cv::INTER_CUBIC);
    texture += fine * (cells < 20 ? 35.0 : 18.0);
  }
  cv::Mat image;
  texture.convertTo(image, CV_8UC3);
  const double pixels_per_metre = size / span_metres;
  const double area = span_metres * span_metres;
  // Feature sizes in metres, turned into texels (at least 1).
  auto texels = [&](double low, double high) {
    return std::max(1, static_cast<int>(rng.uniform(low, high) * pixels_per_metre));
  };
  auto count = [&](double per_square_metre, int minimum) {
    return std::max(minimum, static_cast<int>(per_square_metre * area));
  };
  auto colour = [&] {
    return cv::Scalar(rng.uniform(0, 256), rng.uniform(0, 256), rng.uniform(0, 256));
  };
  for (int i = count(60, 14); i > 0; --i) {
    const cv::Point centre(rng.uniform(0, size), rng.uniform(0, size));
    const cv::Size axes(texels(0.01, 0.06), texels(0.01, 0.06));
    cv::ellipse(image, centre, axes, rng.uniform(0, 180), 0, 360, colour(), cv::FILLED,
                cv::LINE_AA);
  }
  for (int i = count(120, 24); i > 0; --i) {
    const cv::Point a(rng.uniform(0, size), rng.uniform(0, size));
    const double length = rng.uniform(0.03, 0.15) * pixels_per_metre;
    const double angle = rng.uniform(0.0, 2 * M_PI);
    const cv::Point b = a + cv::Point(static_cast<int>(length * std::cos(angle)),
                                      static_cast<int>(length * std::sin(angle)));
    cv::line(image, a, b, colour(), texels(0.003, 0.012), cv::LINE_AA);
  }
  static const char kLetters[] = "ABCDEFGHKLMNPRSTUWXYZ0123456789#&@%";
  for (int i = count(60, 14); i > 0; --i) {
    std::string word;
    for (int k = rng.uniform(2, 7); k > 0; --k)
      word += kLetters[rng.uniform(0, sizeof(kLetters) - 1)];
    const cv::Point origin(rng.uniform(-size / 8, size), rng.uniform(0, size + size / 8));
    // Hershey fonts are about 22 units tall at scale 1: letters 2-8 cm high.
    const double letter_height = rng.uniform(0.02, 0.08) * pixels_per_metre;
    cv::putText(image, word, origin, rng.uniform(0, 7), letter_height / 22.0, colour(),
                std::max(1, static_cast<int>(letter_height / 10)), cv::LINE_AA);
  }
  return image;
}

}  // namespace ocg::sim
