#include "ocg/sim/scene_io.h"

#include <yaml-cpp/yaml.h>

#include "ocg/core/file_io.h"
#include "ocg/core/settings_file.h"
#include "ocg/sim/detector.h"

namespace ocg::sim {
namespace {

class Reader {
 public:
  explicit Reader(std::string name) : name_(std::move(name)) {}

  [[noreturn]] void Fail(const YAML::Node& node, const std::string& field,
                         const std::string& message) const {
    throw SettingsError(FileLocation(name_, node.Mark().line + 1) + ": field '" + field +
                        "': " + message);
  }

  // The sections: a present node of another shape is an error, not an empty section.
  YAML::Node Map(const YAML::Node& parent, const std::string& key) const {
    const YAML::Node node = parent[key];
    if (node && !node.IsNull() && !node.IsMap()) Fail(node, key, "expected a map of fields");
    return node;
  }
  YAML::Node List(const YAML::Node& parent, const std::string& key, const std::string& path) const {
    const YAML::Node node = parent[key];
    if (node && !node.IsNull() && !node.IsSequence()) Fail(node, path + key, "expected a list");
    return node;
  }

  template <typename T>
  void Optional(const YAML::Node& parent, const std::string& key, const std::string& path,
                T* value) const {
    const YAML::Node node = parent[key];
    if (!node) return;
    try {
      *value = node.as<T>();
    } catch (const YAML::Exception&) {
      Fail(node, path + key, "wrong type");
    }
  }

  void Vector(const YAML::Node& parent, const std::string& key, const std::string& path,
              Eigen::Vector3d* value, bool required = false) const {
    const YAML::Node node = parent[key];
    if (!node) {
      if (required) Fail(parent, path + key, "missing");
      return;
    }
    std::vector<double> items;
    try {
      items = node.as<std::vector<double>>();
    } catch (const YAML::Exception&) {
      Fail(node, path + key, "expected a list of 3 numbers");
    }
    if (items.size() != 3) Fail(node, path + key, "expected a list of 3 numbers");
    *value = Eigen::Vector3d(items[0], items[1], items[2]);
  }

 private:
  std::string name_;
};

YAML::Node VectorNode(const Eigen::Vector3d& v) {
  YAML::Node node;
  node.SetStyle(YAML::EmitterStyle::Flow);
  node.push_back(v.x());
  node.push_back(v.y());
  node.push_back(v.z());
  return node;
}

// The fields of a parsed scene file; yaml-cpp throws when a node has the wrong shape.
SceneFile ReadSceneFields(const YAML::Node& root, const std::string& name) {
  const Reader read(name);
  SceneFile file;
  Scene& scene = file.scene;
  read.Optional(root, "name", "", &scene.name);
  read.Optional(root, "seed", "", &scene.seed);
  read.Optional(root, "fps", "", &scene.fps);
  read.Optional(root, "duration", "", &scene.duration);
  read.Optional(root, "time_origin", "", &scene.time_origin);
  if (const YAML::Node session = read.Map(root, "session")) {
    read.Optional(session, "index", "session.", &scene.session.index);
    read.Optional(session, "previous", "session.", &scene.session.previous);
    read.Optional(session, "previous_end", "session.", &scene.session.previous_end);
  }
  read.Optional(root, "ambient", "", &scene.ambient);
  read.Vector(root, "room_size", "", &scene.room_size);
  read.Vector(root, "light_direction", "", &scene.light_direction);
  if (const YAML::Node camera = read.Map(root, "camera")) {
    read.Optional(camera, "fx", "camera.", &scene.camera.fx);
    read.Optional(camera, "fy", "camera.", &scene.camera.fy);
    read.Optional(camera, "cx", "camera.", &scene.camera.cx);
    read.Optional(camera, "cy", "camera.", &scene.camera.cy);
    read.Optional(camera, "width", "camera.", &scene.camera.width);
    read.Optional(camera, "height", "camera.", &scene.camera.height);
  }
  if (const YAML::Node path = read.Map(root, "path")) {
    read.Optional(path, "kind", "path.", &scene.path.kind);
    read.Optional(path, "radius", "path.", &scene.path.radius);
    read.Optional(path, "side_offset", "path.", &scene.path.side_offset);
    read.Optional(path, "height", "path.", &scene.path.height);
    read.Optional(path, "speed", "path.", &scene.path.speed);
    read.Optional(path, "jitter", "path.", &scene.path.jitter);
    read.Optional(path, "start", "path.", &scene.path.start);
  }
  if (const YAML::Node noise = read.Map(root, "noise")) {
    DetectionNoise& n = scene.noise;
    read.Optional(noise, "perfect", "noise.", &n.perfect);
    read.Optional(noise, "min_visible_pixels", "noise.", &n.min_visible_pixels);
    read.Optional(noise, "box_jitter", "noise.", &n.box_jitter);
    read.Optional(noise, "miss_base", "noise.", &n.miss_base);
    read.Optional(noise, "miss_occlusion", "noise.", &n.miss_occlusion);
    read.Optional(noise, "miss_truncation", "noise.", &n.miss_truncation);
    read.Optional(noise, "miss_small", "noise.", &n.miss_small);
    read.Optional(noise, "small_box_pixels", "noise.", &n.small_box_pixels);
    read.Optional(noise, "burst_continue", "noise.", &n.burst_continue);
    read.Optional(noise, "confusion", "noise.", &n.confusion);
    read.Optional(noise, "false_positives_per_frame", "noise.", &n.false_positives_per_frame);
    read.Optional(noise, "duplicate", "noise.", &n.duplicate);
    std::string model = DetectorKindName(n.kind);
    read.Optional(noise, "model", "noise.", &model);
    try {
      n.kind = DetectorKindFromName(model);
    } catch (const std::invalid_argument& error) {
      read.Fail(noise["model"], "noise.model", error.what());
    }
    if (const YAML::Node realistic = read.Map(noise, "realistic")) {
      read.Optional(realistic, "seed", "noise.realistic.", &n.realistic.seed);
      for (const RealisticField& field : RealisticFields()) {
        read.Optional(realistic, field.name, "noise.realistic.", &(n.realistic.*field.member));
      }
    }
  }
  if (const YAML::Node look = read.Map(root, "look")) {
    LookOptions& l = scene.look;
    std::string kind = "procedural";
    read.Optional(look, "kind", "look.", &kind);
    try {
      l.kind = LookKindFromName(kind);
    } catch (const std::invalid_argument& error) {
      read.Fail(look["kind"], "look.kind", error.what());
    }
    read.Optional(look, "min_exposure_ms", "look.", &l.min_exposure_ms);
    read.Optional(look, "max_exposure_ms", "look.", &l.max_exposure_ms);
    read.Optional(look, "max_gain", "look.", &l.max_gain);
    read.Optional(look, "target_brightness", "look.", &l.target_brightness);
    read.Optional(look, "exposure_adaptation", "look.", &l.exposure_adaptation);
    read.Optional(look, "illumination_variation", "look.", &l.illumination_variation);
    read.Optional(look, "vignetting", "look.", &l.vignetting);
    read.Optional(look, "shot_noise", "look.", &l.shot_noise);
    read.Optional(look, "read_noise", "look.", &l.read_noise);
    read.Optional(look, "optical_blur", "look.", &l.optical_blur);
    read.Optional(look, "rolling_shutter_ms", "look.", &l.rolling_shutter_ms);
    read.Optional(look, "max_blur_samples", "look.", &l.max_blur_samples);
    read.Optional(look, "k1", "look.", &l.k1);
    read.Optional(look, "k2", "look.", &l.k2);
    read.Optional(look, "k3", "look.", &l.k3);
    read.Optional(look, "p1", "look.", &l.p1);
    read.Optional(look, "p2", "look.", &l.p2);
  }
  const YAML::Node furniture = read.List(root, "furniture", "");
  for (size_t i = 0; furniture && i < furniture.size(); ++i) {
    const std::string path = "furniture[" + std::to_string(i) + "].";
    Furniture item;
    read.Optional(furniture[i], "name", path, &item.name);
    read.Vector(furniture[i], "centre", path, &item.centre, true);
    read.Vector(furniture[i], "size", path, &item.size, true);
    read.Optional(furniture[i], "yaw", path, &item.yaw);
    read.Optional(furniture[i], "texture_seed", path, &item.texture_seed);
    scene.furniture.push_back(item);
  }
  const YAML::Node objects = read.List(root, "objects", "");
  for (size_t i = 0; objects && i < objects.size(); ++i) {
    const YAML::Node node = objects[i];
    const std::string path = "objects[" + std::to_string(i) + "].";
    SceneObject object;
    read.Optional(node, "id", path, &object.id);
    read.Optional(node, "class_id", path, &object.class_id);
    std::string shape = "box";
    read.Optional(node, "shape", path, &shape);
    if (shape != "box" && shape != "cylinder")
      read.Fail(node, path + "shape", "must be box or cylinder");
    object.shape = shape == "box" ? Shape::kBox : Shape::kCylinder;
    read.Vector(node, "size", path, &object.size, true);
    read.Optional(node, "texture_seed", path, &object.texture_seed);
    const YAML::Node history = read.List(node, "history", path);
    if (!history || history.size() == 0)
      read.Fail(node, path + "history", "needs at least the pose at time 0");
    for (size_t k = 0; k < history.size(); ++k) {
      const std::string pose_path = path + "history[" + std::to_string(k) + "].";
      PlacedPose pose;
      read.Optional(history[k], "time", pose_path, &pose.time);
      read.Optional(history[k], "present", pose_path, &pose.present);
      read.Vector(history[k], "centre", pose_path, &pose.centre, pose.present);
      read.Optional(history[k], "yaw", pose_path, &pose.yaw);
      object.history.push_back(pose);
    }
    if (const YAML::Node before = read.Map(node, "before_session")) {
      PlacedPose pose;
      read.Optional(before, "present", path + "before_session.", &pose.present);
      read.Vector(before, "centre", path + "before_session.", &pose.centre, pose.present);
      read.Optional(before, "yaw", path + "before_session.", &pose.yaw);
      object.before_session = pose;
    }
    scene.objects.push_back(object);
  }
  const YAML::Node walkers = read.List(root, "walkers", "");
  for (size_t i = 0; walkers && i < walkers.size(); ++i) {
    const YAML::Node node = walkers[i];
    const std::string path = "walkers[" + std::to_string(i) + "].";
    Walker walker;
    read.Optional(node, "id", path, &walker.id);
    read.Optional(node, "height", path, &walker.height);
    read.Optional(node, "texture_seed", path, &walker.texture_seed);
    const YAML::Node waypoints = read.List(node, "waypoints", path);
    if (!waypoints || waypoints.size() < 2)
      read.Fail(node, path + "waypoints", "needs at least 2 waypoints [time, x, y]");
    for (size_t k = 0; k < waypoints.size(); ++k) {
      const std::string field = path + "waypoints[" + std::to_string(k) + "]";
      std::vector<double> items;
      try {
        items = waypoints[k].as<std::vector<double>>();
      } catch (const YAML::Exception&) {
        read.Fail(waypoints[k], field, "expected [time, x, y]");
      }
      if (items.size() != 3) read.Fail(waypoints[k], field, "expected [time, x, y]");
      walker.waypoints.push_back({items[0], Eigen::Vector2d(items[1], items[2])});
    }
    scene.walkers.push_back(walker);
  }
  const YAML::Node moves = read.List(root, "moves", "");
  for (size_t i = 0; moves && i < moves.size(); ++i) {
    const std::string path = "moves[" + std::to_string(i) + "].";
    PlannedMove move;
    read.Optional(moves[i], "object_id", path, &move.object_id);
    read.Optional(moves[i], "removal", path, &move.removal);
    read.Optional(moves[i], "earliest", path, &move.earliest);
    read.Optional(moves[i], "new_yaw", path, &move.new_yaw);
    read.Vector(moves[i], "new_centre", path, &move.new_centre, !move.removal);
    file.moves.push_back(move);
  }
  try {
    scene.Check();
  } catch (const std::invalid_argument& error) {
    throw SettingsError(name + ": " + error.what());
  }
  return file;
}

}  // namespace

SceneFile LoadSceneFile(const std::string& path) {
  try {
    return ParseSceneYaml(ReadTextFile(path), path);
  } catch (const FileError& error) {
    throw SettingsError(std::string("scene: ") + error.what());
  }
}

SceneFile ParseSceneYaml(const std::string& text, const std::string& name) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& error) {
    throw SettingsError(FileLocation(name, error.mark.line + 1) + ": not valid YAML: " + error.msg);
  }
  if (root && !root.IsNull() && !root.IsMap()) {
    throw SettingsError(FileLocation(name, root.Mark().line + 1) +
                        ": expected a map of scene fields at the top level");
  }
  try {
    return ReadSceneFields(root, name);
  } catch (const YAML::Exception& error) {
    // A field of the wrong shape (a list or scalar where a map is expected, or the
    // reverse): yaml-cpp's own exceptions never leave the reader.
    throw SettingsError(FileLocation(name, error.mark.line + 1) +
                        ": a field has the wrong structure: " + error.msg);
  }
}

std::string SceneToYaml(const Scene& scene) {
  YAML::Node root;
  root["name"] = scene.name;
  root["seed"] = scene.seed;
  root["fps"] = scene.fps;
  root["duration"] = scene.duration;
  // Later visits only: first visits' files stay as they were.
  if (scene.time_origin != Scene().time_origin) root["time_origin"] = scene.time_origin;
  if (scene.session.index > 0) {
    root["session"]["index"] = scene.session.index;
    root["session"]["previous"] = scene.session.previous;
    root["session"]["previous_end"] = scene.session.previous_end;
  }
  root["room_size"] = VectorNode(scene.room_size);
  root["light_direction"] = VectorNode(scene.light_direction);
  root["ambient"] = scene.ambient;
  const PinholeCamera& c = scene.camera;
  root["camera"]["fx"] = c.fx;
  root["camera"]["fy"] = c.fy;
  root["camera"]["cx"] = c.cx;
  root["camera"]["cy"] = c.cy;
  root["camera"]["width"] = c.width;
  root["camera"]["height"] = c.height;
  root["path"]["kind"] = scene.path.kind;
  root["path"]["radius"] = scene.path.radius;
  root["path"]["side_offset"] = scene.path.side_offset;
  root["path"]["height"] = scene.path.height;
  root["path"]["speed"] = scene.path.speed;
  root["path"]["jitter"] = scene.path.jitter;
  if (scene.path.start != 0.0) root["path"]["start"] = scene.path.start;
  const DetectionNoise& n = scene.noise;
  root["noise"]["perfect"] = n.perfect;
  root["noise"]["min_visible_pixels"] = n.min_visible_pixels;
  root["noise"]["box_jitter"] = n.box_jitter;
  root["noise"]["miss_base"] = n.miss_base;
  root["noise"]["miss_occlusion"] = n.miss_occlusion;
  root["noise"]["miss_truncation"] = n.miss_truncation;
  root["noise"]["miss_small"] = n.miss_small;
  root["noise"]["small_box_pixels"] = n.small_box_pixels;
  root["noise"]["burst_continue"] = n.burst_continue;
  root["noise"]["confusion"] = n.confusion;
  root["noise"]["false_positives_per_frame"] = n.false_positives_per_frame;
  root["noise"]["duplicate"] = n.duplicate;
  if (n.kind == DetectorKind::kRealistic) {  // absent otherwise: those files stay as they were
    root["noise"]["model"] = DetectorKindName(n.kind);
    YAML::Node realistic;
    realistic["seed"] = n.realistic.seed;
    for (const RealisticField& field : RealisticFields()) {
      realistic[field.name] = n.realistic.*field.member;
    }
    root["noise"]["realistic"] = realistic;
  }
  if (scene.look.realistic()) {  // absent for the procedural look: its files stay as they were
    const LookOptions& l = scene.look;
    YAML::Node look;
    look["kind"] = LookKindName(l.kind);
    look["min_exposure_ms"] = l.min_exposure_ms;
    look["max_exposure_ms"] = l.max_exposure_ms;
    look["max_gain"] = l.max_gain;
    look["target_brightness"] = l.target_brightness;
    look["exposure_adaptation"] = l.exposure_adaptation;
    look["illumination_variation"] = l.illumination_variation;
    look["vignetting"] = l.vignetting;
    look["shot_noise"] = l.shot_noise;
    look["read_noise"] = l.read_noise;
    look["optical_blur"] = l.optical_blur;
    look["rolling_shutter_ms"] = l.rolling_shutter_ms;
    look["max_blur_samples"] = l.max_blur_samples;
    look["k1"] = l.k1;
    look["k2"] = l.k2;
    look["k3"] = l.k3;
    look["p1"] = l.p1;
    look["p2"] = l.p2;
    root["look"] = look;
  }
  for (const Furniture& item : scene.furniture) {
    YAML::Node node;
    node["name"] = item.name;
    node["centre"] = VectorNode(item.centre);
    node["size"] = VectorNode(item.size);
    node["yaw"] = item.yaw;
    node["texture_seed"] = item.texture_seed;
    root["furniture"].push_back(node);
  }
  for (const SceneObject& object : scene.objects) {
    YAML::Node node;
    node["id"] = object.id;
    node["class_id"] = object.class_id;
    node["shape"] = object.shape == Shape::kBox ? "box" : "cylinder";
    node["size"] = VectorNode(object.size);
    node["texture_seed"] = object.texture_seed;
    for (const PlacedPose& pose : object.history) {
      YAML::Node entry;
      entry["time"] = pose.time;
      entry["present"] = pose.present;
      entry["centre"] = VectorNode(pose.centre);
      entry["yaw"] = pose.yaw;
      node["history"].push_back(entry);
    }
    if (object.before_session) {
      node["before_session"]["present"] = object.before_session->present;
      node["before_session"]["centre"] = VectorNode(object.before_session->centre);
      node["before_session"]["yaw"] = object.before_session->yaw;
    }
    root["objects"].push_back(node);
  }
  for (const Walker& walker : scene.walkers) {  // none: the key is absent, files stay as they were
    YAML::Node node;
    node["id"] = walker.id;
    node["height"] = walker.height;
    node["texture_seed"] = walker.texture_seed;
    for (const Waypoint& waypoint : walker.waypoints) {
      YAML::Node entry;
      entry.SetStyle(YAML::EmitterStyle::Flow);
      entry.push_back(waypoint.time);
      entry.push_back(waypoint.position.x());
      entry.push_back(waypoint.position.y());
      node["waypoints"].push_back(entry);
    }
    root["walkers"].push_back(node);
  }
  YAML::Emitter emitter;
  emitter.SetDoublePrecision(10);
  emitter << root;
  return "# OCG-SLAM synthetic scene (docs/synthetic.md)\n" + std::string(emitter.c_str()) + "\n";
}

}  // namespace ocg::sim
