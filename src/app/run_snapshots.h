#pragma once
// The run's PNG snapshots (docs/viewer.md; private to ObjectSlam): the map from three
// viewpoints and the last frame at the end, the map and the frame every N SLAM keyframes
// when asked, and the map just before the OCG's first removal (with the final map, a
// before/after pair). Threading: the tracking thread only (the writer owns a GL context).

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "object_layer.h"
#include "ocg/app/pose_given.h"
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
  std::vector<Eigen::Vector2d> last_keypoints_;  // the last tracked frame's, in its image
  int keyframes_ = 0;
  double seconds_ = 0.0;
  std::vector<std::string> written_;
};

// A pose-given run's (`ocg_slam objects`) trajectories and snapshots, as a SLAM run writes
// them: CameraTrajectory.txt (the given poses of the frames used) and
// KeyFrameTrajectory.txt (the OCG keyframes'), and under snapshots/ the final map from the
// four viewpoints (no map points; the given poses drawn as the camera path, the OCG
// keyframes as frustums), the last frame used (on its image when the frame names one that
// can be read, else on a grey canvas of the camera's size), the map just before the OCG's
// first removal, and every N OCG keyframes the map and the frame (SnapshotPolicy).
// Threading: the frame loop's thread (the writer owns a GL context).
class PoseGivenOutputs {
 public:
  // folder: the run's output folder. Removes the PNG files of an earlier run under
  // folder/snapshots when the policy takes any.
  PoseGivenOutputs(const Settings& settings, SnapshotPolicy policy, std::string folder);
  // Just before mapper.AddKeyframe() (keeps the objects for the before/after pair).
  void BeforeKeyframe(const ObjectMapper& mapper);
  // After each frame used (and its keyframe when it was one).
  void AfterFrame(const ObjectMapper& mapper, const PoseGivenFrame& frame,
                  const FrameAssociation& association, bool keyframe);
  // After the object map's files are written (the final views are ocg_render's of the
  // folder): writes the trajectories and the final snapshots; returns run.json's
  // "snapshots" section (null when none). Throws FileError when a file cannot be written.
  nlohmann::json Finish(const ObjectMapper& mapper);

 private:
  MapScene Scene(const ObjectMapper& mapper) const;
  void WriteFrame(const ObjectMapper& mapper, const std::string& name);

  const Settings& settings_;
  SnapshotPolicy policy_;
  std::string folder_;
  SnapshotWriter writer_;
  std::vector<StampedPose> frames_, keyframes_;
  std::string last_image_path_;
  FrameAssociation last_association_;
  std::optional<std::vector<ObjectView>> before_keyframe_;
  bool removal_seen_ = false;
  int keyframe_count_ = 0;
  double seconds_ = 0.0;
  std::vector<std::string> written_;
};

}  // namespace ocg::app_detail
