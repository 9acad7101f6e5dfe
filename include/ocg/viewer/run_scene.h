#pragma once
// A finished run's map, read back from its output folder, for `ocg_render`.

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "ocg/viewer/map_view.h"

namespace ocg {

// Reads RUN_DIR/map_points.ply, KeyFrameTrajectory.txt, CameraTrajectory.txt,
// objects.json (live objects, their state, "up") and changes.json (removed objects, as
// ghosts; moved ones as ghosts with an arrow to where they went): the folder of any run
// (ocg_slam run, a later session, ocg_slam objects, whose run.json names its trajectory
// "given camera path"; ocg_replay's changes). Any of the files may be missing (a SLAM run
// without detections has no objects, a pose-given one no map points), not all. Throws
// FileError naming the folder when it holds none, FileError / ParseError naming the file.
MapScene ReadRunScene(const std::string& run_dir);

// The arrows of a change log: for every "moved" entry of changes.json's "changes" list
// that a later "restored" entry has not undone, its old centre and its new one ("to"),
// as MapScene::moves draws them (map frame). Throws nlohmann::json's errors on a malformed
// entry.
std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> MovesInChanges(
    const nlohmann::json& changes);

}  // namespace ocg
