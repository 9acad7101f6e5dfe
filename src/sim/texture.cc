#include "ocg/sim/texture.h"

#include <opencv2/imgproc.hpp>

namespace ocg::sim {

cv::Mat MakeTexture(std::uint64_t seed, int size) {
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
  const int scale = std::max(1, size / 256);
  auto colour = [&] {
    return cv::Scalar(rng.uniform(0, 256), rng.uniform(0, 256), rng.uniform(0, 256));
  };
  const int blobs = 12 + rng.uniform(0, 10);
  for (int i = 0; i < blobs * scale; ++i) {
    const cv::Point centre(rng.uniform(0, size), rng.uniform(0, size));
    const cv::Size axes(rng.uniform(4, 28) * scale, rng.uniform(4, 28) * scale);
    cv::ellipse(image, centre, axes, rng.uniform(0, 180), 0, 360, colour(), cv::FILLED,
                cv::LINE_AA);
  }
  const int strokes = 20 + rng.uniform(0, 20);
  for (int i = 0; i < strokes * scale; ++i) {
    const cv::Point a(rng.uniform(0, size), rng.uniform(0, size));
    const cv::Point b = a + cv::Point(rng.uniform(-40, 40) * scale, rng.uniform(-40, 40) * scale);
    cv::line(image, a, b, colour(), rng.uniform(1, 4) * scale, cv::LINE_AA);
  }
  static const char kLetters[] = "ABCDEFGHKLMNPRSTUWXYZ0123456789#&@%";
  const int words = 10 + rng.uniform(0, 10);
  for (int i = 0; i < words * scale; ++i) {
    std::string word;
    for (int k = rng.uniform(2, 7); k > 0; --k)
      word += kLetters[rng.uniform(0, sizeof(kLetters) - 1)];
    const cv::Point origin(rng.uniform(-20, size), rng.uniform(10, size + 20));
    cv::putText(image, word, origin, rng.uniform(0, 7), rng.uniform(0.4, 1.6) * scale, colour(),
                rng.uniform(1, 3) * scale, cv::LINE_AA);
  }
  return image;
}

}  // namespace ocg::sim
