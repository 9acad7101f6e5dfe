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

  // The pose in force at time t, nullopt when the object is absent.
  std::optional<PlacedPose> PoseAt(double t) const;
  bool Moves() const { return history.size() > 1; }
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
};

struct DetectionNoise {
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

struct Scene {
  std::string name = "custom";
  std::uint64_t seed = 1;
  PinholeCamera camera;  // intrinsics; the realistic look adds its lens distortion (OutputCamera)
  double fps = 30.0;
  double duration = 60.0;  // seconds
  Eigen::Vector3d room_size = Eigen::Vector3d(6.0, 5.0, 2.8);
  Eigen::Vector3d light_direction = Eigen::Vector3d(0.3, 0.5, -1.0);
  double ambient = 0.45;
  std::vector<Furniture> furniture;  // the table and partition included
  std::vector<SceneObject> objects;
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
