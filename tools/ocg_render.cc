// ocg_render: PNG snapshots of a finished run's map, from its output folder alone
// (docs/viewer.md): map points, keyframes, trajectory, object cuboids coloured by OCG
// state and removed objects as ghosts, from ORB-SLAM2's viewpoint and the automatic ones;
// and the object map as a mesh (PLY, OBJ).

#include <chrono>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "cli_common.h"
#include "ocg/app/settings.h"
#include "ocg/eval/trajectory_error.h"
#include "ocg/io/trajectory.h"
#include "ocg/viewer/object_mesh.h"
#include "ocg/viewer/run_scene.h"
#include "ocg/viewer/snapshots.h"

namespace {

std::vector<ocg::MapViewpoint> ParseViews(const std::string& text) {
  std::vector<ocg::MapViewpoint> views;
  std::stringstream list(text);
  std::string name;
  while (std::getline(list, name, ',')) {
    bool known = false;
    for (ocg::MapViewpoint view : {ocg::MapViewpoint::kFollow, ocg::MapViewpoint::kTopDown,
                                   ocg::MapViewpoint::kThreeQuarter, ocg::MapViewpoint::kObjects}) {
      if (name == ocg::ToString(view)) {
        views.push_back(view);
        known = true;
      }
    }
    if (!known) {
      throw std::invalid_argument("--views: unknown view '" + name +
                                  "' (follow, top, three_quarter, objects)");
    }
  }
  return views;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ocg_render: snapshots of a finished run's map (docs/viewer.md)", "ocg_render"};
  std::string log_level, run_dir, output, settings_path, groundtruth,
      views_text = "follow,top,three_quarter,objects";
  std::string prefix = "map";
  std::vector<std::string> meshes;
  ocg::tools::AddLogLevelOption(app, &log_level);
  app.add_option("--run", run_dir,
                 "a run's output folder (ocg_slam run, a later session, ocg_slam objects)")
      ->required()
      ->check(CLI::ExistingDirectory);
  app.add_option("--out", output, "folder for the PNGs (default: RUN/snapshots)");
  app.add_option("--settings", settings_path, "settings file for Viewer.* (size, viewpoint)")
      ->check(CLI::ExistingFile);
  app.add_option("--groundtruth", groundtruth,
                 "ground-truth trajectory (TUM format), drawn aligned to the run (Sim(3))")
      ->check(CLI::ExistingFile);
  app.add_option("--views", views_text, "comma-separated: follow, top, three_quarter, objects")
      ->capture_default_str();
  app.add_option("--prefix", prefix, "file names: PREFIX_<view>.png")->capture_default_str();
  app.add_option("--mesh", meshes,
                 "also write the object map as a mesh: F.ply or F.obj (+ F.mtl), a box per live "
                 "object coloured by OCG state (repeat for both)");
  return ocg::tools::RunTool(app, argc, argv, log_level, [&] {
    const std::vector<ocg::MapViewpoint> views = ParseViews(views_text);
    for (const std::string& path : meshes) {  // before any drawing
      const std::string extension = std::filesystem::path(path).extension().string();
      if (extension != ".ply" && extension != ".obj")
        throw std::invalid_argument("--mesh '" + path + "': the file must end in .ply or .obj");
    }
    ocg::ViewerOptions options;
    if (!settings_path.empty()) options = ocg::LoadSettings(settings_path).settings.viewer;
    ocg::MapScene scene = ocg::ReadRunScene(run_dir);
    if (!groundtruth.empty()) {
      const std::vector<ocg::StampedPose> truth = ocg::ReadTumTrajectory(groundtruth);
      std::string trajectory = run_dir + "/KeyFrameTrajectory.txt";
      if (!std::filesystem::exists(trajectory)) trajectory = run_dir + "/CameraTrajectory.txt";
      const ocg::Sim3 run_from_truth =
          ocg::ComputeAte(truth, ocg::ReadTumTrajectory(trajectory), {})
              .reference_from_estimate.Inverse();
      for (const ocg::StampedPose& pose : truth)
        scene.groundtruth.push_back(run_from_truth * pose.T_wc.translation());
    }
    ocg::SnapshotWriter writer(output.empty() ? run_dir + "/snapshots" : output, options);
    const auto start = std::chrono::steady_clock::now();
    const std::vector<std::string> paths = writer.WriteMapViews(scene, prefix, views);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << "ocg_render: " << scene.points.size() << " points, " << scene.keyframes.size()
              << " keyframes, " << scene.objects.size() << " objects; " << paths.size()
              << " views in " << seconds << " s\n";
    for (const std::string& path : paths) std::cout << "wrote " << path << "\n";
    if (!meshes.empty()) {
      const ocg::ObjectMesh mesh = ocg::MakeObjectMesh(scene.objects, scene.up);
      for (const std::string& path : meshes) {
        ocg::WriteObjectMesh(path, mesh);
        std::cout << "wrote " << path << " (" << mesh.objects.size() << " objects, "
                  << mesh.triangles.size() << " triangles)\n";
      }
    }
  });
}
