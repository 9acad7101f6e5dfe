#pragma once
// The run's PNG snapshots (docs/viewer.md; private to ObjectSlam): the map from three
// viewpoints and the last frame at the end, the map and the frame every N SLAM keyframes
// when asked, and the map just before the OCG's first removal (with the final map, a
// before/after pair). Threading: the tracking thread only (the writer owns a GL context).

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "object_layer.h"
#include "ocg/app/settings.h"
#include "ocg/io/trajectory.h"
#include "ocg/slam/system.h"
#include "ocg/viewer/snapshots.h"

namespace ocg::app_detail {

class RunSnapshots {
 public:
  // Removes the PNG files of an earlier run in folder when the policy takes any.
  RunSnapshots(const Settings& settings, SnapshotPolicy policy, const std::string& folder,
               std::vector<StampedPose> groundtruth);

  // image: the frame's pixels, kept for the frame views unless image_path names its file
  // (read again in colour when a frame view is drawn).
  void AfterFrame(const System& system, ObjectLayer& objects, const TrackingResult& result,
                  const cv::Mat& image, const std::string& image_path);
  // The final snapshots; returns run.json's "snapshots" section (null when none).
  nlohmann::json Finish(const System& system, const ObjectLayer& objects);

 private:
  MapScene Scene(const System& system, const ObjectLayer& objects, bool with_groundtruth) const;
  void WriteFrame(const ObjectLayer& objects, const std::string& name);
  void Record(const std::vector<std::string>& paths);

  SnapshotPolicy policy_;
  SnapshotWriter writer_;
  PinholeCamera camera_;
  std::vector<StampedPose> groundtruth_;
  bool tracked_ = false;
  std::string last_image_path_;
  cv::Mat last_image_;
  SE3 last_pose_;
  int keyframes_ = 0;
  double seconds_ = 0.0;
  std::vector<std::string> written_;
};

}  // namespace ocg::app_detail
