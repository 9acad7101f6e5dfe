#pragma once
// ObjectMapper: the object layer as one unit — detections in, object map kept up to date
// by the OCG out. Used by the pose-given mode (`ocg_slam objects`) and by the SLAM run.
//
// Threading: AddFrame() and AddKeyframe() from one producer thread. In threaded mode the
// OCG runs on its own thread and its removals reach the map from there; every access to
// the map goes through map_mutex_. Readers (ObjectsJson() ...) may be called from any
// thread; they see whole frames.

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "ocg/core/text_spool.h"
#include "ocg/objects/map_cues.h"
#include "ocg/objects/object_map.h"
#include "ocg/objects/slam_map_copy.h"
#include "ocg/ocg/manager.h"
#include "ocg/ocg/options.h"

namespace ocg {

struct MapFileAccess;

// The work of the last FollowSlamMap(), in map points touched: what changed, and the
// points the supporting plane was fitted to when it was fitted again (0 when kept).
struct SlamFollowWork {
  std::size_t points_changed = 0;
  std::size_t plane_points = 0;
  bool plane_refit = false;
};

struct ObjectLayerStats {
  std::int64_t frames = 0;
  std::int64_t keyframes = 0;
  std::int64_t detections_used = 0;
  std::int64_t detections_matched = 0;
  std::int64_t objects_created = 0;
  std::int64_t objects_removed = 0;  // by the OCG
  // AddFrame()'s colour images (keyframes with detections after filtering) and the
  // sightings they gave a colour signature.
  std::int64_t colour_images = 0;
  std::int64_t colour_sightings = 0;
  double colour_cpu_seconds = 0.0;  // of colouring them (the caller's thread)
  // SLAM runs: the last supporting plane found (0 inliers: none, up from the cameras).
  int plane_inliers = 0;
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
};

class ObjectMapper {
 public:
  ObjectMapper(ObjectsOptions objects, OcgOptions ocg, PinholeCamera camera, bool sequential);
  ~ObjectMapper();
  ObjectMapper(const ObjectMapper&) = delete;
  ObjectMapper& operator=(const ObjectMapper&) = delete;

  // Detections straight from the files: filtered here. points: the SLAM map points
  // tracked in the frame (SLAM runs), else null. colour: the frame's BGR image (a
  // keyframe's, both run kinds; empty: none): the sightings the frame made take their
  // colour signatures (SetSightingColours) in the same step, before the OCG (on its own
  // thread in threaded mode) can remove their objects, so a removed object keeps them.
  FrameAssociation AddFrame(std::int64_t frame, double timestamp, const SE3& T_cw,
                            const std::vector<Detection>& detections,
                            const std::vector<PointObservation>* points = nullptr,
                            const cv::Mat& colour = cv::Mat());
  // SLAM runs, before each AddKeyframe(): the copy of the SLAM map takes the changes; up
  // from the supporting plane of the map points refined by the objects' bottoms; the
  // sightings moved to their frames' optimized poses and the objects' points to their
  // optimized positions. The plane (RANSAC seeded with seed) is fitted again only when
  // the whole map changed or Objects.plane_refit_share of its points were added or removed
  // since the last fit, so a keyframe costs what changed, not what the map holds.
  void FollowSlamMap(const SlamMapChanges& changes, std::uint64_t seed);
  // The copy FollowSlamMap() keeps, and the work of its last call.
  const SlamMapCopy& SlamMap() const { return slam_map_; }
  SlamFollowWork LastFollowWork() const { return follow_work_; }
  // The frames whose poses FollowSlamMap() reads: ObjectMap::SightingFrames().
  std::vector<std::int64_t> SightingFrames() const;
  // Hands the OCG this keyframe (at the last added frame's pose). frame: that frame's
  // features (SLAM runs; OCG.mode "points" searches the points of the objects not detected
  // in them), read during the call only.
  void AddKeyframe(std::int64_t keyframe_id, double timestamp, const SE3& T_cw,
                   const FrameFeatureSearch* frame = nullptr);
  // Keeps every keyframe's OCG input as a JSON line (SPEC 3.1), so the OCG can be replayed
  // alone (`ocg_replay`) in other modes. Call before the first keyframe.
  void RecordObservations() { record_observations_ = true; }
  std::string ObservationsJsonl() const;
  // Sessions (map files): the map and the OCG start session `session`, whose first frame
  // is first_frame (ObjectMap and ObjectChangeDetector::StartSession); call before it.
  void StartSession(int session, std::int64_t first_frame);
  // Lets the OCG finish every keyframe, then ends the session (the camera leaves:
  // ObjectChangeDetector::EndSession), and estimates the objects whose changes were
  // waiting for their share (Objects.reestimate_share). Idempotent.
  void Finish();

  std::string ObjectsJson() const;
  // The object map's change log, and its live objects as the log's revision reads them
  // (ReviseChangeLog, change_log.h).
  std::vector<ObjectChange> Changes() const;
  std::vector<ObjectRecord> LiveObjects() const;
  std::string GraphJson() const;
  ObjectLayerStats Stats() const;
  // The live objects with their OCG state, and the removed ones (for viewers).
  std::vector<ObjectView> Views() const;
  // The up direction the cuboids are aligned with.
  Eigen::Vector3d Up() const;
  std::size_t LiveObjectCount() const;
  // ObjectMap::point_presence_stats().
  ObjectMap::PointPresenceStats PointPresenceStats() const;
  // ObjectMap::Appearances().
  std::map<ObjectId, std::vector<Descriptor>> Appearances() const;
  // ObjectMap::SeenAsClassThisSession().
  SeenAsClass SeenAsClassThisSession() const;
  // ObjectMap::BoxAppearances().
  std::map<ObjectId, std::vector<Descriptor>> BoxAppearances(const KeyframeFeatureMap& keyframes,
                                                             const BoxAppearanceOptions& options,
                                                             int max_distance) const;
  // ObjectMap::ColourAppearances().
  std::map<ObjectId, ColourHistogram> ColourAppearances(int min_signatures) const;

 private:
  friend struct MapFileAccess;    // map files (src/app/object_map_file.cc)
  mutable std::mutex map_mutex_;  // guards map_ and stats_
  ObjectMap map_;
  ObjectLayerStats stats_;
  bool record_observations_ = false;
  TextSpool observations_jsonl_;  // grows with the run: in a temporary file
  OcgManager manager_;
  // FollowSlamMap()'s, on the producer thread.
  SlamMapCopy slam_map_;
  SupportingPlane plane_;
  bool plane_fitted_ = false;
  std::size_t points_at_fit_ = 0;
  std::size_t changed_since_fit_ = 0;
  SlamFollowWork follow_work_;
};

}  // namespace ocg
