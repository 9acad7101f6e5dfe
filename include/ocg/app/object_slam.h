#pragma once
// ObjectSlam: the whole system behind one class — monocular SLAM, the object layer on its
// tracked frames, the OCG that keeps the object map up to date, and the run's snapshots.
// `ocg_slam run` and the Python module `ocg.ObjectSlam` are thin callers of it.
//
// Threading contract:
//  - Track() and Shutdown() from one caller thread (the "tracking thread"), never
//    concurrently with each other. In sequential mode (System.sequential) local mapping,
//    loop closing and the OCG run inside Track(), so identical inputs give identical
//    outputs; otherwise they run on threads of their own, started by the constructor and
//    joined by Shutdown().
//  - The readers (Pose(), Objects(), Changes(), KeyFrameTrajectory(), CameraTrajectory())
//    between Track() calls, from the tracking thread or from another thread the caller
//    keeps from overlapping Track() (a SLAM map reset inside Track() replaces the object
//    map; the Python binding serializes every call with one lock). They see whole
//    frames; the trajectories are final only after Shutdown().
//  - Save() after Shutdown(), from the tracking thread.
//  - Track() after Shutdown() throws std::logic_error; Shutdown() is idempotent; the
//    destructor shuts down when the caller has not.

#include <Eigen/Core>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ocg/app/run_stop.h"
#include "ocg/app/settings.h"
#include "ocg/core/lie.h"
#include "ocg/features/orb_extractor.h"
#include "ocg/io/detections.h"
#include "ocg/io/trajectory.h"
#include "ocg/slam/tracking.h"
#include "ocg/viewer/snapshots.h"

namespace ocg {

struct ObjectSlamOptions {
  // Vocabulary file; empty: the settings' Vocabulary.path.
  std::string vocabulary_path;
  // Map objects from the detections given to Track() (false: SLAM alone, no object files).
  bool map_objects = true;
  // PNG snapshots (docs/viewer.md) written under snapshot_folder; none when not enabled.
  SnapshotPolicy snapshots{false, 0};
  std::string snapshot_folder;
  // Ground truth (camera to world, TUM) drawn in the final snapshots, aligned by Sim(3).
  std::vector<StampedPose> groundtruth;
  // A map file (SaveMap) to continue: this run is its next session. It relocalizes in the
  // loaded map, then tracks, maps and closes loops in its coordinates; keyframes and
  // objects of every session live in one map. Empty: a new map.
  std::string load_map;
  // More object layers, one per (OCG.mode, output folder), fed the same SLAM frames as
  // the settings' own. SLAM never reads the objects, so in sequential mode each writes
  // what a run of its own in that mode would (timings aside), for the cost of one SLAM
  // run. Save() writes each folder like its own (without snapshots). Only with
  // map_objects and in sequential mode (the constructor throws SettingsError otherwise).
  std::vector<std::pair<std::string, std::string>> also_modes;
  // A request to end the run early (a signal), which the caller's frame loop asks through
  // StopRequested(); Save() marks run.json "interrupted": true when it was requested
  // before Shutdown(). Null: none. Not owned; must outlive the ObjectSlam.
  const RunStop* stop = nullptr;
};

// What a long run shows of its growth (Status(), run.json's "progress").
struct RunStatus {
  double seconds = 0.0;            // wall time since the first frame
  std::size_t frames = 0;          // given to Track()
  std::size_t keyframes = 0;       // live in the SLAM map
  std::size_t map_points = 0;      // in the SLAM map
  std::size_t objects = 0;         // live in the object map
  std::size_t resident_bytes = 0;  // the process's resident memory (0 where unknown)
  std::size_t heap_bytes = 0;      // of it, allocated and in use (0 where unknown)
};

// What Track() is told about a frame besides its pixels (all optional).
struct FrameSource {
  // The frame's timestamp as written in the trajectories (default: the number, %.6f).
  std::string timestamp_text;
  // The image file, read in colour for the frame snapshots (empty: the pixels given) and,
  // when the pixels given are grey, for the objects' colour signatures if the frame is an
  // OCG keyframe with detections, as it comes (docs/sessions.md, "Moves in changes.json";
  // empty: the frame's sightings get none).
  std::string image_path;
  // The image's ORB features from ObjectSlam::FeatureExtractor(), made ahead on another
  // thread; null: tracking extracts them (it always does while initializing).
  std::shared_ptr<const ExtractedFeatures> features = nullptr;
};

// What tracking made of the last frame given to ObjectSlam::Track().
struct FrameReport {
  TrackingState state = TrackingState::kNoImages;
  std::optional<SE3> T_cw;    // world to camera, when tracked
  bool new_keyframe = false;  // the frame became a keyframe
  bool relocalized = false;   // tracked again after being lost (or in a loaded map)
  int inliers = 0;            // map points matched, tracked frames
};

// Where the run came from, for run.json.
struct RunDescription {
  std::string sequence;    // sequence folder
  std::string settings;    // settings file
  std::string detections;  // detection folder (empty: none)
  std::size_t detection_files_matched = 0;
  // How the images were fed (LiveFeed::Report() for a real-time replay), run.json's
  // "feed"; null: as fast as the system took them, and no "feed" is written.
  nlohmann::json feed = nullptr;
  // How the frames were read and their detections made (FeedReport::reader), run.json's
  // "reader"; null: none is written.
  nlohmann::json reader = nullptr;
};

class ObjectSlam {
 public:
  // Reads the map file to load (options.load_map) first, then loads the vocabulary and
  // starts SLAM (and, in threaded mode, its threads). Throws MapFileError naming the map
  // file when it is not one, of another version, truncated or damaged, or made with
  // another camera or vocabulary; FileError when the vocabulary cannot be read,
  // SettingsError for impossible settings.
  explicit ObjectSlam(const Settings& settings, ObjectSlamOptions options = {});
  ~ObjectSlam();
  ObjectSlam(const ObjectSlam&) = delete;
  ObjectSlam& operator=(const ObjectSlam&) = delete;

  // One frame: image CV_8UC1 grey or CV_8UC3 BGR of the settings' size (pixels; a BGR
  // image gives the objects' colour signatures, a grey one leaves them to
  // source.image_path);
  // timestamp in seconds, finite, strictly increasing; detections in this image's pixels
  // (EAO format, ignored when the options map no objects). Returns T_cw (world to camera,
  // map units) when the frame was tracked, else nothing. Throws std::invalid_argument for
  // an empty image, another type or size, a timestamp not finite or not later than the last
  // frame's; std::logic_error after Shutdown().
  std::optional<SE3> Track(const cv::Mat& image, double timestamp,
                           const std::vector<Detection>& detections,
                           const FrameSource& source = {});
  // A function that extracts an image's ORB features as tracking does (System::
  // MakeFeatureExtractor), for a thread that prepares frames ahead: give its result to
  // Track() in FrameSource::features. One per thread; safe to call before Track().
  std::function<ExtractedFeatures(const cv::Mat&)> FeatureExtractor() const;
  // Finishes local mapping, loop closing and the OCG; the objects take the final poses.
  // Idempotent; rethrows a failure of a worker thread.
  void Shutdown();
  bool IsShutDown() const { return shut_down_; }
  // Whether options.stop was requested: the caller's frame loop then gives no more frames
  // and goes on to Shutdown(), Save() and SaveMap() as at the end of its frames.
  bool StopRequested() const;
  // The counts of the run so far; between Track() calls, from the tracking thread (it
  // takes the map's lock, so a few times a second at most).
  RunStatus Status() const;

  // What tracking made of the last frame given (state kNoImages before the first).
  FrameReport LastFrame() const;
  // The last tracked frame's pose (T_cw), if any frame was tracked since the last reset.
  std::optional<SE3> Pose() const;
  // objects.json and changes.json (docs/objects.md): the object map and the change log.
  std::string Objects() const;
  std::string Changes() const;
  std::vector<StampedPose> KeyFrameTrajectory() const;  // camera to world
  std::vector<StampedPose> CameraTrajectory() const;    // camera to world
  std::size_t FramesGiven() const;

  const std::string& VocabularyFile() const { return vocabulary_file_; }
  std::size_t VocabularyWords() const;
  double VocabularyLoadSeconds() const { return vocabulary_seconds_; }
  bool Sequential() const;

  // After Shutdown(): writes KeyFrameTrajectory.txt, CameraTrajectory.txt,
  // map_points.ply, the object files (objects.json, changes.json, ocg.json,
  // ocg_observations.jsonl) when objects are mapped, the final snapshots, and run.json
  // (docs/slam.md) into folder, and the same for every folder of options.also_modes;
  // returns folder's run.json content. Throws std::logic_error before Shutdown(),
  // FileError when a file cannot be written.
  nlohmann::json Save(const std::string& folder, const RunDescription& description);
  // After Shutdown(): the whole state (SLAM map, object map, OCG, the settings) as a map
  // file (docs/sessions.md), written atomically; call before Save() so that run.json
  // names it. Throws std::logic_error before Shutdown(), FileError when it cannot be
  // written.
  void SaveMap(const std::string& path);
  // This run's session index: 0 for a new map, one more than the loaded file's last.
  int Session() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
  std::string vocabulary_file_;
  double vocabulary_seconds_ = 0.0;
  bool shut_down_ = false;
};

}  // namespace ocg
