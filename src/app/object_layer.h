#pragma once
// The object layer inside a SLAM run (private to ObjectSlam): every tracked frame's
// detections with its pose and tracked map points; at each SLAM keyframe (after its bundle
// adjustment) the objects follow the optimized poses and the supporting plane. The OCG
// gets every Objects.keyframe_interval-th tracked frame, as in pose-given mode, not SLAM's
// keyframes: it counts doubt in keyframes, and SLAM's keyframe rate follows the camera's
// motion (every 3 frames on the 10 Hz smoke preset, every 9 at 30 Hz), which would make
// one setting remove objects three times sooner on one sequence than on another.
//
// Threading: the tracking thread calls everything but the readers (Views, Up, Objects,
// Changes), which may be called from any thread (ObjectMapper locks its map).

#include <cstdint>
#include <iosfwd>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "keyframe_colours.h"
#include "ocg/app/settings.h"
#include "ocg/core/statistics.h"
#include "ocg/io/detections.h"
#include "ocg/objects/change_log.h"
#include "ocg/objects/object_mapper.h"
#include "ocg/slam/system.h"
#include "ocg/viewer/frame_view.h"

namespace ocg::app_detail {

// Writes the object map's files (objects.json, changes.json revised as ReviseChangeLog says,
// ocg.json, ocg_observations.jsonl) into folder; returns the counts run.json reports of it.
// changes.json's entries: the mapper's change log revised as ReviseChangeLog says.
std::vector<ChangeEntry> RevisedChangeLog(const ObjectMapper& mapper,
                                          const ChangeLogContext& context);

nlohmann::json WriteObjectMap(const ObjectMapper& mapper, const std::string& folder,
                              const ChangeLogContext& change_log);

// run.json's timing entry of a list of durations in seconds, or of their summary.
nlohmann::json Timing(const std::vector<double>& seconds);
nlohmann::json Timing(const DurationSummary& seconds);
// run.json's timing.object_layer_per_keyframe: the median CPU time of the first and of the
// last quarter of the keyframes' (in order), their ratio and the count.
nlohmann::json PerKeyframeTiming(const std::vector<double>& cpu_seconds);
// Whether a keyframe moved from before to now by more than tolerance (map units): the
// shift of its camera centre plus its turn in radians times one map unit, a bound on how
// far a point one unit in front of it (and its frames' views of it) moved.
bool KeyframeMoved(const KeyFrameState& before, const KeyFrameState& now, double tolerance);

class ObjectLayer {
 public:
  // enabled false: no object layer (every call does nothing). keep_first_removal: keep the
  // objects as they were just before the OCG's first removal (for the before/after
  // snapshots; a copy of the object list at every OCG keyframe until then).
  ObjectLayer(const Settings& settings, bool enabled, bool keep_first_removal);
  bool Enabled() const { return enabled_; }

  // colour: the frame's colour image, asked for only at an OCG keyframe with detections,
  // whose sightings take their colour signatures as they are made (keyframe_colours.h).
  void AddFrame(const System& system, const TrackingResult& result, std::int64_t frame,
                double timestamp, const std::vector<Detection>& detections,
                FrameColourImage& colour);
  // The objects for the viewer (none without detections) and their up direction.
  std::vector<ObjectView> Views() const;
  // The objects in the map now (Views() also lists removed ones); 0 without a layer.
  std::size_t LiveObjectCount() const;
  std::optional<Eigen::Vector3d> Up() const;
  // The detections of the last frame given, with the objects they were associated to.
  std::vector<FrameDetection> LastFrameDetections() const;
  // Once: the objects just before the OCG's first removal, if there was one.
  std::optional<std::vector<ObjectView>> TakeFirstRemoval();
  // After SLAM has finished: the objects take the final poses, the OCG its last keyframe;
  // the session's colours (ObjectMap::ColourAppearances) and, in a later session, the
  // box appearances are taken for the change log. Does nothing when not enabled.
  void Finish(const System& system);
  // objects.json, changes.json ("" without an object layer).
  std::string Objects() const;
  std::string Changes() const;
  // Writes the object outputs; returns run.json's "objects" section (without the
  // detection folder's fields, which the caller knows).
  nlohmann::json Write(const std::string& output) const;

  // Map files (object_map_file.h). SaveState after Finish(). LoadState, before the first
  // frame, continues the saved object map and OCG; StartSession alone when the file held
  // no objects. session: this run's index; frame_offset: the frames the earlier sessions
  // were given (AddFrame's frame numbers continue after theirs, so their sightings keep
  // their own frames).
  // file_version: the map file's. SaveState also keeps the revised change log, so a later
  // session lists this one's moves, additions and reasons as this one did.
  void SaveState(std::ostream& out) const;
  void LoadState(std::istream& in, int session, std::int64_t frame_offset,
                 std::uint32_t file_version);
  void StartSession(int session, std::int64_t frame_offset);

 private:
  void Start();
  void Follow(const System& system);
  ChangeLogContext ChangeLog() const;

  const Settings& settings_;
  bool enabled_;
  bool keep_first_removal_;
  std::unique_ptr<ObjectMapper> mapper_;
  // OCG.mode "points": how the keyframe's features are searched for the objects' points
  // (the pyramid of ORBextractor.*, the window of Objects.presence_search_radius, the
  // thresholds of Matcher.*); its features are set at each keyframe.
  FrameFeatureSearch point_search_;
  std::int64_t keyframes_ = 0;
  std::int64_t tracked_frames_ = 0;
  int resets_ = 0;
  int session_ = 0;
  std::int64_t frame_offset_ = 0;
  bool loaded_ = false;  // LoadState() gave the object map
  std::int64_t loaded_tracked_frames_ = 0;
  FrameAssociation last_association_;
  std::optional<std::vector<ObjectView>> first_removal_;
  bool removal_seen_ = false;
  DurationSummary seconds_;
  // The object layer's CPU time (its thread's) at each SLAM keyframe, in order (8 bytes a
  // keyframe); run.json gives the medians of the first and last quarters.
  std::vector<double> keyframe_cpu_seconds_;
  // The SLAM map's version the mapper's copy is up to (none: empty), and how many times
  // the copy read the whole map (the first time, loop corrections, merges ...).
  std::optional<std::uint64_t> map_version_;
  int full_map_reads_ = 0;
  // Follow()'s frame poses, so a keyframe reads the poses that changed, not every sighting
  // frame's: this session's frames (call indices) given a pose, by the keyframe it was
  // taken from (System::FramePoses' anchors; a frame no sighting keeps any more may
  // stay until the next reading of every frame), the frames with detections given to the
  // mapper since, and whether the next Follow() reads every sighting frame's pose (the
  // first, after a new mapper or session; the SLAM map's "everything" too).
  std::map<std::uint64_t, std::vector<std::size_t>> frames_by_anchor_;
  std::vector<std::size_t> new_frames_;
  // The frames frames_by_anchor_ holds, and how many it held after its last pruning: once
  // twice as many, the frames no object or candidate keeps a sighting of any more
  // (Objects.max_sightings thins them) leave it, so a keyframe's re-posed frames stay
  // bounded as the run grows (amortized: a pruning per doubling).
  std::size_t anchored_frames_ = 0;
  std::size_t anchored_after_pruning_ = 0;
  // Each anchor keyframe's pose when its frames' poses were last read: its frames are read
  // again once it moved more than Objects.follow_tolerance from there (KeyframeMoved).
  std::map<std::uint64_t, KeyFrameState> anchor_read_at_;
  void PruneAnchoredFrames();
  bool follow_every_frame_ = true;
  std::optional<double> session_start_;                      // timestamp of the first frame given
  std::optional<std::vector<ChangeEntry>> earlier_changes_;  // the loaded map file's log
  // Finish(): ObjectMap::BoxAppearances() over every keyframe of the SLAM map.
  std::map<ObjectId, std::vector<Descriptor>> box_appearance_;
  // The keyframe colours' images and counts (run.json's colour_signatures).
  KeyframeColours colours_;
  // Finish(): ObjectMap::ColourAppearances().
  std::map<ObjectId, ColourHistogram> colour_;
};

}  // namespace ocg::app_detail
