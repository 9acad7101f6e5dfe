#include "ocg/sim/presets.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <set>
#include <stdexcept>

namespace ocg::sim {
namespace {

struct ObjectKind {
  int class_id;
  Shape shape;
  Eigen::Vector3d size;  // full extents, metres (cylinder: diameter, diameter, height)
};

// COCO desk-scene classes with real-world sizes.
const ObjectKind kDeskKinds[] = {
    {41, Shape::kCylinder, {0.085, 0.085, 0.10}},  // cup
    {39, Shape::kCylinder, {0.07, 0.07, 0.24}},    // bottle
    {45, Shape::kCylinder, {0.16, 0.16, 0.07}},    // bowl
    {73, Shape::kBox, {0.16, 0.23, 0.035}},        // book
    {63, Shape::kBox, {0.33, 0.23, 0.03}},         // laptop (closed)
    {66, Shape::kBox, {0.44, 0.14, 0.03}},         // keyboard
    {64, Shape::kBox, {0.065, 0.11, 0.035}},       // mouse
    {67, Shape::kBox, {0.075, 0.15, 0.012}},       // cell phone
    {62, Shape::kBox, {0.50, 0.07, 0.32}},         // tv / monitor
    {77, Shape::kBox, {0.20, 0.15, 0.28}},         // teddy bear
    {58, Shape::kCylinder, {0.15, 0.15, 0.30}},    // potted plant
    {75, Shape::kCylinder, {0.10, 0.10, 0.22}},    // vase
    {65, Shape::kBox, {0.05, 0.18, 0.022}},        // remote
    {74, Shape::kCylinder, {0.20, 0.20, 0.05}},    // clock
};
constexpr double kTableTop = 0.75;
constexpr double kMaxYaw = 0.2;       // objects stand roughly square to the table
constexpr double kTableLength = 2.6;  // along x
constexpr double kTableWidth = 1.3;   // along y; the partition stands at y = 0

PinholeCamera TumLikeCamera() {
  PinholeCamera camera;  // TUM freiburg3 intrinsics, rendered without distortion
  camera.fx = 535.4;
  camera.fy = 539.2;
  camera.cx = 320.1;
  camera.cy = 247.6;
  camera.width = 640;
  camera.height = 480;
  return camera;
}

void AddFurniture(Scene& scene, const std::string& name, const Eigen::Vector3d& centre,
                  const Eigen::Vector3d& size) {
  Furniture item;
  item.name = name;
  item.centre = centre;
  item.size = size;
  item.texture_seed = scene.seed * 1000 + scene.furniture.size() + 1;
  scene.furniture.push_back(item);
}

void AddRoom(Scene& scene) {
  const Eigen::Vector3d room = scene.room_size;
  const double t = 0.05;  // wall thickness
  AddFurniture(scene, "floor", {0, 0, -t / 2}, {room.x(), room.y(), t});
  AddFurniture(scene, "ceiling", {0, 0, room.z() + t / 2}, {room.x(), room.y(), t});
  AddFurniture(scene, "wall_north", {0, room.y() / 2 + t / 2, room.z() / 2},
               {room.x(), t, room.z()});
  AddFurniture(scene, "wall_south", {0, -room.y() / 2 - t / 2, room.z() / 2},
               {room.x(), t, room.z()});
  AddFurniture(scene, "wall_east", {room.x() / 2 + t / 2, 0, room.z() / 2},
               {t, room.y(), room.z()});
  AddFurniture(scene, "wall_west", {-room.x() / 2 - t / 2, 0, room.z() / 2},
               {t, room.y(), room.z()});
  AddFurniture(scene, "table_top", {0, 0, kTableTop - 0.02}, {kTableLength, kTableWidth, 0.04});
  for (double x : {-kTableLength / 2 + 0.08, kTableLength / 2 - 0.08}) {
    for (double y : {-kTableWidth / 2 + 0.08, kTableWidth / 2 - 0.08}) {
      AddFurniture(scene, "table_leg", {x, y, (kTableTop - 0.04) / 2},
                   {0.05, 0.05, kTableTop - 0.04});
    }
  }
  AddFurniture(scene, "partition", {0, 0, kTableTop + 0.24}, {kTableLength, 0.03, 0.48});
  AddFurniture(scene, "cabinet_east", {room.x() / 2 - 0.3, 0.8, 0.45}, {0.5, 1.4, 0.9});
  AddFurniture(scene, "cabinet_west", {-room.x() / 2 + 0.3, -0.9, 0.5}, {0.5, 1.2, 1.0});
  AddFurniture(scene, "shelf_north", {0.6, room.y() / 2 - 0.2, 1.0}, {1.6, 0.35, 2.0});
}

class Placer {
 public:
  Placer(Scene& scene, std::mt19937_64& rng) : scene_(scene), rng_(rng) {}

  // A free place on one half of the table (side -1: y < 0, +1: y > 0), or nullopt. A move
  // (away_from set) must take the object at least its largest extent, and 0.25 m, from
  // where it was: a shift within its own footprint is not a move anyone could measure.
  std::optional<Eigen::Vector3d> FreePlace(const ObjectKind& kind, int side, int ignore_id = -1,
                                           const Eigen::Vector3d* away_from = nullptr) {
    const double min_move = std::max(0.25, kind.size.maxCoeff());
    const Eigen::Vector2d half = Footprint(kind.size);
    std::uniform_real_distribution<double> x(-kTableLength / 2 + half.x() + 0.03,
                                             kTableLength / 2 - half.x() - 0.03);
    std::uniform_real_distribution<double> y(0.04 + half.y(), kTableWidth / 2 - half.y() - 0.03);
    for (int attempt = 0; attempt < 400; ++attempt) {
      const Eigen::Vector3d centre(x(rng_), side * y(rng_), kTableTop + kind.size.z() / 2);
      if (away_from != nullptr && (centre - *away_from).head<2>().norm() < min_move) continue;
      if (IsFree(centre, half, ignore_id)) return centre;
    }
    return std::nullopt;
  }

  // Whether an object of this kind fits at centre (every pose of every other object counts).
  bool Fits(const ObjectKind& kind, const Eigen::Vector3d& centre, int ignore_id) const {
    return IsFree(centre, Footprint(kind.size), ignore_id);
  }

  // Adds an object on one half of the table; absent_at_start: it appears later (an
  // addition), and its first pose holds the place it will appear at.
  bool Add(int side, bool absent_at_start = false) {
    std::uniform_int_distribution<size_t> pick(0, std::size(kDeskKinds) - 1);
    const ObjectKind& kind = kDeskKinds[pick(rng_)];
    auto centre = FreePlace(kind, side);
    if (!centre) centre = FreePlace(kind, -side);  // this half is full: the other one
    // The table is full: the cabinet tops (for objects that never move).
    if (!centre && !absent_at_start) centre = FreePlaceOnCabinet(kind);
    if (!centre) return false;
    SceneObject object;
    object.id = 1;  // after every id in use: a later visit's scene may have gaps
    for (const SceneObject& other : scene_.objects) object.id = std::max(object.id, other.id + 1);
    object.class_id = kind.class_id;
    object.shape = kind.shape;
    object.size = kind.size;
    object.texture_seed = scene_.seed * 100000 + static_cast<std::uint64_t>(object.id);
    PlacedPose pose;
    pose.centre = *centre;
    pose.yaw = std::uniform_real_distribution<double>(-kMaxYaw, kMaxYaw)(rng_);
    pose.present = !absent_at_start;
    object.history.push_back(pose);
    scene_.objects.push_back(object);
    return true;
  }

 private:
  // A free place on top of one of the cabinets (AddRoom's cabinet_east / cabinet_west).
  std::optional<Eigen::Vector3d> FreePlaceOnCabinet(const ObjectKind& kind) {
    const Eigen::Vector2d half = Footprint(kind.size);
    for (const Furniture& item : scene_.furniture) {
      if (item.name.rfind("cabinet", 0) != 0) continue;
      const Eigen::Vector2d room = 0.5 * item.size.head<2>() - half - Eigen::Vector2d(0.03, 0.03);
      if ((room.array() <= 0).any()) continue;
      std::uniform_real_distribution<double> x(-room.x(), room.x()), y(-room.y(), room.y());
      for (int attempt = 0; attempt < 100; ++attempt) {
        const Eigen::Vector3d centre(item.centre.x() + x(rng_), item.centre.y() + y(rng_),
                                     item.centre.z() + item.size.z() / 2 + kind.size.z() / 2);
        if (IsFree(centre, half, -1)) return centre;
      }
    }
    return std::nullopt;
  }

  // Half extents on the table of an object turned by at most kMaxYaw, as an axis-aligned
  // rectangle (packs desks far better than circles).
  static Eigen::Vector2d Footprint(const Eigen::Vector3d& size) {
    const double slack = std::sin(kMaxYaw) * 0.5 * std::max(size.x(), size.y());
    return {0.5 * size.x() + slack, 0.5 * size.y() + slack};
  }

  // Every pose counts, present or not: a future addition's place is reserved too.
  bool IsFree(const Eigen::Vector3d& centre, const Eigen::Vector2d& half, int ignore_id) const {
    for (const SceneObject& other : scene_.objects) {
      if (other.id == ignore_id) continue;
      const Eigen::Vector2d other_half = Footprint(other.size);
      for (const PlacedPose& pose : other.history) {
        const Eigen::Vector2d gap = (pose.centre - centre).head<2>().cwiseAbs();
        if (gap.x() < half.x() + other_half.x() + 0.03 &&
            gap.y() < half.y() + other_half.y() + 0.03) {
          return false;
        }
      }
    }
    return true;
  }

  Scene& scene_;
  std::mt19937_64& rng_;
};

struct PresetSpec {
  std::string name;
  std::string path;
  double duration;
  double fps;
  int objects;
  int moves;
  int removals;
  int additions;
};

// Durations give the camera time to see everything (a lap), to be away while objects
// change (moves start after 0.8 laps) and to come back and leave again (about 2.8 laps).
const PresetSpec kPresets[] = {
    {"smoke", "round", 55.0, 10.0, 8, 1, 0, 0},
    {"straight_1", "straight", 110.0, 30.0, 28, 7, 0, 0},
    {"straight_2", "straight", 120.0, 30.0, 32, 9, 1, 1},
    {"round_1", "round", 100.0, 30.0, 38, 6, 0, 0},
    {"round_2", "round", 120.0, 30.0, 40, 9, 1, 1},
    {"desk_static", "round", 60.0, 30.0, 30, 0, 0, 0},
    // A lap and a quarter (35.9 s laps): the whole room mapped, for a later visit.
    {"session_a", "round", 45.0, 30.0, 24, 0, 0, 0},
    // desk_static with people walking through (PlanWalkers): same layout and camera.
    {"walkers", "round", 60.0, 30.0, 30, 0, 0, 0},
};

const PresetSpec* LookupPreset(const std::string& name) {
  for (const PresetSpec& spec : kPresets) {
    if (spec.name == name) return &spec;
  }
  return nullptr;
}

const PresetSpec& FindPreset(const std::string& name) {
  if (const PresetSpec* spec = LookupPreset(name)) return *spec;
  std::string names;
  for (const PresetSpec& spec : kPresets) names += (names.empty() ? "" : ", ") + spec.name;
  throw std::invalid_argument("unknown preset '" + name + "' (use " + names + ")");
}

}  // namespace

std::vector<std::string> PresetNames() {
  std::vector<std::string> names;
  for (const PresetSpec& spec : kPresets) names.push_back(spec.name);
  return names;
}

Scene MakePreset(const std::string& name, std::uint64_t seed) {
  const PresetSpec& spec = FindPreset(name);
  Scene scene;
  scene.name = spec.name;
  scene.seed = seed;
  scene.camera = TumLikeCamera();
  scene.fps = spec.fps;
  scene.duration = spec.duration;
  scene.path.kind = spec.path;
  scene.path.speed = name == "smoke" ? 0.4 : 0.35;
  if (name == "smoke") scene.path.radius = 1.4;  // a shorter lap: 27.5 s
  if (name == "walkers") {
    // Room for people between the camera and the table: a wider path (3 x 2.4 m) in a
    // larger room, the camera 1.75 m from the table's long sides.
    scene.path.radius = 2.4;
    scene.room_size = Eigen::Vector3d(8.6, 7.0, 2.8);
  }
  AddRoom(scene);
  std::mt19937_64 rng(seed);
  Placer placer(scene, rng);
  // A kind that does not fit any more is replaced by another (usually smaller) one.
  for (int i = 0; i < spec.objects; ++i) {
    for (int attempt = 0; attempt < 12 && !placer.Add(i % 2 == 0 ? -1 : 1); ++attempt) {
    }
  }
  for (int i = 0; i < spec.additions; ++i)
    placer.Add(i % 2 == 0 ? 1 : -1, /*absent_at_start=*/true);
  if (name == "walkers") scene.walkers = PlanWalkers(scene, seed);
  scene.Check();
  return scene;
}

namespace {

// An axis-aligned floor rectangle a walker's centre must stay out of.
struct FloorBlock {
  Eigen::Vector2d low, high;
  bool Contains(const Eigen::Vector2d& p) const {
    return (p.array() >= low.array()).all() && (p.array() <= high.array()).all();
  }
};

// How a candidate pass meets the camera: too close at some time, and its seconds in view.
struct PassView {
  bool too_close = false;
  double seconds_in_view = 0.0;
};

constexpr double kWalkerStep = 0.05;  // seconds between the checks along a pass

PassView ViewOfPass(const Scene& scene, const Walker& walker, double min_camera_distance) {
  PassView view;
  for (double t = walker.StartTime(); t <= walker.EndTime(); t += kWalkerStep) {
    const PlacedPose pose = *walker.PoseAt(t);
    const SE3 T_cw = CameraPoseAt(scene, t);
    const Eigen::Vector3d eye = T_cw.Inverse().translation();
    const double distance = (eye.head<2>() - pose.centre.head<2>()).norm();
    if (distance < min_camera_distance) {
      view.too_close = true;
      return view;
    }
    bool in_view = false;
    for (const double z : {0.3, 0.9, 1.5}) {
      const Eigen::Vector3d p = T_cw * Eigen::Vector3d(pose.centre.x(), pose.centre.y(), z);
      if (p.z() < 0.1) continue;
      const Eigen::Vector2d pixel = scene.camera.ProjectUndistorted(p);
      in_view = in_view || (pixel.x() >= 0 && pixel.x() < scene.camera.width && pixel.y() >= 0 &&
                            pixel.y() < scene.camera.height);
    }
    if (in_view) view.seconds_in_view += kWalkerStep;
  }
  return view;
}

// Whether two walkers come closer than their bodies allow at any time both are there.
bool WalkersCollide(const Walker& a, const Walker& b) {
  const double from = std::max(a.StartTime(), b.StartTime());
  const double to = std::min(a.EndTime(), b.EndTime());
  for (double t = from; t <= to; t += kWalkerStep) {
    const auto pa = a.PoseAt(t), pb = b.PoseAt(t);
    if (pa && pb && (pa->centre - pb->centre).norm() < a.Radius() + b.Radius() + 0.1) return true;
  }
  return false;
}

}  // namespace

std::vector<Walker> PlanWalkers(const Scene& scene, std::uint64_t seed, double first_time,
                                double min_camera_distance) {
  std::mt19937_64 rng(seed * 7919 + 17);  // not the layout's generator: the room stays as it is
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto uniform = [&](double low, double high) { return low + (high - low) * unit(rng); };
  const double height = 1.75;
  const double radius = Walker().Radius();
  // Furniture standing on the floor, grown by the body's radius and a little air.
  std::vector<FloorBlock> blocks;
  for (const Furniture& item : scene.furniture) {
    const bool stands_on_floor = item.name == "table_top" || item.name.rfind("cabinet", 0) == 0 ||
                                 item.name.rfind("shelf", 0) == 0;
    if (!stands_on_floor) continue;
    const Eigen::Vector2d half =
        0.5 * item.size.head<2>() + Eigen::Vector2d::Constant(radius + 0.05);
    blocks.push_back({item.centre.head<2>() - half, item.centre.head<2>() + half});
  }
  const Eigen::Vector2d floor_half =
      0.5 * scene.room_size.head<2>() - Eigen::Vector2d::Constant(radius + 0.15);
  auto free = [&](const Eigen::Vector2d& p) {
    if ((p.cwiseAbs().array() > floor_half.array()).any()) return false;
    for (const FloorBlock& block : blocks) {
      if (block.Contains(p)) return false;
    }
    return true;
  };
  std::vector<Walker> walkers;
  int pass = 0;
  for (double slot = first_time; slot < scene.duration - 2.0; slot += uniform(1.5, 5.0), ++pass) {
    int in_room = 0;
    for (const Walker& other : walkers) in_room += other.EndTime() > slot ? 1 : 0;
    if (in_room >= 2) continue;
    // Two passes in three cross the camera's view close in front of it (as near as
    // min_camera_distance allows): the large occluders; the others go anywhere.
    const bool near = pass % 3 != 2;
    std::optional<Walker> chosen;
    for (int attempt = 0; attempt < 300 && !chosen; ++attempt) {
      const double speed = uniform(0.8, 1.3);
      Eigen::Vector2d a, b;
      double start = slot;
      // Where the camera looks at a table's corner no one fits in front of it: after half
      // the attempts, a pass anywhere.
      if (near && attempt < 150) {
        // Through the optical axis, D ahead of where the camera will be when the walker
        // crosses it, along the table's edge the camera faces (so it passes the table).
        const double crossing = slot + uniform(1.0, 2.5);
        const SE3 T_wc = CameraPoseAt(scene, crossing).Inverse();
        const Eigen::Vector2d eye = T_wc.translation().head<2>();
        const Eigen::Vector3d axis = T_wc.rotation().col(2);
        if (axis.head<2>().norm() < 1e-6) continue;
        const Eigen::Vector2d forward = axis.head<2>().normalized();
        const Eigen::Vector2d across = std::abs(forward.y()) > std::abs(forward.x())
                                           ? Eigen::Vector2d::UnitX()
                                           : Eigen::Vector2d::UnitY();
        const Eigen::Vector2d centre =
            eye + uniform(min_camera_distance + 0.05, min_camera_distance + 0.45) * forward;
        const double side = unit(rng) < 0.5 ? -1.0 : 1.0;
        const double half = uniform(1.5, 2.2);
        a = centre - side * half * across;
        b = centre + side * half * across;
        start = crossing - half / speed;
        if (start < first_time) continue;
      } else {
        auto floor_point = [&] {
          return Eigen::Vector2d(uniform(-floor_half.x(), floor_half.x()),
                                 uniform(-floor_half.y(), floor_half.y()));
        };
        a = floor_point();
        b = floor_point();
      }
      const double length = (b - a).norm();
      if (length < 2.5) continue;
      bool clear = true;
      for (double s = 0.0; s <= length && clear; s += 0.05)
        clear = free(a + (s / length) * (b - a));
      if (!clear || !free(b)) continue;
      Walker walker;
      walker.id = static_cast<int>(walkers.size()) + 1;
      walker.height = height;
      walker.texture_seed = scene.seed * 7000000 + static_cast<std::uint64_t>(walker.id);
      walker.waypoints.push_back({start, a});
      if (unit(rng) < 1.0 / 3.0) {  // stops on the way
        const double share = uniform(0.3, 0.7);
        const Eigen::Vector2d stop = a + share * (b - a);
        const double arrive = start + share * length / speed;
        walker.waypoints.push_back({arrive, stop});
        walker.waypoints.push_back({arrive + uniform(1.0, 2.5), stop});
      }
      walker.waypoints.push_back(
          {walker.waypoints.back().time + (b - walker.waypoints.back().position).norm() / speed,
           b});
      if (walker.EndTime() > scene.duration) continue;
      const PassView view = ViewOfPass(scene, walker, min_camera_distance);
      if (view.too_close || view.seconds_in_view < 1.0) continue;
      bool collides = false;
      for (const Walker& other : walkers) collides = collides || WalkersCollide(walker, other);
      if (!collides) chosen = walker;
    }
    if (chosen) walkers.push_back(*chosen);
  }
  return walkers;
}

namespace {

// Stand-ins for the moves and removals, for ScheduleMoves when a change has no moment at
// which it goes unseen: a move across the partition on a round path (its own half was
// full) shows one of its two places at every moment. Per move, in order: the same object to
// another place on its own half (the partition hides both places from the same stretch of
// path); objects of the new place's half that change in no plan, into that place; such
// objects to a free place on their own half. Per removal: such objects removed. Up to four
// per change. planning holds every planned place, and each stand-in's place is reserved in
// it as it is drawn; the generator is their own, so the planned changes stay as drawn.
void AddAlternatives(Scene& planning, std::uint64_t seed, std::vector<PlannedMove>& moves) {
  constexpr std::size_t kMaxAlternatives = 4;
  std::mt19937_64 rng(seed * 31 + 13);
  Placer placer(planning, rng);
  std::set<int> taken;  // objects that change in a plan or a stand-in already
  for (const PlannedMove& move : moves) taken.insert(move.object_id);
  auto free_on_table = [&](const SceneObject& object) {
    const double on_table = kTableTop + object.size.z() / 2;
    return taken.count(object.id) == 0 && object.history[0].present &&
           std::abs(object.history[0].centre.z() - on_table) < 1e-9;
  };
  auto reserve = [](SceneObject& object, const PlannedMove& change) {
    PlacedPose marker = object.history[0];  // reserve the place for later choices
    marker.time = 1.0;
    marker.present = !change.removal;
    marker.centre = change.new_centre;
    object.history.push_back(marker);
  };
  // object to a free place on its own half (or removed)
  auto elsewhere = [&](SceneObject& object, bool removal) -> std::optional<PlannedMove> {
    PlannedMove alternative;
    alternative.object_id = object.id;
    alternative.removal = removal;
    if (!removal) {
      const ObjectKind kind{object.class_id, object.shape, object.size};
      const int side = object.history[0].centre.y() < 0 ? -1 : 1;
      const auto place = placer.FreePlace(kind, side, object.id, &object.history[0].centre);
      if (!place) return std::nullopt;
      alternative.new_centre = *place;
      alternative.new_yaw = std::uniform_real_distribution<double>(-kMaxYaw, kMaxYaw)(rng);
    }
    reserve(object, alternative);
    return alternative;
  };
  for (PlannedMove& move : moves) {
    SceneObject* object = planning.FindObject(move.object_id);
    if (object == nullptr || !object->history[0].present) continue;  // an addition
    std::vector<PlannedMove>& alternatives = move.alternatives;
    if (!move.removal) {
      if (auto alternative = elsewhere(*object, false)) alternatives.push_back(*alternative);
      // Into the planned place, which the planned object then leaves free.
      const std::vector<PlacedPose> reserved = object->history;
      object->history.resize(1);
      for (SceneObject& other : planning.objects) {
        if (alternatives.size() >= kMaxAlternatives - 1) break;
        if (!free_on_table(other) ||
            (other.history[0].centre.y() < 0) != (move.new_centre.y() < 0)) {
          continue;
        }
        const ObjectKind kind{other.class_id, other.shape, other.size};
        Eigen::Vector3d centre = move.new_centre;
        centre.z() = kTableTop + other.size.z() / 2;
        const double min_move = std::max(0.25, other.size.maxCoeff());
        if ((centre - other.history[0].centre).head<2>().norm() < min_move ||
            !placer.Fits(kind, centre, other.id)) {
          continue;
        }
        PlannedMove alternative;
        alternative.object_id = other.id;
        alternative.new_centre = centre;
        alternative.new_yaw = move.new_yaw;
        reserve(other, alternative);
        alternatives.push_back(alternative);
        taken.insert(other.id);
      }
      object->history = reserved;
    }
    for (SceneObject& other : planning.objects) {
      if (alternatives.size() >= kMaxAlternatives) break;
      if (!free_on_table(other)) continue;
      if (auto alternative = elsewhere(other, move.removal)) {
        alternatives.push_back(*alternative);
        taken.insert(other.id);
      }
    }
    for (PlannedMove& alternative : alternatives) alternative.earliest = move.earliest;
  }
}

}  // namespace

std::vector<PlannedMove> PresetMoves(const std::string& name, const Scene& scene,
                                     std::uint64_t seed) {
  const PresetSpec* spec = LookupPreset(name);
  if (spec == nullptr || spec->moves + spec->removals + spec->additions == 0) return {};
  std::mt19937_64 rng(seed * 31 + 7);
  Scene planning = scene;  // new places must not collide with earlier moves
  Placer placer(planning, rng);
  std::vector<PlannedMove> moves;
  const int total = spec->moves + spec->removals + spec->additions;
  // Spread the changes over the middle of the sequence, alternating halves of the table.
  for (int i = 0; i < spec->moves + spec->removals; ++i) {
    const int side = i % 2 == 0 ? 1 : -1;
    for (SceneObject& object : planning.objects) {
      if (object.Moves() || !object.history[0].present ||
          object.history[0].centre.y() * side <= 0) {
        continue;
      }
      const bool removal = i >= spec->moves;
      PlannedMove move;
      move.object_id = object.id;
      move.removal = removal;
      move.earliest = LapDuration(scene.path) * (0.8 + 0.8 * i / std::max(1, total));
      if (!removal) {
        const ObjectKind kind{object.class_id, object.shape, object.size};
        auto place = placer.FreePlace(kind, side, object.id, &object.history[0].centre);
        if (!place) place = placer.FreePlace(kind, -side, object.id, &object.history[0].centre);
        if (!place) continue;
        move.new_centre = *place;
        move.new_yaw = std::uniform_real_distribution<double>(-kMaxYaw, kMaxYaw)(rng);
      }
      PlacedPose marker = object.history[0];  // reserve the new place for later choices
      marker.time = 1.0;
      marker.centre = move.new_centre;
      marker.present = !removal;
      object.history.push_back(marker);
      moves.push_back(move);
      break;
    }
  }
  // Additions: objects absent at the start appear at the place their first pose holds.
  int index = spec->moves + spec->removals;
  for (const SceneObject& object : scene.objects) {
    if (object.history[0].present) continue;
    PlannedMove move;
    move.object_id = object.id;
    move.new_centre = object.history[0].centre;
    move.new_yaw = object.history[0].yaw;
    move.earliest = LapDuration(scene.path) * (0.8 + 0.8 * index++ / std::max(1, total));
    moves.push_back(move);
  }
  AddAlternatives(planning, seed, moves);
  return moves;
}

VisitChanges PresetVisitChanges(const std::string& name) {
  VisitChanges changes;
  if (name == "session_b") return changes;
  const PresetSpec* spec = LookupPreset(name);
  if (spec == nullptr) {
    std::string names = "session_b";
    for (const PresetSpec& known : kPresets) names += ", " + known.name;
    throw std::invalid_argument("unknown preset '" + name + "' for a later visit (use " + names +
                                ")");
  }
  changes.moves = spec->moves;
  changes.removals = spec->removals;
  changes.additions = spec->additions;
  return changes;
}

Scene MakeLaterVisit(const Scene& previous, const VisitChanges& changes, std::uint64_t seed) {
  if (changes.moves < 0 || changes.removals < 0 || changes.additions < 0)
    throw std::invalid_argument("visit changes: counts must be >= 0");
  // The later visit starts on ground the previous one saw only if it covered a lap.
  if (previous.duration < LapDuration(previous.path)) {
    throw std::invalid_argument("visit changes: the previous visit ('" + previous.name +
                                "') lasts " + std::to_string(previous.duration) +
                                " s, less than a lap of its path (" +
                                std::to_string(LapDuration(previous.path)) +
                                " s): a later visit could start where it never looked");
  }
  Scene scene = previous;
  scene.seed = seed;
  scene.session.index = previous.session.index + 1;
  scene.session.previous = previous.name;
  scene.session.previous_end = previous.time_origin + previous.duration;
  scene.name = previous.name + "_visit" + std::to_string(scene.session.index + 1);
  scene.time_origin = scene.session.previous_end + changes.gap;
  if (changes.duration > 0) scene.duration = changes.duration;
  scene.path.start = std::fmod(previous.path.start + changes.path_start, 1.0);
  // Where the previous visit left every object: objects gone by then stay gone.
  scene.objects.clear();
  for (const SceneObject& object : previous.objects) {
    const PlacedPose last = object.history.back();
    if (!last.present) continue;
    SceneObject kept = object;
    kept.history = {last};
    kept.history[0].time = 0.0;
    kept.before_session.reset();
    scene.objects.push_back(kept);
  }
  std::mt19937_64 rng(seed * 31 + 11);
  std::vector<std::size_t> order(scene.objects.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::shuffle(order.begin(), order.end(), rng);
  if (static_cast<std::size_t>(changes.moves + changes.removals) > order.size())
    throw std::invalid_argument("visit changes: more moves and removals than objects");
  Placer placer(scene, rng);
  int moved = 0, removed = 0;
  for (std::size_t index : order) {
    if (moved == changes.moves && removed == changes.removals) break;
    SceneObject& object = scene.objects[index];
    const PlacedPose before = object.history[0];
    if (removed < changes.removals && moved == changes.moves) {
      object.before_session = before;
      object.history[0].present = false;
      ++removed;
      continue;
    }
    const ObjectKind kind{object.class_id, object.shape, object.size};
    const int side = before.centre.y() < 0 ? -1 : 1;
    auto place = placer.FreePlace(kind, side, object.id, &before.centre);
    if (!place) place = placer.FreePlace(kind, -side, object.id, &before.centre);
    if (!place) continue;  // no room for it: another object moves instead
    object.before_session = before;
    object.history[0].centre = *place;
    object.history[0].yaw = std::uniform_real_distribution<double>(-kMaxYaw, kMaxYaw)(rng);
    // The old place stays reserved while the rest is placed (Placer avoids every pose of a
    // history), so no addition lands where an object was; dropped below.
    PlacedPose reserve = before;
    reserve.time = 1.0;
    object.history.push_back(reserve);
    ++moved;
  }
  if (moved < changes.moves)
    throw std::invalid_argument("visit changes: no free place on the table for every move");
  for (int i = 0; i < changes.additions; ++i) {
    const int side = i % 2 == 0 ? 1 : -1;
    bool placed = placer.Add(side);
    if (!placed) {  // a full table: the places moved objects left are free after all
      for (SceneObject& object : scene.objects) object.history.resize(1);
      placed = placer.Add(side);
    }
    if (!placed)
      throw std::invalid_argument("visit changes: no free place on the table for an addition");
    SceneObject& added = scene.objects.back();
    added.before_session = added.history[0];
    added.before_session->present = false;
  }
  for (SceneObject& object : scene.objects) object.history.resize(1);
  scene.Check();
  return scene;
}

}  // namespace ocg::sim
