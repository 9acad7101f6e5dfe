// The realistic look: image statistics against real TUM frames, motion blur, lens
// distortion, auto-exposure, vignetting, rolling shutter and reproducibility.

#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "ocg/app/settings.h"
#include "ocg/core/file_io.h"
#include "ocg/sim/generator.h"
#include "ocg/sim/look.h"
#include "test_support.h"

namespace ocg::sim {
namespace {

namespace fs = std::filesystem;

// The 20 real frames of TUM fr3 long_office measured with MeasureFast (ocg_synth
// --measure ../shared/data/tum_fr3_long_office), used when the data is absent.
constexpr double kTumMeanCorners = 1066;
constexpr double kTumMeanCellShare = 0.86;
constexpr double kBand = 0.2;  // the calibration band: within 20 %

struct Reference {
  double mean_corners = kTumMeanCorners;
  double mean_cell_share = kTumMeanCellShare;
};

Reference TumReference() {
  Reference reference;
  const std::optional<std::string> data = testing::SharedDataDir();
  if (!data) return reference;
  std::vector<FastStatistics> frames;
  for (const auto& entry : fs::directory_iterator(*data + "/tum_fr3_long_office/rgb")) {
    frames.push_back(MeasureFast(cv::imread(entry.path().string(), cv::IMREAD_COLOR)));
  }
  const FastSummary summary = Summarize(frames);
  if (summary.frames == 0) return reference;
  reference.mean_corners = summary.mean_corners;
  reference.mean_cell_share = summary.mean_cell_share;
  return reference;
}

Scene Realistic(Scene scene) {
  scene.look.kind = LookKind::kRealistic;
  return scene;
}

TEST(RealisticLook, FastStatisticsWithinTheBandOfRealFrames) {
  const Reference real = TumReference();
  for (const std::string name : {"straight_1", "round_2"}) {
    const Scene scene = Realistic(MakePreset(name, 1));
    SceneRenderer renderer(scene);
    std::vector<FastStatistics> frames;
    constexpr int kSamples = 6;
    for (int k = 0; k < kSamples; ++k) {
      const double t = scene.duration * (k + 0.5) / kSamples;
      frames.push_back(
          MeasureFast(renderer.Colour(t, CameraPoseAt(scene, t), static_cast<std::uint64_t>(k))));
    }
    const FastSummary summary = Summarize(frames);
    std::cout << name << ": FAST corners mean " << summary.mean_corners << " (min "
              << summary.min_corners << ", max " << summary.max_corners << "), cells "
              << summary.mean_cell_share << "; real " << real.mean_corners << ", "
              << real.mean_cell_share << "\n";
    EXPECT_NEAR(summary.mean_corners, real.mean_corners, kBand * real.mean_corners) << name;
    EXPECT_NEAR(summary.mean_cell_share, real.mean_cell_share, kBand * real.mean_cell_share)
        << name;
  }
}

// A scene whose camera passes the same place at two speeds (no wobble), noise-free and
// with a fixed exposure, so only the motion differs.
Scene SpeedScene(double speed) {
  Scene scene = Realistic(MakePreset("smoke", 1));
  scene.fps = 30;
  scene.path.speed = speed;
  scene.path.jitter = 0.0;
  scene.look.min_exposure_ms = scene.look.max_exposure_ms = 30.0;
  scene.look.shot_noise = scene.look.read_noise = 0.0;
  scene.look.illumination_variation = 0.0;
  return scene;
}

// The same place seen at a speed (metres per second; 0: a still camera).
cv::Mat FrameAtSpeed(double speed) {
  Scene scene = SpeedScene(speed > 0 ? speed : 0.1);
  if (speed == 0) scene.look.max_blur_samples = 1;  // one render at mid-exposure
  SceneRenderer renderer(scene);
  const double t = 0.6 / scene.path.speed;  // 0.6 m along the path
  return renderer.Colour(t, CameraPoseAt(scene, t), 1);
}

TEST(RealisticLook, MotionBlurGrowsWithCameraSpeed) {
  // Blur is the departure from the still image of the same pose.
  const cv::Mat still = FrameAtSpeed(0.0);
  double previous = 0.0;
  for (double speed : {0.15, 0.25, 0.4}) {  // image motion over 30 ms: 2.4, 4 and 6.4 px
    cv::Mat difference;
    cv::absdiff(FrameAtSpeed(speed), still, difference);
    const cv::Scalar mean = cv::mean(difference);
    const double blur = mean[0] + mean[1] + mean[2];
    EXPECT_GT(blur, previous * 1.5 + 0.01) << "speed " << speed << " m/s";
    previous = blur;
  }
  // More renders per exposure for faster image motion.
  CameraSensor sensor(SpeedScene(0.4).look, OutputCamera(SpeedScene(0.4)), 1);
  EXPECT_EQ(sensor.SampleTimes(0.0).size(), 1u);
  EXPECT_GT(sensor.SampleTimes(200.0).size(), 2u);
}

// The camera looks down at a tilted floor: every pixel's depth there tells where its ray
// goes, so the rendered depth checks the lens model of camera.yaml pixel by pixel.
TEST(RealisticLook, CameraYamlDistortionMatchesTheRenderedGeometry) {
  Scene scene = Realistic(MakePreset("smoke", 1));
  scene.objects.clear();
  scene.furniture.erase(std::remove_if(scene.furniture.begin(), scene.furniture.end(),
                                       [](const Furniture& item) { return item.name != "floor"; }),
                        scene.furniture.end());
  const PinholeCamera lens =
      ParseSettings(CameraSettingsYaml(scene), "camera.yaml").settings.camera.model;
  ASSERT_TRUE(lens.HasDistortion());
  EXPECT_NEAR(lens.k1, 0.262383, 1e-6);
  EXPECT_NEAR(lens.k2, -0.953104, 1e-6);
  SceneRenderer renderer(scene);
  const SE3 T_cw = LookAt({0.0, -1.0, 1.2}, {0.0, 0.2, 0.0});
  cv::Mat depth;
  renderer.Ids(0.0, T_cw, &depth);
  ASSERT_EQ(depth.cols, lens.width);
  const SE3 T_wc = T_cw.Inverse();
  const PinholeCamera pinhole = [&] {
    PinholeCamera ideal = lens;
    ideal.k1 = ideal.k2 = ideal.k3 = ideal.p1 = ideal.p2 = 0.0;
    return ideal;
  }();
  double worst_lens = 0.0, worst_pinhole = 0.0;
  for (int v = 20; v < lens.height; v += 40) {
    for (int u = 20; u < lens.width; u += 40) {
      const float rendered = depth.at<float>(v, u);
      ASSERT_GT(rendered, 0.0f) << u << ", " << v;
      // The floor point z = 0 on each model's ray; its depth against the rendered one.
      for (const PinholeCamera* model : {&lens, &pinhole}) {
        const Eigen::Vector3d ray = model->Unproject(Eigen::Vector2d(u, v));  // z = 1
        const Eigen::Vector3d origin = T_wc.translation();
        const Eigen::Vector3d direction = T_wc.rotation() * ray;
        const double depth_on_floor = -origin.z() / direction.z();
        const double error = std::abs(depth_on_floor - rendered) / rendered;
        double& worst = model == &lens ? worst_lens : worst_pinhole;
        worst = std::max(worst, error);
      }
    }
  }
  EXPECT_LT(worst_lens, 0.004);    // nearest-pixel lookup of a pinhole render
  EXPECT_GT(worst_pinhole, 0.02);  // the distortion is visible: the ideal model misses
}

TEST(RealisticLook, SameSeedSameFramesOtherSeedOtherFrames) {
  GeneratorOptions options;
  options.max_frames = 3;
  options.keyframe_interval = 0;
  const std::string dir = testing::MakeTempDir("look");
  for (const auto& [folder, seed] : {std::pair{"a", 3}, std::pair{"b", 3}, std::pair{"c", 4}}) {
    Scene scene = Realistic(MakePreset("smoke", static_cast<std::uint64_t>(seed)));
    Generate(scene, dir + "/" + folder, options);
  }
  for (const char* file : {"rgb/1000.100000.png", "exposure.txt", "camera.yaml"}) {
    EXPECT_EQ(ReadTextFile(dir + "/a/" + file), ReadTextFile(dir + "/b/" + file)) << file;
  }
  EXPECT_NE(ReadTextFile(dir + "/a/rgb/1000.100000.png"),
            ReadTextFile(dir + "/c/rgb/1000.100000.png"));
}

// CameraSensor alone, on constant renders: exact expectations.
PinholeCamera SmallCamera() {
  PinholeCamera camera = testing::TestCamera(160.0, 80.0, 60.0);
  camera.width = 160;
  camera.height = 120;
  return camera;
}

LookOptions QuietLook() {
  LookOptions look;
  look.kind = LookKind::kRealistic;
  look.shot_noise = look.read_noise = look.optical_blur = 0.0;
  look.illumination_variation = 0.0;
  look.k1 = look.k2 = look.k3 = look.p1 = look.p2 = 0.0;
  return look;
}

cv::Mat Uniform(const CameraSensor& sensor, double grey) {
  return cv::Mat(sensor.maps().pinhole.height, sensor.maps().pinhole.width, CV_8UC3,
                 cv::Scalar::all(grey));
}

TEST(CameraSensor, VignettingDarkensTheCornersByItsShare) {
  LookOptions look = QuietLook();
  look.min_exposure_ms = look.max_exposure_ms = 20.0;  // recorded as rendered
  CameraSensor sensor(look, SmallCamera(), 1);
  const cv::Mat image = sensor.Record({Uniform(sensor, 200)}, {0.0}, 0.0, 1);
  EXPECT_NEAR(image.at<cv::Vec3b>(60, 80)[1], 200, 1);
  EXPECT_NEAR(image.at<cv::Vec3b>(0, 0)[1], 200 * (1 - look.vignetting), 3);
}

TEST(CameraSensor, AutoExposureLengthensThenGainsInTheDark) {
  LookOptions look = QuietLook();
  look.vignetting = 0.0;
  CameraSensor sensor(look, SmallCamera(), 1);
  double brightness = 0.0;
  for (int frame = 0; frame < 40; ++frame) {
    brightness = cv::mean(sensor.Record({Uniform(sensor, 20)}, {0.0}, frame / 30.0, 1))[0] / 255;
  }
  EXPECT_DOUBLE_EQ(sensor.exposure_ms(), look.max_exposure_ms);
  EXPECT_GT(sensor.gain(), 1.5);
  EXPECT_NEAR(brightness, look.target_brightness, 0.05);
  // Bright light: the gain goes first, then the exposure shortens.
  for (int frame = 0; frame < 40; ++frame) sensor.Record({Uniform(sensor, 250)}, {0.0}, 0.0, 1);
  EXPECT_DOUBLE_EQ(sensor.gain(), 1.0);
  EXPECT_LT(sensor.exposure_ms(), 15.0);
}

TEST(CameraSensor, RollingShutterReadsTopRowsEarlier) {
  for (double readout : {0.0, 30.0}) {
    LookOptions look = QuietLook();
    look.vignetting = 0.0;
    look.min_exposure_ms = look.max_exposure_ms = 10.0;
    look.rolling_shutter_ms = readout;
    CameraSensor sensor(look, SmallCamera(), 1);
    // The scene brightens over time: 10 grey levels per render.
    const std::vector<double> times = sensor.SampleTimes(1000.0);
    std::vector<cv::Mat> renders;
    for (std::size_t i = 0; i < times.size(); ++i)
      renders.push_back(Uniform(sensor, 50 + 10.0 * i));
    const cv::Mat image = sensor.Record(renders, times, 0.0, 1);
    const double top = cv::mean(image.row(1))[0], bottom = cv::mean(image.row(118))[0];
    if (readout == 0.0) {
      EXPECT_NEAR(top, bottom, 0.5);
    } else {
      EXPECT_GT(bottom, top + 20) << "rows later in the readout see a later scene";
    }
  }
}

}  // namespace
}  // namespace ocg::sim
