// ocg_diff: what changed between two object maps (docs/sessions.md): objects removed,
// added, moved and unchanged, and a before/after snapshot pair with removed objects as
// ghosts and moves as arrows.

#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cli_common.h"
#include "ocg/core/coco.h"
#include "ocg/core/file_io.h"
#include "ocg/objects/map_diff.h"
#include "ocg/objects/map_frames.h"
#include "ocg/viewer/diff_view.h"
#include "ocg/viewer/run_scene.h"
#include "ocg/viewer/snapshots.h"

namespace {

namespace fs = std::filesystem;

std::string Describe(const ocg::ObjectRecord& record) {
  const Eigen::Vector3d& c = record.cuboid.centre;
  char text[160];
  std::snprintf(text, sizeof(text), "%lld %s at (%.3f, %.3f, %.3f)",
                static_cast<long long>(record.id), ocg::CocoClassName(record.class_id).c_str(),
                c.x(), c.y(), c.z());
  return text;
}

void PrintDiff(const ocg::MapDiff& diff, const std::string& unit, const std::string& frame,
               const std::string& after) {
  std::printf("removed %zu, added %zu, moved %zu, unchanged %zu (distances in %s)\n",
              diff.removed.size(), diff.added.size(), diff.moved.size(), diff.unchanged.size(),
              unit.c_str());
  std::printf("one frame: %s\n", frame.c_str());
  for (const ocg::ObjectRecord& record : diff.removed)
    std::printf("  removed    %s\n", Describe(record).c_str());
  for (const ocg::ObjectRecord& record : diff.added)
    std::printf("  added      %s\n", Describe(record).c_str());
  for (const ocg::MoveLink& link : diff.moved) {
    std::printf("  moved      %s -> %s (%.3f %s%s)\n", Describe(link.from).c_str(),
                Describe(link.to).c_str(), link.distance, unit.c_str(),
                link.recorded ? (", as " + after + "/changes.json records it").c_str() : "");
  }
  for (const ocg::MoveLink& link : diff.unchanged) {
    std::printf(
        "  unchanged  %s%s\n", Describe(link.to).c_str(),
        link.from.id == link.to.id ? "" : (" (was " + std::to_string(link.from.id) + ")").c_str());
  }
}

// A run folder's points, keyframes and trajectory, drawn behind the objects.
ocg::MapScene Background(const std::string& path) {
  if (fs::is_directory(path) && fs::exists(path + "/KeyFrameTrajectory.txt"))
    return ocg::ReadRunScene(path);
  return {};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "ocg_diff: objects removed, added, moved and unchanged between two object maps in one "
      "frame (a later session's map against the one it continued)",
      "ocg_diff"};
  std::string log_level, before, after, json_path, snapshots;
  bool json = false, any_frame = false;
  ocg::MapDiffOptions options;
  ocg::tools::AddLogLevelOption(app, &log_level);
  app.add_option("--before", before, "the earlier map: objects.json or a run folder")
      ->required()
      ->check(CLI::ExistingPath);
  app.add_option("--after", after, "the later map: objects.json or a run folder")
      ->required()
      ->check(CLI::ExistingPath);
  app.add_option("--same-place-factor", options.same_place_factor,
                 "same class within this many largest extents: the same object, unchanged")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--move-factor", options.moves.search_factor,
                 "a removed and an added object of one class within this many largest extents "
                 "of each other: a move")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_flag("--any-frame", any_frame,
               "compare maps that do not look like one world frame (by default refused: a "
               "pose-given map against a SLAM map, or two SLAM runs from empty maps)");
  app.add_flag("--json", json, "print the diff as JSON instead of text");
  app.add_option("--out", json_path, "also write the diff as JSON into this file");
  app.add_option("--snapshots", snapshots,
                 "write diff_before_<view>.png and diff_after_<view>.png (top, objects) into "
                 "this folder: removed objects as ghosts, moves as arrows");
  return ocg::tools::RunTool(app, argc, argv, log_level, [&] {
    const auto readers = ocg::ObjectMapReaders();
    const ocg::SavedObjectMap first = ocg::ReadObjectMap(before, readers);
    const ocg::SavedObjectMap second = ocg::ReadObjectMap(after, readers);
    ocg::FrameCheckOptions frame_options;
    frame_options.same_place_factor = options.same_place_factor;
    const ocg::FrameCheck frame = ocg::CheckOneFrame(first, second, frame_options);
    if (!frame.one_frame && !any_frame) {
      throw std::invalid_argument(
          "'" + before + "' and '" + after + "' are not in one world frame: " + frame.evidence +
          ". ocg_diff compares maps in one frame: a later session that continued the earlier "
          "one's map file (ocg_slam run --load-map), or pose-given runs (ocg_slam objects) on "
          "one ground truth; two SLAM runs from empty maps, or a SLAM map and a pose-given "
          "one, each have their own frame and scale. --any-frame compares them anyway");
    }
    const std::string unit = ocg::DistanceUnit(first, second);
    const ocg::MapDiff diff =
        ocg::DiffObjectMaps(first.objects, second.objects, options, ocg::MovesSince(first, second));
    const std::string frame_text =
        frame.one_frame ? frame.evidence
                        : "NOT one frame, compared as asked (--any-frame): " + frame.evidence;
    const std::string text = ocg::MapDiffJson(diff, unit, frame_text);
    if (!json_path.empty()) ocg::WriteFileAtomically(json_path, text);
    if (json) {
      std::cout << text;
    } else {
      PrintDiff(diff, unit, frame_text, after);
    }
    if (!snapshots.empty()) {
      ocg::MapScene background = Background(after);
      background.up = second.up;
      const ocg::DiffScenes scenes = ocg::MakeDiffScenes(diff, background);
      ocg::SnapshotWriter writer(snapshots, ocg::ViewerOptions{});
      const std::vector<ocg::MapViewpoint> views = {ocg::MapViewpoint::kTopDown,
                                                    ocg::MapViewpoint::kObjects};
      for (const std::string& path : writer.WriteMapViews(scenes.before, "diff_before", views))
        std::cerr << "wrote " << path << "\n";
      for (const std::string& path : writer.WriteMapViews(scenes.after, "diff_after", views))
        std::cerr << "wrote " << path << "\n";
    }
  });
}
