#pragma once
// A synthetic semi-static scene: a room, furniture, a table with a central partition,
// desk objects whose pose history holds moves, removals and additions, a camera path and
// a detector noise model. Scenes come from presets (presets.h) or YAML files
// (scene_io.h); docs/synthetic.md documents the fields.

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ocg/core/camera.h"
#include "ocg/core/lie.h"
#include "ocg/sim/look.h"

namespace ocg::sim {

enum class Shape { kBox, kCylinder };

// Where an object is from a time on; present = false means removed (or not yet added).
struct PlacedPose {
  double time = 0.0;  // seconds from the start of the sequence
  bool present = true;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // world frame, metres
  double yaw = 0.0;                                  // about world z, radians
};

struct SceneObject {
  int id = 0;        // 1-based, unique
  int class_id = 0;  // COCO-80
  Shape shape = Shape::kBox;
  Eigen::Vector3d size = Eigen::Vector3d(0.1, 0.1, 0.1);  // full extents (cylinder: d, d, h)
  std::uint64_t texture_seed = 0;
  std::vector<PlacedPose> history;  // ascending time; history[0].time == 0
  // A later visit (Scene::session.index > 0): where the object stood when the previous
  // visit ended (present false: it was not there), when that differs from history[0].
  std::optional<PlacedPose> before_session;

  // The pose in force at time t, nullopt when the object is absent.
  std::optional<PlacedPose> PoseAt(double t) const;
  bool Moves() const { return history.size() > 1; }
};

// A person walking through the room (bonn-style dynamic scenes): an upright textured body
// (legs, torso, arms, head; `height` tall, about 0.6 m across the shoulders) that walks
// straight between waypoints on the floor at constant speed, facing where it goes, and
// stands still between two waypoints at the same place. Absent before its first waypoint's
// time and after its last one's. Not an object of the map: its pixels carry id 0 in the id
// pass (it hides objects as furniture does) and the detector boxes no person.
struct Waypoint {
  double time = 0.0;                                   // seconds from the sequence's start
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  // world x, y on the floor, metres
};

struct Walker {
  int id = 0;            // 1-based, unique among the walkers
  double height = 1.75;  // metres
  std::uint64_t texture_seed = 0;
  std::vector<Waypoint> waypoints;  // ascending times (equal places: standing), at least 2

  // Where the walker stands at t (centre of its footprint on the floor, z = 0; yaw: the
  // direction it faces), nullopt before the first and after the last waypoint.
  std::optional<PlacedPose> PoseAt(double t) const;
  double StartTime() const { return waypoints.front().time; }
  double EndTime() const { return waypoints.back().time; }
  // Half the body's width across the shoulders and arms: its footprint's radius.
  double Radius() const { return 0.31 * height / 1.75; }
};

// Static scenery: a textured box (walls are the room box seen from inside).
struct Furniture {
  std::string name;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d size = Eigen::Vector3d::Ones();
  double yaw = 0.0;
  std::uint64_t texture_seed = 0;
};

struct CameraPath {
  std::string kind = "round";  // "round": around the table; "straight": along its sides
  double radius = 1.6;         // round: distance from the table centre, metres
  double side_offset = 1.25;   // straight: distance from the table's long axis
  double height = 1.35;        // camera height, metres
  double speed = 0.3;          // metres per second along the path (<= 0.4)
  double jitter = 0.01;        // hand-held wobble amplitude, metres (and ~1 degree)
  double start = 0.0;          // share of a lap already covered at t = 0, in [0, 1)
};

// The realistic detector model (detector.h): the probability of detecting a visible object
// is a logistic function of a logit made of the terms below (each a logit change), an
// object's own detectability, a slow per-object wander, and seconds-long dropout stretches
// of the whole detector. Calibrated against real YOLO detections (docs/synthetic.md).
struct RealisticDetection {
  std::uint64_t seed = 0;   // mixed with the scene's seed: other draws, same scene
  double base_logit = 4.5;  // a near, large, sharp, face-on, fully visible object
  // Per-object detectability, drawn once per object from the seed.
  double object_logit_std = 0.6;
  double hard_share = 0.2;   // share of objects that are simply hard
  double hard_logit = -4.5;  // added for them
  // Viewing conditions.
  double reference_distance = 1.2;  // metres; farther costs distance_logit per metre
  double distance_logit = -0.8;
  double reference_box_pixels = 4000;  // box area; size_logit per ln(area / reference), up to 0
  double size_logit = 0.9;
  double angle_logit = -1.5;       // edge-on view of the largest vertical face (box objects)
  double exposure_ms = 20;         // motion blur = image speed over this time
  double blur_logit = -0.08;       // per pixel of motion blur
  double occlusion_logit = -4.0;   // per unit of occluded share
  double truncation_logit = -4.0;  // per unit of share outside the image
  // Scale of the frame-to-frame logistic noise on the logit (1: a coin flip with the
  // logistic probability each frame; smaller: misses follow the slow terms, fewer flickers).
  double frame_noise = 0.4;
  // Slow wander of each object's logit: an AR(1) process with this time constant.
  double wander_seconds = 1.5;
  double wander_logit_std = 1.5;
  // Stretches of seconds where the detector finds far fewer boxes.
  double dropouts_per_minute = 2.0;
  double dropout_seconds = 3.0;  // length: exponential, clamped to 1 to 3 times this
  double dropout_logit = -5.5;   // mean depth (each stretch 0.5 to 1.5 times)
  double dropout_share = 0.7;    // share of the objects a stretch hits (drawn per stretch)
  // Class flips (cup<->bowl, book<->laptop, bottle->cup) that persist.
  double flips_per_second = 0.5;  // starting rate for a detected object
  double flip_seconds = 0.2;      // mean length (exponential)
  // Score: score_base + score_per_logit * (logit without wander) + noise, in [0.25, 0.97].
  double score_base = 0.57;
  double score_per_logit = 0.03;
  double score_noise = 0.13;
};

enum class DetectorKind { kIndependent, kRealistic };

struct DetectionNoise {
  // kIndependent: the original model (misses per frame, short bursts, the fields below);
  // kRealistic: `realistic` decides misses, classes and scores; jitter, duplicates and
  // false positives stay as below.
  DetectorKind kind = DetectorKind::kIndependent;
  RealisticDetection realistic;
  bool perfect = false;             // no noise at all: exact boxes, every visible object
  double min_visible_pixels = 150;  // fewer visible pixels: never detected
  double box_jitter = 0.03;         // std of each box edge, share of the box size
  double miss_base = 0.04;          // miss probability of a fully visible object
  double miss_occlusion = 0.6;      // added per unit of occluded share
  double miss_truncation = 0.7;     // added per unit of share outside the image
  double miss_small = 0.3;          // added for boxes smaller than small_box_pixels
  double small_box_pixels = 900;
  double burst_continue = 0.6;  // a miss repeats in the next frame with this probability
  double confusion = 0.05;      // cup<->bowl, book<->laptop, bottle<->cup
  double false_positives_per_frame = 0.15;
  double duplicate = 0.03;  // a second, shifted box for the same object
};

// Which visit of a room a scene is (ocg_synth --session-of renders later visits).
struct SessionLink {
  int index = 0;              // 0: a first visit (sessions count from 0, as map files)
  std::string previous;       // the previous visit's scene name (index > 0)
  double previous_end = 0.0;  // timestamp of the previous visit's end, seconds
};

struct Scene {
  std::string name = "custom";
  std::uint64_t seed = 1;
  PinholeCamera camera;  // intrinsics; the realistic look adds its lens distortion (OutputCamera)
  double fps = 30.0;
  double duration = 60.0;       // seconds
  double time_origin = 1000.0;  // timestamp of frame 0, seconds (later visits: later origins)
  SessionLink session;
  Eigen::Vector3d room_size = Eigen::Vector3d(6.0, 5.0, 2.8);
  Eigen::Vector3d light_direction = Eigen::Vector3d(0.3, 0.5, -1.0);
  double ambient = 0.45;
  std::vector<Furniture> furniture;  // the table and partition included
  std::vector<SceneObject> objects;
  std::vector<Walker> walkers;  // people walking through; none in the room presets
  CameraPath path;
  DetectionNoise noise;
  LookOptions look;  // procedural (default) or realistic frames

  int FrameCount() const { return static_cast<int>(duration * fps); }
  // The object with this id, or nullptr.
  const SceneObject* FindObject(int id) const;
  SceneObject* FindObject(int id);
  double TimeOfFrame(int frame) const { return frame / fps; }
  // Throws std::invalid_argument naming the field when the scene is impossible.
  void Check() const;
};

// The camera the frames are seen through: scene.camera with the look's distortion.
PinholeCamera OutputCamera(const Scene& scene);

// Seconds the camera takes for one lap of its path.
double LapDuration(const CameraPath& path);

// Camera pose T_cw at time t (seconds), smooth, deterministic in the scene's seed.
SE3 CameraPoseAt(const Scene& scene, double t);

}  // namespace ocg::sim
