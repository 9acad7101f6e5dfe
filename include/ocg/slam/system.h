#pragma once
// The monocular SLAM system: owns the map, the keyframe database, tracking and local
// mapping, and starts and stops the local mapping thread.
//
// Threading: TrackImage, Shutdown and the trajectory getters are for one caller thread.
// In sequential mode (SystemConfig::sequential) local mapping runs inside TrackImage
// after each new keyframe, so identical inputs give identical outputs; otherwise it runs
// on its own thread, fed through a bounded queue, and loop closing on another, fed by
// local mapping.

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "ocg/core/statistics.h"
#include "ocg/features/bow_database.h"
#include "ocg/features/vocabulary.h"
#include "ocg/io/trajectory.h"
#include "ocg/slam/local_mapping.h"
#include "ocg/slam/loop_closing.h"
#include "ocg/slam/map.h"
#include "ocg/slam/map_file.h"
#include "ocg/slam/tracking.h"

namespace ocg {

struct SystemConfig {
  PinholeCamera camera;
  double fps = 30.0;
  bool sequential = true;
  OrbExtractorOptions orb;
  MatcherOptions matcher;
  InitialMapOptions initializer;
  TrackingOptions tracking;
  LocalMappingOptions local_mapping;
  LoopClosingOptions loop_closing;
  std::uint64_t seed = 42;  // System.seed: loop closing's RANSAC
};

// One frame given to TrackImage, as the trajectories need it: kept for every frame of the
// run, so kept small (about 100 bytes; its timestamp's text and timings are not in it:
// System::TimestampText(), System::Timings()).
struct FrameRecord {
  double timestamp = 0.0;
  // Pose relative to the reference keyframe when tracked (ORB-SLAM2's way of writing
  // the full trajectory after the keyframes have been optimized).
  KeyFrameId reference = 0;
  SE3 T_c_reference;
  // The map the frame was tracked in (0, 1, ... in the order they were started); a map
  // reset is forgotten, its frames untracked. A merge moves frames into another map:
  // System::FrameMaps() says where each frame is now.
  int map = 0;
  TrackingState state = TrackingState::kNoImages;
  bool relocalized = false;
  bool new_keyframe = false;
  bool tracked = false;
  // The timestamp's text is the timestamp printed with this many decimals ("%.*f"), or,
  // when -1, kept whole by the System (a text no printing of the number gives back).
  std::int8_t text_decimals = -1;
};

// The timings of every frame given to TrackImage, summarised (seconds).
struct FrameTimings {
  DurationSummary tracking;       // feature extraction and tracking, per frame
  DurationSummary tracking_cpu;   // the same, CPU time of the tracking thread
  DurationSummary local_mapping;  // sequential mode: local mapping, per keyframe
  DurationSummary map_lock_wait;  // tracking waiting for the map lock (threaded mode)
};

// One map of the atlas: every map the run started (tracking got lost in one too long and
// started the next), kept with its keyframes and points; the current one is tracked.
// Poses of different maps are in different frames and scales, until a merge moves one
// into another's frame: a merged map is then empty, its frames and keyframes counted
// in the map it went into.
struct MapSummary {
  int index = 0;
  bool current = false;
  std::size_t frames_tracked = 0;  // frames placed in it now (CameraTrajectory)
  std::uint64_t first_frame = 0;   // call index of its first and last tracked frame
  std::uint64_t last_frame = 0;
  std::size_t keyframes = 0;
  std::size_t map_points = 0;
  // Merged into another map (LoopClosing's merges): which, when (the frame id of the
  // keyframe that recognized the other map's place), the similarity's scale (the other
  // map's units per unit of this one) and how many frames were in this map then.
  int merged_into = -1;
  std::uint64_t merged_at_frame = 0;
  double merge_scale = 1.0;
};

class System {
 public:
  // vocabulary must outlive the system.
  System(const SystemConfig& config, const Vocabulary& vocabulary);
  ~System();
  System(const System&) = delete;
  System& operator=(const System&) = delete;

  // features: see Tracking::Track (made by MakeFeatureExtractor; null: extracted here).
  TrackingResult TrackImage(const cv::Mat& image, double timestamp,
                            const std::string& timestamp_text,
                            const ExtractedFeatures* features = nullptr);
  // The ORB features of the last frame TrackImage tracked (null before one was): valid
  // until the next TrackImage. For the caller's thread (the object layer's point search).
  const ExtractedFeatures* LastFrameFeatures() const;
  // A function that extracts an image's ORB features as tracking does once initialized
  // (same options, camera and undistortion), with an extractor of its own: for another
  // thread, so that extraction, half of tracking's CPU, runs while the previous frame is
  // tracked. Give its result to TrackImage. Not thread-safe itself: one per thread.
  std::function<ExtractedFeatures(const cv::Mat&)> MakeFeatureExtractor() const;
  // Finishes local mapping (threaded mode) and stops its thread. Idempotent; rethrows a
  // failure of the local mapping thread.
  void Shutdown();
  // Whether local mapping and loop closing (its global adjustment included) have nothing
  // queued nor running (threaded mode; always true in sequential mode).
  bool MappingIdle() const;
  // Tests: called by TrackImage on the caller's thread after tracking has placed the frame
  // and before the frame is recorded (in threaded mode the mapping threads may move the
  // map in between; a hook that waits for them puts every correction exactly there).
  void SetAfterTrackingHook(std::function<void()> hook) { after_tracking_ = std::move(hook); }

  // Camera-to-world poses (TUM convention) of the keyframes of the main map (the map
  // with the most tracked frames; the current one on a tie or with a single map).
  std::vector<StampedPose> KeyFrameTrajectory() const;
  // Every frame tracked in the main map, placed relative to its reference keyframe's
  // final pose (frames of maps merged into it: in its frame).
  std::vector<StampedPose> CameraTrajectory() const;
  // The same for one map (MapSummary::index): its poses now, in its frame; nothing for
  // a map merged into another.
  std::vector<StampedPose> KeyFrameTrajectory(int map) const;
  std::vector<StampedPose> CameraTrajectory(int map) const;
  // Every map of the run, in the order they were started.
  std::vector<MapSummary> Maps() const;
  int MainMap() const;
  // Per frame given to TrackImage, in call order: the map it is placed in now (its
  // reference keyframe's), -1 when not tracked or its map was reset.
  std::vector<int> FrameMaps() const;
  // The current pose (after bundle adjustment) of every frame given to TrackImage, in
  // call order, in the current map's frame; none for frames not tracked, whose map was
  // reset or that are placed in another map (FrameMaps() says which).
  std::vector<std::optional<SE3>> FramePoses() const;
  // The same for some frames (call indices; those beyond the last call have none).
  // anchors (optional): per frame with a pose, the keyframe it was taken from
  // (PoseFromReference); the pose stays as it is until MapChangesSince() names that
  // keyframe (moved or culled) or says everything changed.
  std::vector<std::optional<SE3>> FramePoses(const std::vector<std::size_t>& frames,
                                             std::vector<std::uint64_t>* anchors = nullptr) const;
  // The positions of the current map's points (for the object layer's supporting plane
  // and point sets), with their ids and descriptors in the same order when those are
  // given.
  std::vector<Eigen::Vector3d> MapPointPositions(
      std::vector<MapPointId>* ids = nullptr, std::vector<Descriptor>* descriptors = nullptr) const;
  // What changed in the current map since version (MapChanges::version of the last call;
  // none: everything), for a reader that keeps a copy of the map (map_journal.h): the
  // points and keyframes changed, or the whole map after a loop correction, a global
  // adjustment, a merge, a reset or a switch of map.
  MapChanges MapChangesSince(std::optional<std::uint64_t> version) const;
  // MapJournal::SetPointTolerance (map units): for the readers of MapChangesSince that
  // read at the same moments (the object layers); call before the first frame.
  void SetMapJournalPointTolerance(double tolerance);
  // The keyframes in the current map (for tests and diagnostics; read them while the
  // system is idle: after Shutdown(), or between TrackImage calls in sequential mode).
  std::vector<KeyFramePtr> KeyFrames() const;
  // Whether this map holds the place a keyframe (of any map) shows: its database's
  // max_candidates best BoW matches verified as loop closing verifies a loop; nothing
  // in the map changes. Same conditions as KeyFrames().
  std::optional<LoopEvent> RecognizePlace(const KeyFramePtr& keyframe,
                                          std::size_t max_candidates) const;
  // The camera-to-world rotations of the keyframes in the current map.
  std::vector<Eigen::Matrix3d> KeyFrameRotations() const;
  const std::vector<FrameRecord>& Frames() const { return frames_; }
  // The timestamp text TrackImage was given with frame (an index of Frames()).
  std::string TimestampText(std::size_t frame) const;
  const FrameTimings& Timings() const { return timings_; }
  // The current map's live keyframes and points.
  std::size_t KeyFrameCount() const;
  std::size_t MapPointCount() const;
  LocalMappingStats MappingStats() const { return local_mapping_->Stats(); }
  // Call after Shutdown() in threaded mode (the worker writes it).
  const LoopClosingStats& LoopStats() const { return loop_closing_->Stats(); }
  int Resets() const { return resets_; }
  // Maps started after the first, each when tracking was lost too long in a bigger one.
  int NewMaps() const { return new_maps_; }
  // Merges of one map into another (LoopClosing's merges; threaded mode: after Shutdown).
  const std::vector<LoopEvent>& Merges() const { return loop_closing_->Stats().merges; }

  // Map files (slam/map_file.h, docs/sessions.md). SaveMap: same conditions as
  // KeyFrames(); saves the whole atlas: every map, the current one and the merges so far
  // (those of earlier sessions too). LoadMap: before the first TrackImage, into the empty
  // map; the atlas comes back as saved (Maps() lists its maps, merged ones with where they
  // went), the keyframe database is rebuilt from the keyframes' BoW vectors, and tracking
  // starts lost: it relocalizes in any map of the loaded atlas and never initializes one
  // of its own. Throws what ocg::LoadMap throws (the map stays empty then) and
  // std::logic_error after a frame. frames_before: the frames the earlier sessions were
  // given; this session's frame ids (KeyFrame::frame_id) continue after them, so a
  // keyframe's frame id is its frame's number over all sessions, as the object layer
  // numbers its sightings. format: the file's layout (older files: kSingleMap).
  void SaveMap(std::ostream& out) const;
  void LoadMap(std::istream& in, std::uint64_t frames_before = 0,
               MapFileFormat format = MapFileFormat::kAtlas);
  // The live keyframes of every map of the atlas.
  std::size_t AtlasKeyFrameCount() const;
  bool MapLoaded() const { return map_loaded_; }
  // The frames given before a map existed and why they did not initialize one.
  const InitializationAttempts& Initialization() const;

 private:
  SystemConfig config_;
  const Vocabulary& vocabulary_;
  Map map_;
  BowDatabase database_;
  std::unique_ptr<LocalMapping> local_mapping_;
  std::unique_ptr<LoopClosing> loop_closing_;
  std::unique_ptr<Tracking> tracking_;
  std::vector<FrameRecord> frames_;
  std::map<std::size_t, std::string> timestamp_texts_;  // FrameRecord::text_decimals -1
  FrameTimings timings_;
  double pending_mapping_seconds_ = 0.0;
  double pending_mapping_cpu_seconds_ = 0.0;
  int resets_ = 0;
  int new_maps_ = 0;
  int merges_seen_ = 0;                  // Map::merges() at the last TrackImage
  std::vector<MapMerge> loaded_merges_;  // the merges of the sessions before (LoadMap)
  int CurrentMap() const;
  // The merges of the sessions before and of this run, in order.
  std::vector<MapMerge> AllMerges() const;
  // FrameMaps() with map_.mutex() held.
  std::vector<int> FrameMapsLocked() const;
  // A tracked frame's pose as the map now stands (map_.mutex() held); none when its
  // reference keyframe is gone.
  std::optional<SE3> FramePoseLocked(const FrameRecord& record,
                                     KeyFrameId* live_keyframe = nullptr) const;
  bool shut_down_ = false;
  bool map_loaded_ = false;
  std::function<void()> after_tracking_;
};

}  // namespace ocg
