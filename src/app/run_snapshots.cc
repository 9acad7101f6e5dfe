#include "run_snapshots.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <utility>

#include "ocg/core/file_io.h"
#include "ocg/eval/trajectory_error.h"
#include "ocg/objects/map_cues.h"
#include "ocg/viewer/run_scene.h"

namespace ocg::app_detail {

RunSnapshots::RunSnapshots(const Settings& settings, SnapshotPolicy policy,
                           const std::string& folder, std::vector<StampedPose> groundtruth)
    : policy_(policy),
      writer_(folder, settings.viewer),
      camera_(settings.camera.model),
      groundtruth_(std::move(groundtruth)) {
  if (policy_.Enabled()) writer_.RemoveOldSnapshots();
}

void RunSnapshots::AfterFrame(const System& system, ObjectLayer& objects,
                              const TrackingResult& result, const cv::Mat& image,
                              const std::string& image_path) {
  if (result.T_cw) {
    tracked_ = true;
    last_image_path_ = image_path;
    // Without a file the pixels are kept, only when a frame view may be drawn.
    if (image_path.empty() && policy_.Enabled()) image.copyTo(last_image_);
    last_pose_ = *result.T_cw;
  }
  if (!policy_.Enabled()) return;
  const auto start = std::chrono::steady_clock::now();
  if (const auto before = objects.TakeFirstRemoval()) {
    MapScene scene = Scene(system, objects, false);
    scene.objects = *before;
    Record(writer_.WriteMapViews(scene, "before_first_removal",
                                 {MapViewpoint::kThreeQuarter, MapViewpoint::kObjects}));
  }
  if (result.new_keyframe && policy_.every_keyframes > 0 &&
      ++keyframes_ % policy_.every_keyframes == 0) {
    char prefix[32];
    std::snprintf(prefix, sizeof prefix, "keyframe_%05d", keyframes_);
    Record(writer_.WriteMapViews(Scene(system, objects, false), prefix,
                                 {MapViewpoint::kThreeQuarter}));
    WriteFrame(objects, std::string(prefix) + "_frame");
  }
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

nlohmann::json RunSnapshots::Finish(const System& system, const ObjectLayer& objects) {
  if (!policy_.Enabled()) return nullptr;
  const auto start = std::chrono::steady_clock::now();
  MapScene scene = Scene(system, objects, true);
  // The change log pairs removals with what appeared elsewhere only now, at the end of the
  // run: its moves are the final views' arrows, as ocg_render draws them from changes.json.
  const std::string changes = objects.Changes();
  if (!changes.empty()) scene.moves = MovesInChanges(nlohmann::json::parse(changes).at("changes"));
  Record(writer_.WriteMapViews(scene, "final",
                               {MapViewpoint::kFollow, MapViewpoint::kTopDown,
                                MapViewpoint::kThreeQuarter, MapViewpoint::kObjects}));
  WriteFrame(objects, "final_frame");
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return {{"folder", writer_.folder()}, {"files", written_}, {"seconds", seconds_}};
}

MapScene RunSnapshots::Scene(const System& system, const ObjectLayer& objects,
                             bool with_groundtruth) const {
  MapScene scene;
  scene.points = system.MapPointPositions();
  for (const StampedPose& pose : system.KeyFrameTrajectory()) scene.keyframes.push_back(pose.T_wc);
  const std::vector<StampedPose> trajectory = system.CameraTrajectory();
  for (const StampedPose& pose : trajectory) scene.trajectory.push_back(pose.T_wc.translation());
  scene.objects = objects.Views();
  if (tracked_) scene.current_camera = last_pose_.Inverse();
  scene.up = objects.Up().value_or(CameraUpPrior(system.KeyFrameRotations()));
  if (with_groundtruth && !groundtruth_.empty()) {
    try {
      // The ground truth in the map's frame: the ATE alignment, inverted.
      const Sim3 map_from_truth =
          ComputeAte(groundtruth_, trajectory, {}).reference_from_estimate.Inverse();
      for (const StampedPose& pose : groundtruth_)
        scene.groundtruth.push_back(map_from_truth * pose.T_wc.translation());
    } catch (const std::invalid_argument& error) {
      spdlog::warn("snapshots: no ground truth drawn: {}", error.what());
    }
  }
  return scene;
}

void RunSnapshots::WriteFrame(const ObjectLayer& objects, const std::string& name) {
  if (!tracked_) return;
  cv::Mat image;
  if (!last_image_path_.empty()) {
    image = cv::imread(last_image_path_, cv::IMREAD_COLOR);
    if (image.empty()) throw FileError("cannot read image '" + last_image_path_ + "'");
  } else if (last_image_.channels() == 1) {
    cv::cvtColor(last_image_, image, cv::COLOR_GRAY2BGR);
  } else {
    image = last_image_;
  }
  const Eigen::Vector3d up = objects.Up().value_or(Eigen::Vector3d::UnitZ());
  written_.push_back(writer_.WriteImage(RenderFrameView(image, objects.LastFrameDetections(),
                                                        objects.Views(), last_pose_, camera_, up),
                                        name));
}

void RunSnapshots::Record(const std::vector<std::string>& paths) {
  written_.insert(written_.end(), paths.begin(), paths.end());
}

}  // namespace ocg::app_detail
