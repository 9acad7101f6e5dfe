#pragma once
// Pose-given mode (`ocg_slam objects`, docs/objects.md): the object map built and kept up
// to date by the OCG from a given camera trajectory and detections alone, no images.

#include <cstddef>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "ocg/app/run_stop.h"
#include "ocg/app/settings.h"
#include "ocg/core/lie.h"
#include "ocg/io/detection_source.h"
#include "ocg/viewer/snapshots.h"

namespace ocg {

struct PoseGivenFrame {
  std::string timestamp_text;  // the frame's name in the detections ("<timestamp_text>.txt")
  double timestamp = 0.0;      // seconds
  std::optional<SE3> T_cw;     // world to camera; none: the frame is skipped
  // Its image, for the frame views ("": none, drawn on grey) and, at a keyframe with
  // detections, the objects' colours (docs/sessions.md, "Moves in changes.json").
  std::string image_path;
};

// Runs the object layer over frames (in time order; every Objects.keyframe_interval-th
// frame with a pose is an OCG keyframe), writes objects.json, changes.json, ocg.json and
// ocg_observations.jsonl into folder and returns the counts and timings run.json reports
// (frames, frames_used, frames_without_pose, keyframes, wall_seconds, timing and the
// object map's counts). It also writes CameraTrajectory.txt (the given poses of the frames
// used), KeyFrameTrajectory.txt (the OCG keyframes') and, as the policy says, snapshots
// like a SLAM run's into folder/snapshots (docs/viewer.md; the report's "snapshots").
// progress(frames done) after each frame, when given. A stop requested (RunStop) ends the
// frames early: the object map of the frames done is written all the same, with
// "interrupted": true in the report. detections is asked for each frame with a pose,
// without an image (files or boxes in memory; a source that NeedsImage() has none to look
// at). Throws FileError when a file cannot be written.
nlohmann::json MapObjectsAlongTrajectory(const Settings& settings,
                                         const std::vector<PoseGivenFrame>& frames,
                                         DetectionSource& detections, const std::string& folder,
                                         const std::function<void(std::size_t)>& progress = {},
                                         const RunStop* stop = nullptr,
                                         const SnapshotPolicy& snapshots = {false, 0});

}  // namespace ocg
