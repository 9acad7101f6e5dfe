#pragma once
// The sequence runner: what feeds a recorded sequence to the system, for `ocg_slam run`,
// `ocg_slam objects` and Python's ObjectSlam.run alike (the tool only parses options).
//  - frames: the image list (TUM, EuRoC, KITTI) or, pose-given, the names of the
//    detection files; EuRoC's nanosecond names written in seconds in the trajectories;
//  - detections: one DetectionSource per run (EAO folder, JSON list, boxes in memory, or
//    the detector network), its format told by the path given;
//  - read-ahead: the image_reader thread decodes the next images, extracts their ORB
//    features and asks the detection source, a few frames ahead of tracking (a detector
//    network then runs there, not on the tracking thread);
//  - the realtime feed (LiveFeed): images at the pace of their timestamps, those a live
//    camera would have replaced dropped;
//  - progress: the terminal line, or a log line every few seconds, and a stop request
//    (RunStop) ending the frames after the one in hand.
//
// Sequential mode is deterministic whatever the read-ahead: the images, features and
// detections handed to tracking are exactly those of reading one frame after the other.

#include <cstddef>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "ocg/app/object_slam.h"
#include "ocg/app/run_stop.h"
#include "ocg/io/detection_source.h"
#include "ocg/io/sequence.h"

namespace ocg {

// Where a run's detections come from (at most one of files and detect).
struct DetectionInput {
  // An EAO folder of <timestamp>.txt files or a JSON list file; empty: none.
  std::string files;
  // Skip malformed lines of the files with a warning instead of failing.
  bool lenient = false;
  // Detect on each frame with a detector network (ocg/detect/detection_model.h).
  bool detect = false;
  std::string model;          // .onnx file; empty: DefaultDetectorModel()
  double detect_score = 0.0;  // minimum confidence; 0: the model's default
  bool Any() const { return detect || !files.empty(); }
};

// The source for input over the frames (timestamp texts) to process; null when input
// names none. Throws std::invalid_argument when both files and detect are given, FileError
// when the files or the model are missing (for the model, how to get it), ParseError for
// malformed files, as OpenDetectionFiles and DetectionModel.
std::unique_ptr<DetectionSource> OpenDetections(const DetectionInput& input,
                                                const std::vector<std::string>& frames);

// "paper,visibility" -> {"paper", "visibility"} (`--modes`). Throws std::invalid_argument
// when a mode is empty or given twice.
std::vector<std::string> ParseModes(const std::string& text);

// EuRoC names images by nanoseconds; trajectories are written in seconds (TUM format),
// with every digit kept: "1403715273262142976" -> "1403715273.262142976". Other formats:
// the text as given.
std::string TimestampInSeconds(const std::string& text, const std::string& format);

struct FeedOptions {
  std::size_t max_frames = 0;  // the first frames only; 0: all
  // Images decoded (and prepared: features, detections) ahead on the image_reader thread;
  // -1: ImageReadAhead::AutomaticDepth(), 0: no thread (each frame prepared when due).
  int read_ahead = -1;
  // Feed at the pace of the timestamps, as a live camera (LiveFeed).
  bool realtime = false;
  std::string format = "tum";  // the sequence's, for TimestampInSeconds
  // The self-overwriting progress line on a terminal (ProgressLine).
  bool progress_line = false;
  // Without a terminal, a log line with the run's status every this many seconds (0: none).
  double status_seconds = 0.0;
};

struct FeedReport {
  std::size_t frames = 0;   // frames to process
  bool stopped = false;     // a stop request ended the frames early
  nlohmann::json feed;      // LiveFeed::Report() with realtime, else null
  nlohmann::json reader;    // read-ahead depth and timings (run.json "reader")
  std::size_t dropped = 0;  // realtime: frames a live camera had replaced
};

// Tracks the sequence's frames (the first max_frames) with their detections (source may
// be null: none). Stops early when slam.StopRequested(). Does not shut slam down. Throws
// FileError naming an image that cannot be read, std::invalid_argument when there is no
// frame, and what Track() and the source throw.
FeedReport FeedSequence(ObjectSlam& slam, const ImageSequence& sequence, DetectionSource* source,
                        const FeedOptions& options);

// `ocg_slam run`: every input read and checked before the first frame (settings, frame
// list, detections, output folders, map file target), the run, then its outputs (those of
// ObjectSlam::Save and SaveMap). Messages for the user go to out.
struct SlamRunRequest {
  std::string settings, sequence, format = "tum", output, vocabulary;
  std::string mode;       // OCG.mode override; empty: the settings'
  std::string modes;      // several modes, comma-separated (ObjectSlamOptions::also_modes)
  std::string snapshots;  // ParseSnapshotPolicy; empty: final, or every Viewer.every_keyframes
  std::string load_map, save_map;
  DetectionInput detections;
  FeedOptions feed;
  const RunStop* stop = nullptr;
  // Called once every input is checked, just before the first frame (ocg_slam: from
  // then on a signal stops the run cleanly).
  std::function<void()> before_frames;
};
// Returns run.json's content. Throws as the steps it runs; a map file that cannot be
// written is reported (FileError) after every other output was written.
nlohmann::json RunSlamOnSequence(const SlamRunRequest& request, std::ostream& out);

// `ocg_slam objects` (pose-given, docs/objects.md): frames from the image list, or named
// by the detection files; poses from the trajectory; MapObjectsAlongTrajectory.
struct PoseGivenRequest {
  std::string trajectory, settings, output;
  std::string frames;  // image list (rgb.txt); empty: the frames the detection files name
  std::string mode;    // OCG.mode override
  std::string snapshots = "final";  // final, every:N (OCG keyframes) or none (docs/viewer.md)
  DetectionInput detections;        // files only
  bool progress_line = false;
  const RunStop* stop = nullptr;
  std::function<void()> before_frames;  // as SlamRunRequest's
};
// Writes the object files, the trajectories, the snapshots and run.json into
// request.output; returns run.json's content.
nlohmann::json RunPoseGiven(const PoseGivenRequest& request, std::ostream& out);

}  // namespace ocg
