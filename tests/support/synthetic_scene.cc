#include "synthetic_scene.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <bitset>
#include <cmath>
#include <random>
#include <stdexcept>

namespace ocg::testing {
namespace {

constexpr double kPi = 3.14159265358979323846;

int HammingDistance(const Descriptor& a, const Descriptor& b) {
  int bits = 0;
  for (std::size_t i = 0; i < a.size(); ++i) bits += std::bitset<64>(a[i] ^ b[i]).count();
  return bits;
}

SE3 PoseOnPath(const SyntheticSceneOptions& options, int frame) {
  if (options.path == SyntheticSceneOptions::Path::kLine) {
    const double share =
        options.frames > 1 ? static_cast<double>(frame) / (options.frames - 1) : 0.0;
    const Eigen::Vector3d eye =
        options.line_start + share * (options.line_end - options.line_start);
    return LookAt(eye, eye + options.line_direction);
  }
  // Each frame a step of laps / frames along the circle: `laps` 1 with N frames ends one
  // step short of the start, so a loop comes back to the start's view without repeating it.
  const double azimuth = options.start_azimuth + 2 * kPi * options.laps * frame / options.frames;
  const Eigen::Vector3d eye =
      options.target + Eigen::Vector3d(options.orbit_radius * std::cos(azimuth),
                                       options.orbit_radius * std::sin(azimuth),
                                       options.orbit_height);
  for (const auto& [first, last] : options.look_away) {
    if (frame >= first && frame < last) {
      const Eigen::Vector3d outward(eye.x() - options.target.x(), eye.y() - options.target.y(), 0);
      return LookAt(eye, eye + outward);
    }
  }
  return LookAt(eye, options.target);
}

}  // namespace

SE3 LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d forward = (target - eye).normalized();
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d down = forward.cross(right);
  Eigen::Matrix3d R_wc;
  R_wc << right, down, forward;
  return SE3(R_wc, eye).Inverse();
}

std::vector<Eigen::Vector3d> CuboidCorners(const SyntheticObject& object) {
  const double c = std::cos(object.yaw), s = std::sin(object.yaw);
  std::vector<Eigen::Vector3d> corners;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d local(((i & 1) ? 0.5 : -0.5) * object.size.x(),
                                ((i & 2) ? 0.5 : -0.5) * object.size.y(),
                                ((i & 4) ? 0.5 : -0.5) * object.size.z());
    corners.push_back(object.centre + Eigen::Vector3d(c * local.x() - s * local.y(),
                                                      s * local.x() + c * local.y(), local.z()));
  }
  return corners;
}

double CentreDistance(const SE3& a_cw, const SE3& b_cw) {
  return (a_cw.Inverse().translation() - b_cw.Inverse().translation()).norm();
}

SyntheticSceneOptions TableWithObjects(int cup_taken_at) {
  SyntheticSceneOptions options;
  options.frames = 120;
  options.laps = 1.0;
  options.look_away = {{60, 70}, {100, 110}};
  const auto object = [](int class_id, const Eigen::Vector3d& centre, const Eigen::Vector3d& size,
                         double yaw) {
    SyntheticObject o;
    o.class_id = class_id;
    o.centre = centre;
    o.size = size;
    o.yaw = yaw;
    return o;
  };
  options.objects = {object(41, {0.15, 0.1, 0.8}, {0.08, 0.08, 0.1}, 0.0),
                     object(63, {-0.2, -0.1, 0.765}, {0.33, 0.23, 0.03}, 0.3),
                     object(39, {0.3, -0.25, 0.85}, {0.07, 0.07, 0.2}, 0.0),
                     object(73, {-0.25, 0.3, 0.765}, {0.2, 0.15, 0.03}, -0.4)};
  options.objects[kTableCup].present_until = cup_taken_at;
  return options;
}

SyntheticScene SynthesizeScene(const SyntheticSceneOptions& options) {
  if (options.frames < 1 || options.points < options.points_on_table ||
      options.points_on_table < 0) {
    throw std::invalid_argument("SynthesizeScene: frames >= 1 and 0 <= points_on_table <= points");
  }
  SyntheticScene scene;
  scene.options = options;
  std::mt19937_64 layout(options.layout_seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < options.points; ++i) {
    if (i < options.points_on_table) {
      scene.points.push_back(options.target + Eigen::Vector3d(1.6 * unit(layout) - 0.8,
                                                              1.6 * unit(layout) - 0.8, -0.05));
    } else {
      const double angle = 2 * kPi * unit(layout);
      scene.points.emplace_back(options.target.x() + options.wall_radius * std::cos(angle),
                                options.target.y() + options.wall_radius * std::sin(angle),
                                2.5 * unit(layout));
    }
    // Random descriptors are 128 bits apart on average; redraw the rare close one.
    Descriptor descriptor;
    bool distinct = false;
    while (!distinct) {
      for (auto& word : descriptor) word = layout();
      distinct = std::all_of(
          scene.descriptors.begin(), scene.descriptors.end(),
          [&](const Descriptor& other) { return HammingDistance(descriptor, other) >= 80; });
    }
    scene.descriptors.push_back(descriptor);
  }

  std::mt19937_64 noise(options.noise_seed);
  std::normal_distribution<double> gaussian(0.0, 1.0);
  scene.projections.resize(static_cast<std::size_t>(options.frames));
  scene.detections.resize(static_cast<std::size_t>(options.frames));
  scene.detected_objects.resize(static_cast<std::size_t>(options.frames));
  for (int frame = 0; frame < options.frames; ++frame) {
    const SE3 T_cw = PoseOnPath(options, frame);
    scene.T_cw.push_back(T_cw);
    scene.timestamps.push_back(frame / options.fps);
    for (int i = 0; i < options.points; ++i) {
      const Eigen::Vector3d p_c = T_cw * scene.points[static_cast<std::size_t>(i)];
      if (p_c.z() <= 0.1) continue;
      Eigen::Vector2d pixel = options.camera.ProjectUndistorted(p_c);
      if (options.pixel_noise > 0.0) {
        pixel += options.pixel_noise * Eigen::Vector2d(gaussian(noise), gaussian(noise));
      }
      if (!options.camera.IsInImage(pixel)) continue;
      scene.projections[static_cast<std::size_t>(frame)].push_back({i, pixel, p_c.z()});
    }
    for (std::size_t k = 0; k < options.objects.size(); ++k) {
      const SyntheticObject& object = options.objects[k];
      if (frame < object.present_from || frame >= object.present_until) continue;
      Eigen::Vector2d low(1e9, 1e9), high(-1e9, -1e9);
      bool whole = true;
      for (const Eigen::Vector3d& corner : CuboidCorners(object)) {
        const Eigen::Vector3d p_c = T_cw * corner;
        if (p_c.z() <= 0.1) {
          whole = false;
          break;
        }
        const Eigen::Vector2d pixel = options.camera.ProjectUndistorted(p_c);
        whole = whole && options.camera.IsInImage(pixel);
        low = low.cwiseMin(pixel);
        high = high.cwiseMax(pixel);
      }
      if (!whole) continue;
      scene.detections[static_cast<std::size_t>(frame)].push_back(
          {object.class_id, low.x(), low.y(), high.x() - low.x(), high.y() - low.y(),
           options.detection_confidence});
      scene.detected_objects[static_cast<std::size_t>(frame)].push_back(static_cast<int>(k));
    }
  }
  return scene;
}

CarriedCups CupsCarriedPastEachOther() {
  CarriedCups cups;
  cups.options = TableWithObjects();
  SyntheticObject red = cups.options.objects[kTableCup];
  red.centre = {0.15, 0.1, 0.8};
  red.present_until = 60;
  SyntheticObject blue = red;
  blue.centre = {0.15, -0.1, 0.8};
  SyntheticObject blue_moved = blue, red_moved = red;
  blue_moved.centre = {0.35, 0.1, 0.8};   // 0.2 from red's old place
  red_moved.centre = {0.35, -0.05, 0.8};  // 0.21 from blue's old place
  blue_moved.present_from = red_moved.present_from = 60;
  blue_moved.present_until = red_moved.present_until = std::numeric_limits<int>::max();
  cups.options.objects[kTableCup] = red;
  cups.options.objects.push_back(blue);
  cups.options.objects.push_back(blue_moved);
  cups.options.objects.push_back(red_moved);
  return cups;
}

bool CarriedCups::IsRed(int object) const {
  return object == static_cast<int>(red) || object == static_cast<int>(red_moved);
}

cv::Mat CarriedCups::ColourImage(const SyntheticScene& scene, std::size_t frame) const {
  cv::Mat bgr(scene.options.camera.height, scene.options.camera.width, CV_8UC3,
              cv::Scalar(128, 128, 128));
  for (std::size_t d = 0; d < scene.detections[frame].size(); ++d) {
    const int object = scene.detected_objects[frame][d];
    if (scene.options.objects[static_cast<std::size_t>(object)].class_id != 41) continue;
    const Detection& box = scene.detections[frame][d];
    const cv::Point centre(static_cast<int>(box.x + 0.5 * box.width),
                           static_cast<int>(box.y + 0.5 * box.height));
    const cv::Size axes(static_cast<int>(0.5 * box.width), static_cast<int>(0.5 * box.height));
    cv::ellipse(bgr, centre, axes, 0, 0, 360,
                IsRed(object) ? cv::Scalar(30, 30, 220) : cv::Scalar(220, 60, 30), cv::FILLED);
  }
  return bgr;
}

std::size_t CarriedCups::PlaceOf(const Eigen::Vector3d& centre) const {
  std::size_t nearest = red;
  for (const std::size_t place : {red, blue, blue_moved, red_moved}) {
    if ((options.objects[place].centre - centre).norm() <
        (options.objects[nearest].centre - centre).norm())
      nearest = place;
  }
  return nearest;
}

}  // namespace ocg::testing
