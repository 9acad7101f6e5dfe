#pragma once
// How rendered frames look. The procedural look (the default) is the saturated, densely
// textured one the generator always had; the realistic look imitates a hand-held consumer
// RGB camera (TUM fr1-like): natural materials, motion blur over the exposure from the
// true camera motion, auto-exposure and gain, vignetting, lens distortion, shot and read
// noise, optionally a rolling shutter. docs/synthetic.md shows both.

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "ocg/core/camera.h"

namespace ocg::sim {

enum class LookKind { kProcedural, kRealistic };

// Settings of the realistic look (scene file section `look:`); ignored by the procedural one.
struct LookOptions {
  LookKind kind = LookKind::kProcedural;
  // Auto-exposure keeps the mean brightness near target_brightness (share of white) with
  // an exposure time in [min_exposure_ms, max_exposure_ms], then gain up to max_gain.
  double min_exposure_ms = 10.0;
  double max_exposure_ms = 30.0;
  double max_gain = 4.0;
  double target_brightness = 0.5;
  double exposure_adaptation = 0.35;  // share of the log error corrected per frame
  // Scene illumination drifts smoothly by up to this share (lamps, daylight), so the
  // auto-exposure has something to follow.
  double illumination_variation = 0.25;
  // Brightness lost in the image corners (1 - relative illumination there).
  double vignetting = 0.35;
  // Shot noise: variance in grey levels per grey level at gain 1; read noise: std in
  // grey levels at gain 1 (both grow with the gain).
  double shot_noise = 0.06;
  double read_noise = 1.2;
  // Gaussian point spread of the lens and demosaicing, pixels.
  double optical_blur = 0.5;
  // Rows are read out over this time, top first (0: global shutter).
  double rolling_shutter_ms = 0.0;
  // At most this many renders are averaged over one exposure (more for faster motion).
  int max_blur_samples = 6;
  // Lens distortion written into camera.yaml and applied to the images: TUM fr1's
  // calibration (ORB-SLAM2's TUM1.yaml).
  double k1 = 0.262383, k2 = -0.953104, k3 = 1.163314, p1 = -0.005358, p2 = 0.002628;

  bool realistic() const { return kind == LookKind::kRealistic; }
  // Throws std::invalid_argument naming the field (look.*) when a value is impossible.
  void Check() const;
};

// "procedural" or "realistic"; throws std::invalid_argument naming the valid names.
LookKind LookKindFromName(const std::string& name);
std::string LookKindName(LookKind kind);

// Camera with the look's distortion (the realistic look) or unchanged (procedural).
PinholeCamera LookCamera(const PinholeCamera& camera, const LookOptions& look);

// Where each pixel of the distorted camera's image comes from in an ideal pinhole render.
// The pinhole camera has the same focal lengths and is enlarged (margin) so that every
// distorted pixel's ray falls inside it.
struct DistortionMaps {
  PinholeCamera pinhole;  // the camera to render with (no distortion)
  cv::Mat map_x, map_y;   // CV_32FC1, distorted image size: source pixel in the pinhole render
};
// Throws std::invalid_argument if the distortion folds over inside the image (a ray that
// would need a pinhole image over four times the size).
DistortionMaps MakeDistortionMaps(const PinholeCamera& distorted);

// FAST corner statistics of images, measured as our ORB extractor detects on its first
// level: grey image, threshold kFastThreshold (ORBextractor.iniThFAST) with non-maximum
// suppression, corners within the extractor's border (kFastImageBorder pixels) only.
struct FastStatistics {
  int corners = 0;
  double cell_share = 0.0;  // share of the 8 x 6 grid's cells with at least one corner
};
constexpr int kFastThreshold = 20;
constexpr int kFastImageBorder = 16;
constexpr int kGridColumns = 8;
constexpr int kGridRows = 6;
FastStatistics MeasureFast(const cv::Mat& image);  // BGR or grey, 8-bit

struct FastSummary {
  int frames = 0;
  double mean_corners = 0.0;
  int min_corners = 0;
  int max_corners = 0;
  double mean_cell_share = 0.0;
  double min_cell_share = 0.0;
};
FastSummary Summarize(const std::vector<FastStatistics>& frames);

// The realistic camera: turns ideal renders into what the sensor records. Stateful (the
// auto-exposure follows the frames in order); deterministic in its seed.
class CameraSensor {
 public:
  CameraSensor(const LookOptions& look, const PinholeCamera& distorted, std::uint64_t seed);

  const DistortionMaps& maps() const { return maps_; }
  // Exposure time (ms) and gain the next frame will use.
  double exposure_ms() const { return exposure_ms_; }
  double gain() const { return gain_; }
  // Times (seconds, relative to the frame's time) at which to render the pinhole
  // images for a frame, given the largest image motion in pixels per second.
  std::vector<double> SampleTimes(double pixels_per_second) const;
  // Records a frame from renders at SampleTimes (BGR 8-bit, pinhole size), at time t on
  // the sequence's clock (illumination drift), then adapts the exposure. frame_seed
  // picks the noise.
  cv::Mat Record(const std::vector<cv::Mat>& renders, const std::vector<double>& times, double t,
                 std::uint64_t frame_seed);
  // Id or depth image of the pinhole render seen through the distorted lens (nearest).
  cv::Mat Distort(const cv::Mat& pinhole_image) const;

 private:
  LookOptions look_;
  DistortionMaps maps_;
  cv::Mat fixed_x_, fixed_y_;  // maps in OpenCV's fast fixed-point form
  cv::Mat vignette_;           // CV_32FC3 relative illumination
  cv::Mat noise_tile_;         // CV_32FC3 standard normal, twice the image size
  std::uint64_t seed_;
  double exposure_ms_;
  double gain_ = 1.0;
  double reference_exposure_ms_;
};

}  // namespace ocg::sim
