#include "ocg/sim/scene.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

namespace ocg::sim {
namespace {

void Require(bool condition, const std::string& message) {
  if (!condition) throw std::invalid_argument("scene: " + message);
}

// Smooth pseudo-random wobble: a few sines with seeded phases and frequencies.
double Wobble(std::uint64_t seed, int channel, double t) {
  double value = 0.0;
  for (int k = 1; k <= 3; ++k) {
    const std::uint64_t h =
        (seed + 0x9e3779b97f4a7c15ULL * static_cast<std::uint64_t>(channel * 7 + k)) *
        0xbf58476d1ce4e5b9ULL;
    const double phase = static_cast<double>(h % 10000) / 10000.0 * 2.0 * M_PI;
    const double frequency = 0.15 * k + static_cast<double>((h >> 20) % 100) / 400.0;
    value += std::sin(2.0 * M_PI * frequency * t + phase) / k;
  }
  return value / 1.83;  // roughly within [-1, 1]
}

// Straight path: the length of each straight pass along x, beyond the table's ends.
constexpr double kStraightLength = 3.2;
// Round path: an ellipse stretched along the table's long axis by this factor.
constexpr double kRoundStretch = 1.25;

}  // namespace

std::optional<PlacedPose> SceneObject::PoseAt(double t) const {
  const PlacedPose* current = nullptr;
  for (const PlacedPose& pose : history) {
    if (pose.time <= t) current = &pose;
  }
  if (current == nullptr || !current->present) return std::nullopt;
  return *current;
}

std::optional<PlacedPose> Walker::PoseAt(double t) const {
  if (waypoints.size() < 2 || t < StartTime() || t > EndTime()) return std::nullopt;
  std::size_t leg = 0;
  while (leg + 2 < waypoints.size() && waypoints[leg + 1].time <= t) ++leg;
  const Waypoint& from = waypoints[leg];
  const Waypoint& to = waypoints[leg + 1];
  const double span = to.time - from.time;
  const double share = span > 0 ? std::clamp((t - from.time) / span, 0.0, 1.0) : 1.0;
  PlacedPose pose;
  pose.time = t;
  pose.centre.head<2>() = from.position + share * (to.position - from.position);
  // Facing: the direction of this leg, or, standing, of the last leg that went somewhere
  // (else of the next one).
  Eigen::Vector2d heading = Eigen::Vector2d::Zero();
  for (std::size_t k = leg + 1; k-- > 0 && heading.norm() < 1e-9;) {
    heading = waypoints[k + 1].position - waypoints[k].position;
  }
  for (std::size_t k = leg + 1; k + 1 < waypoints.size() && heading.norm() < 1e-9; ++k) {
    heading = waypoints[k + 1].position - waypoints[k].position;
  }
  pose.yaw = heading.norm() > 1e-9 ? std::atan2(heading.y(), heading.x()) : 0.0;
  return pose;
}

const SceneObject* Scene::FindObject(int id) const {
  for (const SceneObject& object : objects) {
    if (object.id == id) return &object;
  }
  return nullptr;
}

SceneObject* Scene::FindObject(int id) {
  return const_cast<SceneObject*>(static_cast<const Scene&>(*this).FindObject(id));
}

void Scene::Check() const {
  camera.Check();
  look.Check();
  Require(fps > 0 && duration > 0, "fps and duration must be positive");
  Require(path.kind == "round" || path.kind == "straight", "path.kind must be round or straight");
  Require(path.speed > 0 && path.speed <= 0.4, "path.speed must be in (0, 0.4] m/s");
  Require(path.start >= 0 && path.start < 1, "path.start must be in [0, 1)");
  Require(session.index >= 0, "session.index must be at least 0");
  const RealisticDetection& r = noise.realistic;
  Require(r.hard_share >= 0 && r.hard_share <= 1 && r.dropout_share >= 0 && r.dropout_share <= 1,
          "noise.realistic: hard_share and dropout_share must be in [0, 1]");
  Require(r.object_logit_std >= 0 && r.wander_logit_std >= 0 && r.score_noise >= 0,
          "noise.realistic: object_logit_std, wander_logit_std and score_noise must be >= 0");
  Require(r.wander_seconds >= 0 && r.dropouts_per_minute >= 0 && r.dropout_seconds >= 0 &&
              r.flips_per_second >= 0 && r.flip_seconds >= 0 && r.exposure_ms >= 0,
          "noise.realistic: wander_seconds, dropouts_per_minute, dropout_seconds, "
          "flips_per_second, flip_seconds and exposure_ms must be >= 0");
  Require(r.frame_noise > 0, "noise.realistic.frame_noise must be positive");
  Require(r.reference_box_pixels > 0, "noise.realistic.reference_box_pixels must be positive");
  std::set<int> ids;
  for (const SceneObject& object : objects) {
    Require(object.id > 0 && ids.insert(object.id).second,
            "object ids must be positive and unique (id " + std::to_string(object.id) + ")");
    Require(object.class_id >= 0 && object.class_id < 80,
            "object " + std::to_string(object.id) + ": class_id must be a COCO-80 index");
    Require(!object.history.empty() && object.history[0].time == 0.0,
            "object " + std::to_string(object.id) + ": history must start at time 0");
    for (size_t i = 1; i < object.history.size(); ++i) {
      Require(object.history[i].time > object.history[i - 1].time,
              "object " + std::to_string(object.id) + ": history times must increase");
    }
    Require((object.size.array() > 0).all(),
            "object " + std::to_string(object.id) + ": size must be positive");
  }
  std::set<int> walker_ids;
  for (const Walker& walker : walkers) {
    const std::string name = "walker " + std::to_string(walker.id);
    Require(walker.id > 0 && walker_ids.insert(walker.id).second,
            "walker ids must be positive and unique (id " + std::to_string(walker.id) + ")");
    Require(walker.height > 0, name + ": height must be positive");
    Require(walker.waypoints.size() >= 2, name + ": needs at least 2 waypoints");
    for (size_t i = 1; i < walker.waypoints.size(); ++i) {
      Require(walker.waypoints[i].time > walker.waypoints[i - 1].time,
              name + ": waypoint times must increase");
    }
  }
}

PinholeCamera OutputCamera(const Scene& scene) { return LookCamera(scene.camera, scene.look); }

double LapDuration(const CameraPath& path) {
  if (path.kind == "round") return 2.0 * M_PI * kRoundStretch * path.radius / path.speed;
  return 2.0 * (kStraightLength + M_PI * path.side_offset) / path.speed;
}

SE3 CameraPoseAt(const Scene& scene, double time) {
  const CameraPath& path = scene.path;
  const double t = time + path.start * LapDuration(path);
  const std::uint64_t seed = scene.seed;
  Eigen::Vector3d eye, target;
  if (path.kind == "round") {
    // On the ellipse the speed peaks on its long half axis: pace the angle by that one.
    const double angle = path.speed * t / (kRoundStretch * path.radius) - M_PI / 2;
    eye = Eigen::Vector3d(kRoundStretch * path.radius * std::cos(angle),
                          path.radius * std::sin(angle), path.height);
    target = Eigen::Vector3d(0.35 * std::cos(angle), 0.2 * std::sin(angle), 0.75);
  } else {
    // Along one long side, round the end, back along the other side, round the other
    // end. The camera looks at the near half of the table (the partition hides the far
    // half), and the target follows the eye continuously, so turns stay smooth.
    const double length = kStraightLength;
    const double side = path.side_offset;
    const double end_arc = M_PI * side;  // the ends are half ellipses (0.4 m deep)
    const double lap = 2.0 * (length + end_arc);
    double s = std::fmod(path.speed * t, lap);
    if (s < length) {
      eye = Eigen::Vector3d(-length / 2 + s, -side, path.height);
    } else if ((s -= length) < end_arc) {
      const double angle = -M_PI / 2 + s / side;
      eye =
          Eigen::Vector3d(length / 2 + 0.4 * std::cos(angle), side * std::sin(angle), path.height);
    } else if ((s -= end_arc) < length) {
      eye = Eigen::Vector3d(length / 2 - s, side, path.height);
    } else {
      const double angle = M_PI / 2 + (s - length) / side;
      eye =
          Eigen::Vector3d(-length / 2 + 0.4 * std::cos(angle), side * std::sin(angle), path.height);
    }
    target = Eigen::Vector3d(std::clamp(0.7 * eye.x(), -1.1, 1.1), 0.25 * eye.y() / side, 0.75);
  }
  const double j = path.jitter;
  eye += j * Eigen::Vector3d(Wobble(seed, 0, t), Wobble(seed, 1, t), Wobble(seed, 2, t));
  target += 6.0 * j * Eigen::Vector3d(Wobble(seed, 3, t), Wobble(seed, 4, t), Wobble(seed, 5, t));
  return LookAt(eye, target);
}

}  // namespace ocg::sim
