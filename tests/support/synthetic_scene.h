#pragma once
// A synthetic scene for unit tests, with known answers: a camera path, static 3-D points
// with a descriptor each, their projections in every frame (with optional pixel noise),
// and optional cuboid objects with the boxes a perfect detector gives. In the manner of
// COLMAP's SynthesizeDataset: one options struct, one call, a separate seed per source of
// randomness, so a test changes the noise without changing the layout.
//
// Frames: T_cw maps world to camera (x right, y down, z forward); the world's z is up.

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <opencv2/core/mat.hpp>
#include <utility>
#include <vector>

#include "ocg/core/camera.h"
#include "ocg/core/lie.h"
#include "ocg/features/descriptor.h"
#include "ocg/io/detections.h"

namespace ocg::testing {

// An object standing in the scene: a cuboid (full extents x, y horizontal, z up; yaw about
// up) detected as class_id while present, i.e. in frames [present_from, present_until).
struct SyntheticObject {
  int class_id = 41;  // COCO-80 (41: cup)
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d size = Eigen::Vector3d(0.1, 0.1, 0.1);
  double yaw = 0.0;
  int present_from = 0;
  int present_until = std::numeric_limits<int>::max();
};

struct SyntheticSceneOptions {
  int frames = 60;
  double fps = 30.0;
  PinholeCamera camera;  // default: a 640 x 480 ideal pinhole, focal 525

  // The camera path. kOrbit: on a circle of orbit_radius about target, orbit_height above
  // it, looking at target, laps laps from azimuth start_azimuth (radians, counter-
  // clockwise seen from above). kLine: from line_start to line_end, looking along
  // line_direction (default: towards +y).
  enum class Path { kOrbit, kLine };
  Path path = Path::kOrbit;
  Eigen::Vector3d target = Eigen::Vector3d(0.0, 0.0, 0.8);
  double orbit_radius = 1.5;
  double orbit_height = 0.5;
  double laps = 0.25;
  double start_azimuth = 0.0;
  Eigen::Vector3d line_start = Eigen::Vector3d(-1.0, -2.0, 1.3);
  Eigen::Vector3d line_end = Eigen::Vector3d(1.0, -2.0, 1.3);
  Eigen::Vector3d line_direction = Eigen::Vector3d(0.0, 1.0, -0.3);
  // Frames [first, last) where the camera turns round and looks at the wall behind it,
  // level (an orbit only): it leaves the objects' observable region and comes back.
  std::vector<std::pair<int, int>> look_away;

  // Static points: points_on_table on the table (a 1.6 m square about target, 5 cm below
  // it), the rest on a cylindrical wall of wall_radius about target, heights 0..2.5 m.
  int points = 400;
  int points_on_table = 100;
  double wall_radius = 4.0;
  std::uint64_t layout_seed = 1;  // points and descriptors

  // Projections: Gaussian noise of this standard deviation (pixels) on each.
  double pixel_noise = 0.0;
  std::uint64_t noise_seed = 2;

  std::vector<SyntheticObject> objects;
  double detection_confidence = 0.9;
};

// A point seen in a frame.
struct SyntheticProjection {
  int point = 0;          // index into SyntheticScene::points
  Eigen::Vector2d pixel;  // undistorted, noise added
  double depth = 0.0;     // along the optical axis, metres
};

struct SyntheticScene {
  SyntheticSceneOptions options;
  std::vector<SE3> T_cw;                // per frame
  std::vector<double> timestamps;       // per frame, seconds (frame / fps)
  std::vector<Eigen::Vector3d> points;  // world
  // One per point, random and pairwise at least 80 bits apart (a matcher tells them apart).
  std::vector<Descriptor> descriptors;
  // Per frame: the points in front of the camera (depth > 0.1 m) projecting inside the
  // image, in point order.
  std::vector<std::vector<SyntheticProjection>> projections;
  // Per frame: the boxes of the objects present whose whole projected cuboid lies in the
  // image (a perfect detector), in object order. Detection::class_id is the object's.
  std::vector<std::vector<Detection>> detections;
  // Per frame, per detection: the index of its object in options.objects.
  std::vector<std::vector<int>> detected_objects;
};

SyntheticScene SynthesizeScene(const SyntheticSceneOptions& options);

// A table (top at z 0.75) with four objects: a cup (class 41), a laptop (63), a bottle (39)
// and a book (73), within 0.35 m of its centre, seen from one lap of 120 frames (3 degrees
// a frame, 30 frames/s) on the default orbit. The camera looks away during frames 60-69
// and 100-109: whatever changed while it looked away, it leaves the objects' observable
// region twice (what the OCG needs to remove a vanished object). The cup is taken away at
// frame cup_taken_at (default: never).
SyntheticSceneOptions TableWithObjects(int cup_taken_at = std::numeric_limits<int>::max());
constexpr int kTableCup = 0;  // the cup's index in TableWithObjects().objects

// Two cups of one size, one red and one blue, on the table of TableWithObjects() (the
// cup of kTableCup is the red one, the fourth object the blue one), carried past each
// other while the camera looks away (frames 60-69): the red one to a place a little
// farther from its old one than the blue one's new place is, and the blue one likewise.
// By distance alone a pairing of moves takes each removal to the nearer newcomer, the
// other cup; their colours tell them apart.
struct CarriedCups {
  SyntheticSceneOptions options;
  std::size_t red = kTableCup, blue = 4, blue_moved = 5, red_moved = 6;  // in options.objects
  bool IsRed(int object) const;
  // A frame's colour image: grey, each detected cup a filled ellipse in its box, red or
  // blue (BGR).
  cv::Mat ColourImage(const SyntheticScene& scene, std::size_t frame) const;
  // The index of the cup place (of the four) nearest centre.
  std::size_t PlaceOf(const Eigen::Vector3d& centre) const;
};
CarriedCups CupsCarriedPastEachOther();

// The camera at eye looking at target, world z up (x right, y down in the image).
SE3 LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target);

// The 8 corners of a cuboid: -+ half the size along its x (bit 0), y (bit 1), z (bit 2),
// turned by yaw about z.
std::vector<Eigen::Vector3d> CuboidCorners(const SyntheticObject& object);

// The SE(3) distance between two camera centres, metres.
double CentreDistance(const SE3& a_cw, const SE3& b_cw);

}  // namespace ocg::testing
