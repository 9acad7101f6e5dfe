#include "ocg/app/sequence_runner.h"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <any>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <stdexcept>
#include <utility>

#include "object_layer.h"
#include "ocg/app/live_feed.h"
#include "ocg/app/pose_given.h"
#include "ocg/app/settings.h"
#include "ocg/core/cpu_time.h"
#include "ocg/core/file_io.h"
#include "ocg/core/logging.h"
#include "ocg/core/settings_file.h"
#include "ocg/core/statistics.h"
#include "ocg/detect/detection_model.h"
#include "ocg/io/image_read_ahead.h"
#include "ocg/io/trajectory.h"

namespace ocg {
namespace {

// Long runs show their growth: on a terminal in the progress line, elsewhere (logs, a
// soak) as a log line every `seconds`.
std::string DescribeStatus(const RunStatus& status) {
  char text[160];
  std::snprintf(text, sizeof text,
                "%zu keyframes, %zu map points, %zu objects, RSS %.0f MB, heap %.0f MB",
                status.keyframes, status.map_points, status.objects,
                static_cast<double>(status.resident_bytes) / 1e6,
                static_cast<double>(status.heap_bytes) / 1e6);
  return text;
}

class StatusLines {
 public:
  StatusLines(double seconds, bool terminal) : seconds_(terminal ? 0.0 : seconds) {}
  void Update(std::size_t done, std::size_t total, const ObjectSlam& slam) {
    if (seconds_ <= 0.0) return;
    const auto now = std::chrono::steady_clock::now();
    if (now < next_) return;
    if (done == 1) start_ = now;
    next_ = now + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                      std::chrono::duration<double>(seconds_));
    if (done == 1) return;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const RunStatus status = slam.Status();
    spdlog::info("progress: {:.0f} s, frame {}/{}, {:.1f} fps, {}", status.seconds, done, total,
                 elapsed > 0.0 ? static_cast<double>(done - 1) / elapsed : 0.0,
                 DescribeStatus(status));
  }

 private:
  double seconds_;
  std::chrono::steady_clock::time_point start_, next_;
};

// What the reader (or, without read-ahead, the frame's turn) made of an image besides
// its pixels.
struct PreparedFrame {
  std::shared_ptr<const ExtractedFeatures> features;  // null: tracking extracts them
  std::vector<Detection> detections;
  double detect_seconds = 0.0;      // wall time of the source's answer
  double detect_cpu_seconds = 0.0;  // the reader thread's CPU time of it
};

// The sequence's first max_frames frames (0: all). Throws when there is none.
std::size_t FramesToProcess(const ImageSequence& sequence, std::size_t max_frames) {
  std::size_t frames = sequence.images.size();
  if (max_frames > 0) frames = std::min(frames, max_frames);
  if (frames == 0) {
    throw std::invalid_argument("no frames to process: '" + sequence.list +
                                "' lists no image (only comments or blank lines)");
  }
  return frames;
}

// The progress line when asked for and stdout is a terminal.
bool ProgressOnTerminal(bool wanted) { return wanted && ::isatty(::fileno(stdout)) != 0; }

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// --save-map is written at the end of a run: a target that cannot take a file fails now,
// before any frame, not after the whole run.
void CheckMapFileTarget(const std::string& path) {
  if (std::filesystem::is_directory(path))
    throw FileError("--save-map '" + path + "' is a folder: give the map file's name, e.g. '" +
                    (std::filesystem::path(path) / "map.ocgmap").string() + "'");
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  try {
    CheckWritableFolder(folder.empty() ? "." : folder.string());
  } catch (const FileError& error) {
    throw FileError("--save-map '" + path + "': " + error.what());
  }
}

// ORB-SLAM2's TUM settings files give no image size, and `objects` reads no image to
// process: the size is then the first readable image of the --frames list. Throws naming
// the keys when there is none.
void TakeImageSizeFromFrames(const PoseGivenRequest& request, CameraSettings* camera) {
  const std::string keys = "Camera.width and Camera.height";
  if (request.frames.empty()) {
    throw SettingsError(request.settings + ": camera keys missing: this command needs " + keys +
                        " (or --frames listing images to take the size from)");
  }
  const std::string base = std::filesystem::path(request.frames).parent_path().string();
  for (const TimedImage& image : ReadTumImageList(request.frames, base)) {
    if (!std::filesystem::is_regular_file(image.path)) continue;
    const cv::Mat first = cv::imread(image.path, cv::IMREAD_UNCHANGED);
    if (first.empty()) continue;
    camera->model.width = first.cols;
    camera->model.height = first.rows;
    camera->Check();
    spdlog::info("image size {}x{} from '{}' ({} not in '{}')", first.cols, first.rows, image.path,
                 keys, request.settings);
    return;
  }
  throw SettingsError(request.settings + ": camera keys missing: this command needs " + keys +
                      " (no image listed in '" + request.frames +
                      "' could be read to take the size from)");
}

}  // namespace

std::unique_ptr<DetectionSource> OpenDetections(const DetectionInput& input,
                                                const std::vector<std::string>& frames) {
  if (input.detect && !input.files.empty()) {
    throw std::invalid_argument("detections: give either files ('" + input.files +
                                "') or the detector, not both");
  }
  if (!input.files.empty()) {
    DetectionReadOptions read_options;
    read_options.lenient = input.lenient;
    return OpenDetectionFiles(input.files, frames, read_options);
  }
  if (!input.detect) return nullptr;
  DetectionModelOptions options;
  options.model_path = input.model.empty() ? DefaultDetectorModel() : input.model;
  if (input.detect_score > 0.0) options.score_threshold = input.detect_score;
  options.Check();
  RequireDetectorModel(options.model_path);
  return std::make_unique<DetectionModel>(options);
}

std::vector<std::string> ParseModes(const std::string& text) {
  std::vector<std::string> modes;
  for (std::size_t start = 0; !text.empty() && start <= text.size();) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    modes.push_back(text.substr(start, comma - start));
    start = comma + 1;
  }
  for (std::size_t i = 0; i < modes.size(); ++i) {
    if (modes[i].empty() ||
        std::find(modes.begin(), modes.begin() + i, modes[i]) != modes.begin() + i) {
      throw std::invalid_argument("--modes '" + text +
                                  "': give each mode once, comma-separated, none empty");
    }
  }
  return modes;
}

std::string TimestampInSeconds(const std::string& text, const std::string& format) {
  if (format != "euroc" || text.size() <= 9 ||
      text.find_first_not_of("0123456789") != std::string::npos) {
    return text;
  }
  return text.substr(0, text.size() - 9) + "." + text.substr(text.size() - 9);
}

FeedReport FeedSequence(ObjectSlam& slam, const ImageSequence& sequence, DetectionSource* source,
                        const FeedOptions& options) {
  FeedReport report;
  const std::size_t frames = FramesToProcess(sequence, options.max_frames);
  report.frames = frames;
  std::vector<std::string> image_paths;
  image_paths.reserve(frames);
  for (std::size_t i = 0; i < frames; ++i) image_paths.push_back(sequence.images[i].path);
  const std::size_t depth = options.read_ahead >= 0 ? static_cast<std::size_t>(options.read_ahead)
                                                    : ImageReadAhead::AutomaticDepth();
  // Read ahead, the reader thread extracts the ORB features too: half of tracking's CPU
  // then runs while the previous frame is tracked. Without a reader thread tracking
  // extracts them itself (the same features). The detections are asked there as well, so
  // a detector network runs off the tracking thread, on the image as read from disk (the
  // pixels ocg_detect sees: a grey decoding is not a colour one converted).
  std::function<ExtractedFeatures(const cv::Mat&)> extractor;
  if (depth > 0) extractor = slam.FeatureExtractor();
  const ImageReadAhead::Prepare prepare = [&](std::size_t index, const cv::Mat& grey) -> std::any {
    PreparedFrame prepared;
    if (extractor) prepared.features = std::make_shared<const ExtractedFeatures>(extractor(grey));
    if (source != nullptr) {
      const TimedImage& image = sequence.images[index];
      cv::Mat as_read;
      if (source->NeedsImage()) {
        as_read = cv::imread(image.path, cv::IMREAD_UNCHANGED);
        if (as_read.empty()) throw FileError("cannot read image '" + image.path + "'");
      }
      const auto start = std::chrono::steady_clock::now();
      const double cpu_start = ThreadCpuSeconds();
      prepared.detections = source->DetectionsFor(image.timestamp_text, as_read);
      prepared.detect_cpu_seconds = ThreadCpuSeconds() - cpu_start;
      prepared.detect_seconds = SecondsSince(start);
    }
    return prepared;
  };
  std::optional<LiveFeed> live;
  ImageReadAhead::Skip replaced;
  if (options.realtime) {
    std::vector<double> timestamps;
    timestamps.reserve(frames);
    for (std::size_t i = 0; i < frames; ++i) timestamps.push_back(sequence.images[i].timestamp);
    live.emplace(std::move(timestamps));
    replaced = [&live](std::size_t index) { return live->Replaced(index); };
  }
  ImageReadAhead images(std::move(image_paths), cv::IMREAD_GRAYSCALE, depth, prepare, replaced);

  ProgressLine progress("frames", frames, ProgressOnTerminal(options.progress_line));
  StatusLines status_lines(options.status_seconds, progress.enabled());
  // Summaries, not one number a frame: a long run keeps its memory flat.
  DurationSummary detect_seconds, detect_cpu_seconds, wait_seconds;
  std::size_t boxes = 0;
  const auto track = [&](std::size_t i) {
    const TimedImage& image = sequence.images[i];
    const auto wait_start = std::chrono::steady_clock::now();
    ImageReadAhead::Frame frame = images.NextFrame();
    wait_seconds.Add(SecondsSince(wait_start));
    if (frame.image.empty())  // LiveFeed::Replaced said it would never be delivered
      throw std::logic_error("image " + std::to_string(i) + " was skipped but is due");
    PreparedFrame prepared = std::any_cast<PreparedFrame>(std::move(frame.prepared));
    FrameSource frame_source{TimestampInSeconds(image.timestamp_text, options.format), image.path,
                             prepared.features};
    if (source != nullptr) {
      detect_seconds.Add(prepared.detect_seconds);
      detect_cpu_seconds.Add(prepared.detect_cpu_seconds);
      boxes += prepared.detections.size();
    }
    slam.Track(frame.image, image.timestamp, prepared.detections, frame_source);
    progress.Update(i + 1, [&slam] { return DescribeStatus(slam.Status()); });
    status_lines.Update(i + 1, frames, slam);
  };
  if (live) {
    images.WaitForNext();  // the camera starts once the system has its first image
    std::size_t images_taken = 0;
    while (!slam.StopRequested()) {
      const std::optional<std::size_t> due = live->Next();
      if (!due) break;
      // Images the live camera replaced before tracking was ready are lost (and were not
      // decoded, unless read ahead before the camera replaced them).
      for (; images_taken < *due; ++images_taken) images.Next();
      track(*due);
      ++images_taken;
    }
    report.feed = live->Report();
    report.dropped = live->Dropped().size();
  } else {
    for (std::size_t i = 0; i < frames && !slam.StopRequested(); ++i) track(i);
  }
  progress.Finish();
  report.stopped = slam.StopRequested();
  // Whether tracking waits for its frames: the time each NextFrame took on the tracking
  // thread (with a reader thread, waiting for it; without, decoding and preparing there).
  report.reader = {{"read_ahead", depth},
                   {"frame_wait_per_frame", app_detail::Timing(wait_seconds)},
                   {"detections", source != nullptr ? source->Describe() : std::string("none")}};
  if (source != nullptr) {
    report.reader["detect_per_frame"] = app_detail::Timing(detect_seconds);
    report.reader["detect_cpu_per_frame"] = app_detail::Timing(detect_cpu_seconds);
    report.reader["boxes"] = boxes;
  }
  return report;
}

nlohmann::json RunSlamOnSequence(const SlamRunRequest& request, std::ostream& out) {
  const LoadedSettings loaded = LoadSettings(request.settings, CameraNeed::kIntrinsics);
  Settings settings = loaded.settings;
  // --modes: the first mode is the run's own, in OUT/<mode>/; the others are object
  // layers fed the same SLAM frames (ObjectSlamOptions::also_modes).
  const std::vector<std::string> modes = ParseModes(request.modes);
  std::string mode = request.mode;
  if (!modes.empty()) {
    if (!request.detections.Any()) throw std::invalid_argument("--modes needs --detections");
    mode = modes.front();
  }
  if (!mode.empty()) {
    settings.ocg.mode = mode;
    settings.ocg.Check();
  }
  const std::string output = modes.empty() ? request.output : request.output + "/" + modes.front();
  // Every input is read and checked before the first frame (the detections of every
  // frame to process included), and the output folder is tried for writing, so no bad
  // input ends a run after the whole sequence.
  const ImageSequence sequence = ReadSequence(request.sequence, request.format);
  const std::size_t frames = FramesToProcess(sequence, request.feed.max_frames);
  CheckCameraFitsImage(loaded, sequence.images.front().path);
  std::vector<std::string> frame_names;
  frame_names.reserve(frames);
  for (std::size_t i = 0; i < frames; ++i) frame_names.push_back(sequence.images[i].timestamp_text);
  const std::unique_ptr<DetectionSource> detections =
      OpenDetections(request.detections, frame_names);
  CheckWritableFolder(output);
  if (!request.save_map.empty()) CheckMapFileTarget(request.save_map);
  ObjectSlamOptions options;
  for (std::size_t i = 1; i < modes.size(); ++i) {
    options.also_modes.emplace_back(modes[i], request.output + "/" + modes[i]);
    CheckWritableFolder(options.also_modes.back().second);
  }
  options.vocabulary_path = request.vocabulary;
  options.load_map = request.load_map;
  options.map_objects = detections != nullptr;
  options.stop = request.stop;
  if (!request.snapshots.empty()) {
    options.snapshots = ParseSnapshotPolicy(request.snapshots);
  } else {
    options.snapshots = SnapshotPolicy{};  // final
    options.snapshots.every_keyframes = settings.viewer.every_keyframes;
  }
  options.snapshot_folder = output + "/snapshots";
  const std::string groundtruth_path = request.sequence + "/groundtruth.txt";
  if (request.format == "tum" && std::filesystem::exists(groundtruth_path))
    options.groundtruth = ReadTumTrajectory(groundtruth_path);
  ObjectSlam slam(settings, options);
  if (!request.load_map.empty()) {
    out << "ocg_slam: session " << slam.Session() << " of the map " << request.load_map
        << " (relocalizing in it)\n";
  }
  out << "ocg_slam: " << frames << " frames of " << request.sequence << ", vocabulary "
      << slam.VocabularyFile() << " (" << slam.VocabularyWords() << " words, loaded in "
      << slam.VocabularyLoadSeconds() << " s), " << (slam.Sequential() ? "sequential" : "threaded")
      << " mode" << (request.detections.detect ? ", detector " + detections->Describe() : "")
      << "\n";
  FeedOptions feed = request.feed;
  feed.format = request.format;
  if (request.before_frames) request.before_frames();
  const FeedReport fed = FeedSequence(slam, sequence, detections.get(), feed);
  if (fed.stopped) {
    out << "stopped by a signal after " << slam.FramesGiven() << " of " << frames
        << " frames: finishing the map, then writing every output\n";
  }
  if (request.feed.realtime) {
    out << "real time: " << fed.dropped << " of " << frames
        << " frames dropped (a live camera had replaced them before tracking was ready)\n";
  }
  if (request.detections.detect) {
    const nlohmann::json& per_frame = fed.reader["detect_per_frame"];
    out << "detector: " << fed.reader["boxes"] << " boxes, median "
        << per_frame["median_ms"].get<double>() << " ms per frame on the "
        << (fed.reader["read_ahead"].get<std::size_t>() > 0 ? "image_reader" : "tracking")
        << " thread; tracking waited a median "
        << fed.reader["frame_wait_per_frame"]["median_ms"].get<double>() << " ms per frame\n";
  }
  slam.Shutdown();
  // A map file that cannot be written (the disk filled during the run) loses none of the
  // run's files: they are written all the same, then the error is reported.
  std::optional<std::string> save_error;
  if (!request.save_map.empty()) {
    try {
      slam.SaveMap(request.save_map);
    } catch (const std::exception& error) {
      save_error = error.what();
    }
  }
  RunDescription description{
      request.sequence, request.settings,
      request.detections.detect
          ? (request.detections.model.empty() ? DefaultDetectorModel() : request.detections.model)
          : request.detections.files,
      detections ? detections->FramesMatched() : 0, fed.feed};
  description.reader = fed.reader;
  const nlohmann::json report = slam.Save(output, description);
  if (save_error)
    throw FileError("--save-map: " + *save_error + " (the run's files are in " + output + ")");
  if (report.contains("objects")) {
    const nlohmann::json& section = report["objects"];
    out << "objects: " << section["objects_created"] << " created, " << section["objects_live"]
        << " live at the end, " << section["keyframes"] << " OCG keyframes (mode "
        << settings.ocg.mode << ")\n";
  }
  if (modes.size() > 1)
    out << "the same SLAM run's objects in the other modes: " << request.output << "/{"
        << request.modes << "}\n";
  out << "tracked " << report["frames_tracked"] << " of " << frames << " frames (first at "
      << report["first_tracked_frame"] << "), lost " << report["frames_lost"] << ", relocalized "
      << report["relocalizations"] << ", resets " << report["map_resets"] << ", loops closed "
      << report["loop_closing"]["loops"].size() << "; " << report["keyframes"] << " keyframes, "
      << report["map_points"] << " points; tracking median "
      << report["timing"]["tracking_per_frame"]["median_ms"].get<double>() << " ms/frame\n"
      << "wrote " << output << "/KeyFrameTrajectory.txt, CameraTrajectory.txt, map_points.ply, "
      << "run.json"
      << (report.contains("objects")
              ? ", objects.json, changes.json, ocg.json, ocg_observations.jsonl"
              : "")
      << "\n";
  if (report["session"].contains("message")) {
    spdlog::warn("{}", report["session"]["message"].get<std::string>());
  } else if (!request.load_map.empty()) {
    out << "session " << slam.Session() << ": relocalized in " << request.load_map << " after "
        << report["session"]["frames_until_relocalized"] << " frame(s)\n";
  }
  if (!request.save_map.empty()) out << "wrote the map file " << request.save_map << "\n";
  if (report["initialization"].contains("message"))
    spdlog::warn("{}", report["initialization"]["message"].get<std::string>());
  return report;
}

nlohmann::json RunPoseGiven(const PoseGivenRequest& request, std::ostream& out) {
  if (request.detections.detect)
    throw std::invalid_argument("pose-given mode reads no image: give detection files");
  const LoadedSettings loaded = LoadSettings(request.settings, CameraNeed::kIntrinsics);
  Settings settings = loaded.settings;
  if (!loaded.image_size_given) TakeImageSizeFromFrames(request, &settings.camera);
  if (!request.mode.empty()) {
    settings.ocg.mode = request.mode;
    settings.ocg.Check();
  }
  const std::vector<StampedPose> trajectory = ReadTumTrajectory(request.trajectory);
  if (trajectory.empty()) throw std::invalid_argument("'" + request.trajectory + "' holds no pose");
  DetectionReadOptions read_options;
  read_options.lenient = request.detections.lenient;
  // The frames to process: the image list's timestamps, or the detection files' names.
  const std::vector<TimedImage> frames =
      request.frames.empty()
          ? FramesNamedByDetections(request.detections.files, read_options)
          : ReadTumImageList(request.frames,
                             std::filesystem::path(request.frames).parent_path().string());
  if (frames.empty()) throw std::invalid_argument("no frames to process");
  // Every input is read and checked before the first frame, so a bad line in the last
  // file or a frame list that matches no pose fails now, not after the whole sequence.
  std::vector<std::string> frame_names;
  frame_names.reserve(frames.size());
  for (const TimedImage& frame : frames) frame_names.push_back(frame.timestamp_text);
  const std::unique_ptr<DetectionSource> detections =
      OpenDetections(request.detections, frame_names);
  if (!detections) throw std::invalid_argument("pose-given mode needs detections");
  std::vector<PoseGivenFrame> pose_given;
  pose_given.reserve(frames.size());
  for (const TimedImage& frame : frames) {
    // The image, when listed, is drawn under the frame views.
    pose_given.push_back({frame.timestamp_text, frame.timestamp,
                          PoseAtTime(trajectory, frame.timestamp),
                          request.frames.empty() ? std::string() : frame.path});
  }
  if (std::none_of(pose_given.begin(), pose_given.end(),
                   [](const PoseGivenFrame& frame) { return frame.T_cw.has_value(); })) {
    throw std::invalid_argument(
        "no frame has a pose in '" + request.trajectory + "': its poses span " +
        trajectory.front().timestamp_text + " .. " + trajectory.back().timestamp_text +
        ", the frames (" +
        (request.frames.empty() ? "from the detection files' names"
                                : "from '" + request.frames + "'") +
        ") span " + frames.front().timestamp_text + " .. " + frames.back().timestamp_text +
        " (timestamps must match within 20 ms or lie between two poses at most 0.1 s apart)");
  }
  CheckWritableFolder(request.output);
  out << "ocg_slam objects: " << frames.size() << " frames, " << trajectory.size()
      << " poses, OCG mode " << settings.ocg.mode << ", a keyframe every "
      << settings.objects.keyframe_interval << " frames\n";

  const SnapshotPolicy snapshots = ParseSnapshotPolicy(request.snapshots);
  ProgressLine progress("frames", frames.size(), ProgressOnTerminal(request.progress_line));
  if (request.before_frames) request.before_frames();
  nlohmann::json report = MapObjectsAlongTrajectory(
      settings, pose_given, *detections, request.output,
      [&progress](std::size_t done) { progress.Update(done); }, request.stop, snapshots);
  progress.Finish();
  report.update({{"command", "objects"},
                 {"trajectory", request.trajectory},
                 {"detections", request.detections.files},
                 {"detection_files_matched", detections->FramesMatched()},
                 {"settings", request.settings},
                 {"ocg_mode", settings.ocg.mode}});
  WriteFileAtomically(request.output + "/run.json", report.dump(2) + "\n");
  out << report["frames_used"] << " frames (" << report["frames_without_pose"]
      << " without a pose skipped), " << report["keyframes"] << " keyframes; "
      << report["objects_created"] << " objects created, " << report["objects_live"]
      << " live at the end; " << report["wall_seconds"].get<double>() << " s\n"
      << "wrote " << request.output
      << "/objects.json, changes.json, ocg.json, ocg_observations.jsonl, run.json, "
         "CameraTrajectory.txt, KeyFrameTrajectory.txt"
      << (report["snapshots"].is_null() ? "" : ", snapshots/") << "\n";
  return report;
}

}  // namespace ocg
