#include "ocg/sim/look.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace ocg::sim {
namespace {

// Exposure at which a frame is recorded as rendered (gain 1, illumination 1).
constexpr double kReferenceExposureMs = 20.0;
// The distorted pixel's ray must be found to this accuracy (pixels), else the lens folds.
constexpr double kUndistortTolerancePixels = 1e-3;

void Require(bool condition, const std::string& field, const std::string& message) {
  if (!condition) throw std::invalid_argument("look." + field + ": " + message);
}

}  // namespace

void LookOptions::Check() const {
  Require(min_exposure_ms > 0 && min_exposure_ms <= max_exposure_ms, "min_exposure_ms",
          "must be positive and at most look.max_exposure_ms");
  Require(max_exposure_ms <= 1000, "max_exposure_ms", "must be at most 1000 ms");
  Require(max_gain >= 1, "max_gain", "must be at least 1");
  Require(target_brightness > 0 && target_brightness < 1, "target_brightness", "must be in (0, 1)");
  Require(exposure_adaptation > 0 && exposure_adaptation <= 1, "exposure_adaptation",
          "must be in (0, 1]");
  Require(illumination_variation >= 0 && illumination_variation < 1, "illumination_variation",
          "must be in [0, 1)");
  Require(vignetting >= 0 && vignetting < 1, "vignetting", "must be in [0, 1)");
  Require(shot_noise >= 0, "shot_noise", "must not be negative");
  Require(read_noise >= 0, "read_noise", "must not be negative");
  Require(optical_blur >= 0 && optical_blur <= 5, "optical_blur", "must be in [0, 5] pixels");
  Require(rolling_shutter_ms >= 0 && rolling_shutter_ms <= 100, "rolling_shutter_ms",
          "must be in [0, 100]");
  Require(max_blur_samples >= 1 && max_blur_samples <= 64, "max_blur_samples",
          "must be in [1, 64]");
  for (double value : {k1, k2, k3, p1, p2})
    Require(std::isfinite(value), "k1..p2", "must be finite");
}

LookKind LookKindFromName(const std::string& name) {
  if (name == "procedural") return LookKind::kProcedural;
  if (name == "realistic") return LookKind::kRealistic;
  throw std::invalid_argument("unknown look '" + name + "' (procedural, realistic)");
}

std::string LookKindName(LookKind kind) {
  return kind == LookKind::kRealistic ? "realistic" : "procedural";
}

PinholeCamera LookCamera(const PinholeCamera& camera, const LookOptions& look) {
  if (!look.realistic()) return camera;
  PinholeCamera distorted = camera;
  distorted.k1 = look.k1;
  distorted.k2 = look.k2;
  distorted.k3 = look.k3;
  distorted.p1 = look.p1;
  distorted.p2 = look.p2;
  return distorted;
}

DistortionMaps MakeDistortionMaps(const PinholeCamera& distorted) {
  const int width = distorted.width, height = distorted.height;
  cv::Mat map_x(height, width, CV_32FC1), map_y(height, width, CV_32FC1);
  double min_u = 0, max_u = width - 1, min_v = 0, max_v = height - 1;
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      const Eigen::Vector3d ray = distorted.Unproject(Eigen::Vector2d(u, v));
      const Eigen::Vector2d back = distorted.Project(ray);
      if (!((back - Eigen::Vector2d(u, v)).norm() < kUndistortTolerancePixels)) {
        throw std::invalid_argument("lens distortion folds over inside the image (pixel " +
                                    std::to_string(u) + ", " + std::to_string(v) +
                                    " has no ray): choose smaller k1, k2, k3");
      }
      const Eigen::Vector2d pinhole = distorted.ProjectUndistorted(ray);
      map_x.at<float>(v, u) = static_cast<float>(pinhole.x());
      map_y.at<float>(v, u) = static_cast<float>(pinhole.y());
      min_u = std::min(min_u, pinhole.x());
      max_u = std::max(max_u, pinhole.x());
      min_v = std::min(min_v, pinhole.y());
      max_v = std::max(max_v, pinhole.y());
    }
  }
  // Two pixels more than needed on each side, for bilinear reads and the optical blur.
  const int left = static_cast<int>(std::ceil(-min_u)) + 2;
  const int top = static_cast<int>(std::ceil(-min_v)) + 2;
  const int right = static_cast<int>(std::ceil(max_u - (width - 1))) + 2;
  const int bottom = static_cast<int>(std::ceil(max_v - (height - 1))) + 2;
  if (left + right > 3 * width || top + bottom > 3 * height) {
    throw std::invalid_argument(
        "lens distortion needs a pinhole image over four times the size: choose smaller k1, k2, "
        "k3");
  }
  DistortionMaps maps;
  maps.pinhole = distorted;
  maps.pinhole.k1 = maps.pinhole.k2 = maps.pinhole.k3 = maps.pinhole.p1 = maps.pinhole.p2 = 0.0;
  maps.pinhole.width = width + left + right;
  maps.pinhole.height = height + top + bottom;
  maps.pinhole.cx += left;
  maps.pinhole.cy += top;
  maps.map_x = map_x + static_cast<float>(left);
  maps.map_y = map_y + static_cast<float>(top);
  return maps;
}

FastStatistics MeasureFast(const cv::Mat& image) {
  cv::Mat grey = image;
  if (image.channels() == 3) cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  const cv::Rect region(kFastImageBorder, kFastImageBorder, grey.cols - 2 * kFastImageBorder,
                        grey.rows - 2 * kFastImageBorder);
  std::vector<cv::KeyPoint> corners;
  cv::FAST(grey(region), corners, kFastThreshold, true);
  std::vector<char> occupied(kGridColumns * kGridRows, 0);
  for (const cv::KeyPoint& corner : corners) {
    const int column =
        static_cast<int>((corner.pt.x + kFastImageBorder) * kGridColumns / grey.cols);
    const int row = static_cast<int>((corner.pt.y + kFastImageBorder) * kGridRows / grey.rows);
    occupied[static_cast<std::size_t>(row * kGridColumns + column)] = 1;
  }
  FastStatistics statistics;
  statistics.corners = static_cast<int>(corners.size());
  statistics.cell_share =
      static_cast<double>(std::count(occupied.begin(), occupied.end(), 1)) / occupied.size();
  return statistics;
}

FastSummary Summarize(const std::vector<FastStatistics>& frames) {
  FastSummary summary;
  summary.frames = static_cast<int>(frames.size());
  if (frames.empty()) return summary;
  summary.min_corners = summary.max_corners = frames.front().corners;
  summary.min_cell_share = frames.front().cell_share;
  for (const FastStatistics& frame : frames) {
    summary.mean_corners += frame.corners;
    summary.mean_cell_share += frame.cell_share;
    summary.min_corners = std::min(summary.min_corners, frame.corners);
    summary.max_corners = std::max(summary.max_corners, frame.corners);
    summary.min_cell_share = std::min(summary.min_cell_share, frame.cell_share);
  }
  summary.mean_corners /= frames.size();
  summary.mean_cell_share /= frames.size();
  return summary;
}

// ---------------------------------------------------------------- CameraSensor

CameraSensor::CameraSensor(const LookOptions& look, const PinholeCamera& distorted,
                           std::uint64_t seed)
    : look_(look),
      maps_(MakeDistortionMaps(distorted)),
      seed_(seed),
      exposure_ms_(std::clamp(kReferenceExposureMs, look.min_exposure_ms, look.max_exposure_ms)),
      reference_exposure_ms_(kReferenceExposureMs) {
  look.Check();
  cv::convertMaps(maps_.map_x, maps_.map_y, fixed_x_, fixed_y_, CV_16SC2);
  // Relative illumination falls with the squared distance from the principal point,
  // by `vignetting` in the farthest corner.
  const int width = distorted.width, height = distorted.height;
  const double corner = std::hypot(std::max(distorted.cx, width - 1 - distorted.cx),
                                   std::max(distorted.cy, height - 1 - distorted.cy));
  cv::Mat falloff(height, width, CV_32FC1);
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      const double r = std::hypot(u - distorted.cx, v - distorted.cy) / corner;
      falloff.at<float>(v, u) = static_cast<float>(1.0 - look.vignetting * r * r);
    }
  }
  cv::merge(std::vector<cv::Mat>{falloff, falloff, falloff}, vignette_);
  noise_tile_.create(2 * height, 2 * width, CV_32FC3);
  cv::RNG(seed * 0x9e3779b97f4a7c15ULL + 7)
      .fill(noise_tile_, cv::RNG::NORMAL, cv::Scalar::all(0), cv::Scalar::all(1));
}

std::vector<double> CameraSensor::SampleTimes(double pixels_per_second) const {
  const double exposure = exposure_ms_ / 1000.0;
  const double readout = look_.rolling_shutter_ms / 1000.0;
  // One render per two pixels of motion over the exposure: with the optical blur the
  // average reads as a smear, not a row of ghosts, at a third of the cost of one per pixel.
  constexpr double kPixelsPerSample = 2.0;
  const int blur_samples =
      std::clamp(static_cast<int>(std::ceil(pixels_per_second * exposure / kPixelsPerSample)), 1,
                 look_.max_blur_samples);
  const double spacing = exposure / blur_samples;
  const double span = exposure + readout;
  const int samples = std::max(1, static_cast<int>(std::ceil(span / spacing - 1e-9)));
  std::vector<double> times;
  for (int i = 0; i < samples; ++i) times.push_back(-span / 2 + (i + 0.5) * span / samples);
  return times;
}

cv::Mat CameraSensor::Record(const std::vector<cv::Mat>& renders, const std::vector<double>& times,
                             double t, std::uint64_t frame_seed) {
  assert(!renders.empty() && renders.size() == times.size());
  const int rows = renders.front().rows;
  const double exposure = exposure_ms_ / 1000.0;
  const double readout = look_.rolling_shutter_ms / 1000.0;
  // Each row integrates the renders inside its own exposure window (all of them with a
  // global shutter); rows are read out top first.
  cv::Mat sum(renders.front().size(), CV_32FC3, cv::Scalar::all(0));
  std::vector<int> count(static_cast<std::size_t>(rows), 0);
  for (std::size_t s = 0; s < renders.size(); ++s) {
    int first = 0, last = rows;  // rows [first, last) see this render
    if (readout > 0) {
      auto row_time = [&](int row) { return readout * ((row + 0.5) / rows - 0.5); };
      while (first < rows && row_time(first) < times[s] - exposure / 2 - 1e-12) ++first;
      last = first;
      while (last < rows && row_time(last) <= times[s] + exposure / 2 + 1e-12) ++last;
    }
    if (first >= last) continue;
    cv::Mat band = sum.rowRange(first, last);
    cv::Mat source;
    renders[s].rowRange(first, last).convertTo(source, CV_32FC3);
    band += source;
    for (int row = first; row < last; ++row) ++count[static_cast<std::size_t>(row)];
  }
  for (int row = 0; row < rows; ++row) {
    assert(count[static_cast<std::size_t>(row)] > 0);
    sum.row(row) *= 1.0 / std::max(1, count[static_cast<std::size_t>(row)]);
  }
  if (look_.optical_blur > 0) cv::GaussianBlur(sum, sum, cv::Size(), look_.optical_blur);
  cv::Mat image;
  cv::remap(sum, image, fixed_x_, fixed_y_, cv::INTER_LINEAR, cv::BORDER_REPLICATE);

  // Smooth seeded drift of the light (two slow waves with seeded phases).
  const double phase_a = static_cast<double>(seed_ % 1000) * 0.00628;
  const double phase_b = static_cast<double>((seed_ / 1000) % 1000) * 0.00628;
  const double illumination =
      1.0 + look_.illumination_variation * (0.6 * std::sin(2 * M_PI * t / 23.0 + phase_a) +
                                            0.4 * std::sin(2 * M_PI * t / 7.3 + phase_b));
  const double scale = illumination * exposure_ms_ / reference_exposure_ms_ * gain_;
  cv::multiply(image, vignette_, image, scale);
  const cv::Scalar mean = cv::mean(image);
  const double mean_brightness = (mean[0] + mean[1] + mean[2]) / (3 * 255.0);

  // Shot noise grows with the signal, read noise does not; the gain amplifies both.
  cv::Mat variance = image * (look_.shot_noise * gain_);
  variance += cv::Scalar::all(look_.read_noise * look_.read_noise * gain_ * gain_);
  cv::Mat sigma;
  cv::sqrt(cv::max(variance, 0.0), sigma);
  const int dx = static_cast<int>(frame_seed % static_cast<std::uint64_t>(image.cols));
  const int dy = static_cast<int>((frame_seed >> 20) % static_cast<std::uint64_t>(image.rows));
  cv::Mat noise;
  cv::multiply(sigma, noise_tile_(cv::Rect(dx, dy, image.cols, image.rows)), noise);
  image += noise;
  cv::Mat recorded;
  image.convertTo(recorded, CV_8UC3);  // saturates: clipped highlights, as a sensor does

  // Auto-exposure: move the product exposure x gain part of the way (in log) towards the
  // target brightness; exposure first, gain only once the exposure is at its longest.
  const double wanted =
      std::clamp(look_.target_brightness / std::max(mean_brightness, 1e-3), 0.25, 4.0);
  const double product = exposure_ms_ * gain_ * std::pow(wanted, look_.exposure_adaptation);
  exposure_ms_ = std::clamp(product, look_.min_exposure_ms, look_.max_exposure_ms);
  gain_ = std::clamp(product / exposure_ms_, 1.0, look_.max_gain);
  return recorded;
}

cv::Mat CameraSensor::Distort(const cv::Mat& pinhole_image) const {
  // remap takes no 32-bit integers; ids up to 2^24 are exact as floats.
  const bool integers = pinhole_image.depth() == CV_32S;
  cv::Mat source = pinhole_image;
  if (integers) pinhole_image.convertTo(source, CV_32F);
  cv::Mat distorted;
  cv::remap(source, distorted, maps_.map_x, maps_.map_y, cv::INTER_NEAREST, cv::BORDER_CONSTANT,
            cv::Scalar::all(0));
  if (integers) distorted.convertTo(distorted, CV_32S);
  return distorted;
}

}  // namespace ocg::sim
