#include "ocg/viewer/run_scene.h"

#include <algorithm>
#include <filesystem>
#include <iterator>
#include <nlohmann/json.hpp>

#include "ocg/core/file_io.h"
#include "ocg/io/change_entries.h"
#include "ocg/io/point_cloud.h"
#include "ocg/io/text_lines.h"
#include "ocg/io/trajectory.h"
#include "ocg/objects/cuboid_json.h"

namespace ocg {
namespace {

nlohmann::json ReadJson(const std::string& path) {
  try {
    return nlohmann::json::parse(ReadTextFile(path));
  } catch (const nlohmann::json::exception& error) {
    throw ParseError(path + ": " + error.what());
  }
}

}  // namespace

MapScene ReadRunScene(const std::string& run_dir) {
  namespace fs = std::filesystem;
  MapScene scene;
  const char* files[] = {"KeyFrameTrajectory.txt", "CameraTrajectory.txt", "map_points.ply",
                         "objects.json", "changes.json"};
  if (!fs::is_directory(run_dir)) throw FileError("'" + run_dir + "' is not a folder");
  if (std::none_of(std::begin(files), std::end(files),
                   [&](const char* name) { return fs::exists(run_dir + "/" + name); })) {
    throw FileError("'" + run_dir +
                    "' holds no run: none of KeyFrameTrajectory.txt, CameraTrajectory.txt, "
                    "map_points.ply, objects.json, changes.json (the outputs of ocg_slam run, "
                    "ocg_slam objects, ocg_replay)");
  }
  if (fs::exists(run_dir + "/KeyFrameTrajectory.txt")) {
    for (const StampedPose& pose : ReadTumTrajectory(run_dir + "/KeyFrameTrajectory.txt"))
      scene.keyframes.push_back(pose.T_wc);
  }
  if (fs::exists(run_dir + "/run.json") &&
      ReadJson(run_dir + "/run.json").value("command", "") == "objects")
    scene.trajectory_name = "given camera path";
  if (fs::exists(run_dir + "/CameraTrajectory.txt")) {
    for (const StampedPose& pose : ReadTumTrajectory(run_dir + "/CameraTrajectory.txt"))
      scene.trajectory.push_back(pose.T_wc.translation());
  }
  if (fs::exists(run_dir + "/map_points.ply"))
    scene.points = ReadPlyPoints(run_dir + "/map_points.ply");
  const std::string objects_path = run_dir + "/objects.json";
  if (fs::exists(objects_path)) {
    const nlohmann::json objects = ReadJson(objects_path);
    try {
      if (objects.contains("up")) scene.up = VectorFromJson(objects.at("up"));
      for (const nlohmann::json& entry : objects.at("objects")) {
        ObjectView view;
        view.id = entry.at("id").get<ObjectId>();
        view.class_id = entry.at("class_id").get<int>();
        view.cuboid = CuboidFromJson(entry.at("cuboid"));
        view.state = entry.at("state").is_null() ? 0 : entry.at("state").get<int>();
        scene.objects.push_back(view);
      }
    } catch (const std::exception& error) {  // nlohmann's, or VectorFromJson's
      throw ParseError(objects_path + ": " + error.what());
    }
  }
  const std::string changes_path = run_dir + "/changes.json";
  if (fs::exists(changes_path)) {
    const nlohmann::json changes = ReadJson(changes_path);
    try {
      const nlohmann::json& list = changes.at("changes");
      const std::vector<bool> standing = StandingRemovals(list);  // restored ones are live
      for (std::size_t i = 0; i < list.size(); ++i) {
        const nlohmann::json& entry = list[i];
        if (!standing[i]) continue;
        ObjectView view;
        view.id = entry.at("object_id").get<ObjectId>();
        view.class_id = entry.at("class_id").get<int>();
        view.cuboid = CuboidFromJson(entry.at("cuboid"));
        view.state = 5;
        view.removed = true;
        scene.objects.push_back(view);
      }
      scene.moves = MovesInChanges(list);
    } catch (const std::exception& error) {
      throw ParseError(changes_path + ": " + error.what());
    }
  }
  return scene;
}

std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> MovesInChanges(
    const nlohmann::json& changes) {
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> moves;
  const std::vector<bool> standing = StandingRemovals(changes);
  for (std::size_t i = 0; i < changes.size(); ++i) {
    const nlohmann::json& entry = changes[i];
    if (standing[i] && entry.at("type").get<std::string>() == "moved")
      moves.emplace_back(CuboidFromJson(entry.at("cuboid")).centre,
                         CuboidFromJson(entry.at("to").at("cuboid")).centre);
  }
  return moves;
}

}  // namespace ocg
