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
    if (policy_.Enabled()) {
      // Tracking keeps undistorted keypoints; the image shows them where the lens put them.
      last_keypoints_.clear();
      for (const TrackedPoint& point : result.points) {
        last_keypoints_.push_back(
            camera_.Project({(point.pixel.x() - camera_.cx) / camera_.fx,
                             (point.pixel.y() - camera_.cy) / camera_.fy, 1.0}));
      }
    }
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
  written_.push_back(
      writer_.WriteImage(RenderFrameView(image, objects.LastFrameDetections(), objects.Views(),
                                         last_pose_, camera_, up, last_keypoints_),
                         name));
}

void RunSnapshots::Record(const std::vector<std::string>& paths) {
  written_.insert(written_.end(), paths.begin(), paths.end());
}

PoseGivenOutputs::PoseGivenOutputs(const Settings& settings, SnapshotPolicy policy,
                                   std::string folder)
    : settings_(settings),
      policy_(policy),
      folder_(std::move(folder)),
      writer_(folder_ + "/snapshots", settings.viewer) {
  if (policy_.Enabled()) writer_.RemoveOldSnapshots();
}

void PoseGivenOutputs::BeforeKeyframe(const ObjectMapper& mapper) {
  if (policy_.Enabled() && !removal_seen_) before_keyframe_ = mapper.Views();
}

void PoseGivenOutputs::AfterFrame(const ObjectMapper& mapper, const PoseGivenFrame& frame,
                                  const FrameAssociation& association, bool keyframe) {
  const SE3 T_wc = frame.T_cw->Inverse();
  frames_.push_back({frame.timestamp, frame.timestamp_text, T_wc});
  if (keyframe) keyframes_.push_back(frames_.back());
  last_image_path_ = frame.image_path;
  last_association_ = association;
  if (!policy_.Enabled() || !keyframe) return;
  const auto start = std::chrono::steady_clock::now();
  if (!removal_seen_ && mapper.Stats().objects_removed > 0) {
    removal_seen_ = true;
    MapScene scene = Scene(mapper);
    if (before_keyframe_) scene.objects = *before_keyframe_;
    const std::vector<std::string> paths = writer_.WriteMapViews(
        scene, "before_first_removal", {MapViewpoint::kThreeQuarter, MapViewpoint::kObjects});
    written_.insert(written_.end(), paths.begin(), paths.end());
    before_keyframe_.reset();
  }
  if (policy_.every_keyframes > 0 && ++keyframe_count_ % policy_.every_keyframes == 0) {
    char prefix[32];
    std::snprintf(prefix, sizeof prefix, "keyframe_%05d", keyframe_count_);
    const std::vector<std::string> paths =
        writer_.WriteMapViews(Scene(mapper), prefix, {MapViewpoint::kThreeQuarter});
    written_.insert(written_.end(), paths.begin(), paths.end());
    WriteFrame(mapper, std::string(prefix) + "_frame");
  }
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

nlohmann::json PoseGivenOutputs::Finish(const ObjectMapper& mapper) {
  WriteTumTrajectory(folder_ + "/CameraTrajectory.txt", frames_);
  WriteTumTrajectory(folder_ + "/KeyFrameTrajectory.txt", keyframes_);
  if (!policy_.Enabled()) return nullptr;
  const auto start = std::chrono::steady_clock::now();
  if (!frames_.empty()) {
    // The folder as ocg_render reads it, so that both draw the same final map.
    MapScene scene = ReadRunScene(folder_);
    scene.trajectory_name = "given camera path";
    scene.current_camera = frames_.back().T_wc;
    const std::vector<std::string> paths =
        writer_.WriteMapViews(scene, "final",
                              {MapViewpoint::kFollow, MapViewpoint::kTopDown,
                               MapViewpoint::kThreeQuarter, MapViewpoint::kObjects});
    written_.insert(written_.end(), paths.begin(), paths.end());
    WriteFrame(mapper, "final_frame");
  }
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return {{"folder", writer_.folder()}, {"files", written_}, {"seconds", seconds_}};
}

MapScene PoseGivenOutputs::Scene(const ObjectMapper& mapper) const {
  MapScene scene;
  for (const StampedPose& pose : keyframes_) scene.keyframes.push_back(pose.T_wc);
  for (const StampedPose& pose : frames_) scene.trajectory.push_back(pose.T_wc.translation());
  scene.trajectory_name = "given camera path";
  scene.objects = mapper.Views();
  scene.up = mapper.Up();
  if (!frames_.empty()) scene.current_camera = frames_.back().T_wc;
  return scene;
}

void PoseGivenOutputs::WriteFrame(const ObjectMapper& mapper, const std::string& name) {
  if (frames_.empty()) return;
  const PinholeCamera& camera = settings_.camera.model;
  cv::Mat image;
  if (!last_image_path_.empty()) image = cv::imread(last_image_path_, cv::IMREAD_COLOR);
  if (image.empty()) {
    // Pose-given runs need no images: the detections and cuboids are drawn all the same.
    if (!last_image_path_.empty())
      spdlog::info("snapshots: cannot read '{}': the frame view is drawn on grey",
                   last_image_path_);
    image = cv::Mat(camera.height, camera.width, CV_8UC3, cv::Scalar(128, 128, 128));
  }
  written_.push_back(writer_.WriteImage(
      RenderFrameView(image, FrameDetectionsOf(last_association_), mapper.Views(),
                      frames_.back().T_wc.Inverse(), camera, mapper.Up()),
      name));
}

}  // namespace ocg::app_detail
