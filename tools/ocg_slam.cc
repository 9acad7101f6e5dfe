// ocg_slam: monocular SLAM on a TUM or EuRoC sequence; writes the keyframe and camera
// trajectories (TUM format) and run.json (docs/slam.md). `ocg_slam objects` builds the
// object map from a given trajectory and detections alone (docs/objects.md).

#include <signal.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <any>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "cli_common.h"
#include "ocg/app/live_feed.h"
#include "ocg/app/object_slam.h"
#include "ocg/app/pose_given.h"
#include "ocg/app/run_stop.h"
#include "ocg/app/settings.h"
#include "ocg/core/file_io.h"
#include "ocg/core/logging.h"
#include "ocg/core/settings_file.h"
#include "ocg/io/detections.h"
#include "ocg/io/image_read_ahead.h"
#include "ocg/io/sequence.h"
#include "ocg/io/trajectory.h"
#include "ocg/viewer/snapshots.h"
#include "settings_command.h"

namespace {

// The signal that stopped the run (0: none); the exit code is 128 + it.
volatile sig_atomic_t stop_signal = 0;

// SIGINT, SIGTERM: the first asks the run to stop after the frame in hand and write
// everything (RunStop); a second exits at once. Only async-signal-safe calls.
extern "C" void OnStopSignal(int signal) {
  const auto say = [](const char* text, std::size_t length) {
    if (::write(STDERR_FILENO, text, length) < 0) return;
  };
  if (ocg::ProcessRunStop().Request() > 1) {
    static const char kNow[] = "\nocg_slam: second signal: exiting at once, outputs not written\n";
    say(kNow, sizeof kNow - 1);
    ::_exit(128 + signal);
  }
  stop_signal = signal;
  static const char kStop[] =
      "\nocg_slam: stopping after the frame in hand, then writing every output and the map "
      "(a second signal exits at once)\n";
  say(kStop, sizeof kStop - 1);
}

void StopOnSignals() {
  struct sigaction action {};
  action.sa_handler = OnStopSignal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

// Long runs show their growth: on a terminal in the progress line, elsewhere (logs, a
// soak) as a log line every `seconds`.
std::string DescribeStatus(const ocg::RunStatus& status) {
  char text[160];
  std::snprintf(text, sizeof text, "%zu keyframes, %zu map points, %zu objects, RSS %.0f MB",
                status.keyframes, status.map_points, status.objects,
                static_cast<double>(status.resident_bytes) / 1e6);
  return text;
}

class StatusLines {
 public:
  StatusLines(double seconds, bool terminal) : seconds_(terminal ? 0.0 : seconds) {}
  void Update(std::size_t done, std::size_t total, const ocg::ObjectSlam& slam) {
    if (seconds_ <= 0.0) return;
    const auto now = std::chrono::steady_clock::now();
    if (now < next_) return;
    if (done == 1) start_ = now;
    next_ = now + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                      std::chrono::duration<double>(seconds_));
    if (done == 1) return;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const ocg::RunStatus status = slam.Status();
    spdlog::info("progress: {:.0f} s, frame {}/{}, {:.1f} fps, {}", status.seconds, done, total,
                 elapsed > 0.0 ? static_cast<double>(done - 1) / elapsed : 0.0,
                 DescribeStatus(status));
  }

 private:
  double seconds_;
  std::chrono::steady_clock::time_point start_, next_;
};

// EuRoC names images by nanoseconds; trajectories are written in seconds (TUM format),
// with every digit kept: "1403715273262142976" -> "1403715273.262142976".
std::string TimestampInSeconds(const std::string& text, const std::string& format) {
  if (format != "euroc" || text.size() <= 9 ||
      text.find_first_not_of("0123456789") != std::string::npos) {
    return text;
  }
  return text.substr(0, text.size() - 9) + "." + text.substr(text.size() - 9);
}

struct ObjectsCommand {
  std::string trajectory, detections, settings, frames, output, mode, snapshots = "final";
  bool lenient = false;
};

// The frames to process: the image list's timestamps (and images, for the frame views),
// or the detection files' names.
struct ObjectsFrame {
  std::string first;  // timestamp text
  double second = 0.0;
  std::string image_path;
};
std::vector<ObjectsFrame> FrameTimestamps(const ObjectsCommand& command) {
  std::vector<ObjectsFrame> frames;
  if (!command.frames.empty()) {
    const std::string base = std::filesystem::path(command.frames).parent_path().string();
    for (const ocg::TimedImage& image : ocg::ReadTumImageList(command.frames, base)) {
      frames.push_back({image.timestamp_text, image.timestamp, image.path});
    }
    return frames;
  }
  for (const auto& entry : std::filesystem::directory_iterator(command.detections)) {
    if (entry.path().extension() != ".txt") continue;
    const std::string stem = entry.path().stem().string();
    char* end = nullptr;
    const double timestamp = std::strtod(stem.c_str(), &end);
    if (end == stem.c_str() || *end != '\0') {
      throw std::invalid_argument("detection file '" + entry.path().string() +
                                  "' is not named <timestamp>.txt (give the frames with --frames)");
    }
    frames.push_back({stem, timestamp, ""});
  }
  std::sort(frames.begin(), frames.end(),
            [](const auto& a, const auto& b) { return a.second < b.second; });
  return frames;
}

// ORB-SLAM2's TUM settings files give no image size, and `objects` reads no image to
// process: the size is then the first readable image of the --frames list. Throws naming
// the keys when there is none.
void TakeImageSizeFromFrames(const ObjectsCommand& command, ocg::CameraSettings* camera) {
  const std::string keys = "Camera.width and Camera.height";
  if (command.frames.empty()) {
    throw ocg::SettingsError(command.settings + ": camera keys missing: this command needs " +
                             keys + " (or --frames listing images to take the size from)");
  }
  const std::string base = std::filesystem::path(command.frames).parent_path().string();
  for (const ocg::TimedImage& image : ocg::ReadTumImageList(command.frames, base)) {
    if (!std::filesystem::is_regular_file(image.path)) continue;
    const cv::Mat first = cv::imread(image.path, cv::IMREAD_UNCHANGED);
    if (first.empty()) continue;
    camera->model.width = first.cols;
    camera->model.height = first.rows;
    camera->Check();
    spdlog::info("image size {}x{} from '{}' ({} not in '{}')", first.cols, first.rows, image.path,
                 keys, command.settings);
    return;
  }
  throw ocg::SettingsError(command.settings + ": camera keys missing: this command needs " + keys +
                           " (no image listed in '" + command.frames +
                           "' could be read to take the size from)");
}

void RunObjects(const ObjectsCommand& command) {
  const ocg::SnapshotPolicy snapshots = ocg::ParseSnapshotPolicy(command.snapshots);
  const ocg::LoadedSettings loaded =
      ocg::LoadSettings(command.settings, ocg::CameraNeed::kIntrinsics);
  ocg::Settings settings = loaded.settings;
  if (!loaded.image_size_given) TakeImageSizeFromFrames(command, &settings.camera);
  if (!command.mode.empty()) {
    settings.ocg.mode = command.mode;
    settings.ocg.Check();
  }
  const std::vector<ocg::StampedPose> trajectory = ocg::ReadTumTrajectory(command.trajectory);
  if (trajectory.empty()) throw std::invalid_argument("'" + command.trajectory + "' holds no pose");
  const auto frames = FrameTimestamps(command);
  if (frames.empty()) throw std::invalid_argument("no frames to process");
  // Every input is read and checked before the first frame, so a bad line in the last
  // file or a frame list that matches no pose fails now, not after the whole sequence.
  ocg::DetectionReadOptions read_options;
  read_options.lenient = command.lenient;
  std::vector<std::string> frame_names;
  frame_names.reserve(frames.size());
  for (const auto& frame : frames) frame_names.push_back(frame.first);
  const ocg::EaoDetectionFolder detections(command.detections, frame_names, read_options);
  std::vector<std::optional<ocg::SE3>> poses;
  poses.reserve(frames.size());
  for (const auto& frame : frames) poses.push_back(ocg::PoseAtTime(trajectory, frame.second));
  if (std::none_of(poses.begin(), poses.end(), [](const auto& pose) { return pose.has_value(); })) {
    throw std::invalid_argument(
        "no frame has a pose in '" + command.trajectory + "': its poses span " +
        trajectory.front().timestamp_text + " .. " + trajectory.back().timestamp_text +
        ", the frames (" +
        (command.frames.empty() ? "from the detection files' names"
                                : "from '" + command.frames + "'") +
        ") span " + frames.front().first + " .. " + frames.back().first +
        " (timestamps must match within 20 ms or lie between two poses at most 0.1 s apart)");
  }
  ocg::CheckWritableFolder(command.output);
  std::cout << "ocg_slam objects: " << frames.size() << " frames, " << trajectory.size()
            << " poses, OCG mode " << settings.ocg.mode << ", a keyframe every "
            << settings.objects.keyframe_interval << " frames\n";

  std::vector<ocg::PoseGivenFrame> pose_given;
  pose_given.reserve(frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i)
    pose_given.push_back({frames[i].first, frames[i].second, poses[i], frames[i].image_path});
  ocg::ProgressLine progress("frames", frames.size());
  StopOnSignals();
  nlohmann::json report = ocg::MapObjectsAlongTrajectory(
      settings, pose_given, detections, command.output,
      [&progress](std::size_t done) { progress.Update(done); }, &ocg::ProcessRunStop(), snapshots);
  progress.Finish();
  report.update({{"command", "objects"},
                 {"trajectory", command.trajectory},
                 {"detections", command.detections},
                 {"detection_files_matched", detections.FilesMatched()},
                 {"settings", command.settings},
                 {"ocg_mode", settings.ocg.mode}});
  ocg::WriteFileAtomically(command.output + "/run.json", report.dump(2) + "\n");
  std::cout << report["frames_used"] << " frames (" << report["frames_without_pose"]
            << " without a pose skipped), " << report["keyframes"] << " keyframes; "
            << report["objects_created"] << " objects created, " << report["objects_live"]
            << " live at the end; " << report["wall_seconds"].get<double>() << " s\n"
            << "wrote " << command.output
            << "/objects.json, changes.json, ocg.json, ocg_observations.jsonl, run.json, "
               "CameraTrajectory.txt, KeyFrameTrajectory.txt"
            << (report["snapshots"].is_null() ? "" : ", snapshots/") << "\n";
}

// --save-map is written at the end of a run: a target that cannot take a file fails now,
// before any frame, not after the whole run.
void CheckMapFileTarget(const std::string& path) {
  if (std::filesystem::is_directory(path))
    throw ocg::FileError("--save-map '" + path + "' is a folder: give the map file's name, e.g. '" +
                         (std::filesystem::path(path) / "map.ocgmap").string() + "'");
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  try {
    ocg::CheckWritableFolder(folder.empty() ? "." : folder.string());
  } catch (const ocg::FileError& error) {
    throw ocg::FileError("--save-map '" + path + "': " + error.what());
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ocg_slam: monocular SLAM (docs/slam.md)", "ocg_slam"};
  std::string log_level;
  ocg::tools::AddLogLevelOption(app, &log_level);
  app.require_subcommand(1);
  app.fallthrough();  // --log-level may follow the subcommand too
  auto* run = app.add_subcommand("run", "run on an image sequence");
  std::string settings_path, sequence_path, format = "tum", detections, output, vocabulary_path;
  int max_frames = 0;
  bool realtime = false;
  int read_ahead = -1;
  run->add_option("--settings", settings_path, "settings file (ours or ORB-SLAM2's)")
      ->required()
      ->check(CLI::ExistingFile);
  run->add_option("--sequence", sequence_path, "sequence folder")
      ->required()
      ->check(CLI::ExistingDirectory);
  run->add_option("--format", format,
                  "tum (rgb.txt), euroc (mav0/) or kitti (image_0/, times.txt, calib.txt)")
      ->capture_default_str()
      ->check(CLI::IsMember({"tum", "euroc", "kitti"}));
  run->add_option("--detections", detections,
                  "folder of <timestamp>.txt detection files (EAO format): maps objects too, "
                  "writes objects.json, changes.json, ocg.json")
      ->check(CLI::ExistingDirectory);
  run->add_option("--out", output, "output folder")->required();
  run->add_option("--max-frames", max_frames, "stop after N frames (0: all)")
      ->check(CLI::NonNegativeNumber);
  run->add_option("--vocabulary", vocabulary_path, "vocabulary file (overrides Vocabulary.path)");
  std::string run_mode, snapshots;
  bool run_lenient = false;
  run->add_flag("--lenient", run_lenient,
                "skip malformed detection lines with a warning instead of failing");
  run->add_option("--snapshots", snapshots,
                  "PNG snapshots under OUT/snapshots/: final, every:N (also every N "
                  "keyframes) or none; default: final, or every:Viewer.every_keyframes");
  auto* mode_option = run->add_option(
      "--mode", run_mode, "OCG.mode override for the object layer (off, visibility, paper, ...)");
  std::string run_modes;
  run->add_option("--modes", run_modes,
                  "several OCG modes, comma-separated, from one SLAM run: each mode's run "
                  "folder is OUT/<mode>/ (sequential mode, needs --detections, cannot continue a "
                  "--load-map)")
      ->excludes(mode_option);
  run->add_option("--read-ahead", read_ahead,
                  "decode up to N images ahead, and extract their ORB features, on a thread of "
                  "their own (0: decode each when "
                  "it is due, on the tracking thread); default: 4 when the run may use two "
                  "cores or more, else 0")
      ->check(CLI::NonNegativeNumber);
  double progress_seconds = 10.0;
  run->add_option("--progress-seconds", progress_seconds,
                  "when stdout is not a terminal, log the progress (frames, keyframes, map "
                  "points, objects, resident memory) every this many seconds (0: never)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  run->add_flag(
      "--realtime", realtime,
      "feed images at the pace of their timestamps, as a live camera: an image replaced by "
      "the next before tracking was ready is dropped (counted in run.json's feed)");
  std::string load_map, save_map;
  run->add_option("--load-map", load_map,
                  "map file to continue (docs/sessions.md): relocalize in it, then track and "
                  "map in its coordinates as its next session")
      ->check(CLI::ExistingFile);
  run->add_option("--save-map", save_map,
                  "write the whole state at the end to this map file (SLAM map, objects, OCG, "
                  "settings)");

  auto* objects = app.add_subcommand(
      "objects",
      "pose-given mode: build and maintain the object map from a trajectory and detections, no "
      "images (writes objects.json, changes.json, ocg.json, run.json, the trajectories and "
      "snapshots)");
  ObjectsCommand objects_command;
  objects
      ->add_option("--trajectory", objects_command.trajectory,
                   "camera poses, TUM format (camera to world)")
      ->required()
      ->check(CLI::ExistingFile);
  objects
      ->add_option("--detections", objects_command.detections,
                   "folder of <timestamp>.txt detection files (EAO format)")
      ->required()
      ->check(CLI::ExistingDirectory);
  objects
      ->add_option("--settings", objects_command.settings,
                   "settings file (camera, Objects.*, OCG.*)")
      ->required()
      ->check(CLI::ExistingFile);
  objects
      ->add_option("--frames", objects_command.frames,
                   "image list (rgb.txt) giving the frames; default: the detection files")
      ->check(CLI::ExistingFile);
  objects->add_option("--out", objects_command.output, "output folder")->required();
  objects->add_option("--mode", objects_command.mode,
                      "OCG.mode override (off, visibility, paper, ...)");
  objects
      ->add_option("--snapshots", objects_command.snapshots,
                   "PNG snapshots under OUT/snapshots/ as a run takes them: final, every:N "
                   "(also every N OCG keyframes) or none (docs/viewer.md)")
      ->capture_default_str();
  objects->add_flag("--lenient", objects_command.lenient,
                    "skip malformed detection lines with a warning instead of failing");

  ocg::tools::SettingsCommand settings_command;
  ocg::tools::AddSettingsCommand(app, &settings_command);

  const int code = ocg::tools::RunTool(app, argc, argv, log_level, [&] {
    if (settings_command.app->parsed()) {
      RunSettingsCommand(settings_command);
      return;
    }
    if (objects->parsed()) {
      RunObjects(objects_command);
      return;
    }
    const ocg::LoadedSettings loaded =
        ocg::LoadSettings(settings_path, ocg::CameraNeed::kIntrinsics);
    ocg::Settings settings = loaded.settings;
    // --modes: the first mode is the run's own, in OUT/<mode>/; the others are object
    // layers fed the same SLAM frames (ObjectSlamOptions::also_modes).
    std::vector<std::string> modes;
    for (std::size_t start = 0; !run_modes.empty() && start <= run_modes.size();) {
      const std::size_t comma = std::min(run_modes.find(',', start), run_modes.size());
      modes.push_back(run_modes.substr(start, comma - start));
      start = comma + 1;
    }
    if (!modes.empty()) {
      if (detections.empty()) throw std::invalid_argument("--modes needs --detections");
      for (std::size_t i = 0; i < modes.size(); ++i) {
        if (modes[i].empty() ||
            std::find(modes.begin(), modes.begin() + i, modes[i]) != modes.begin() + i) {
          throw std::invalid_argument("--modes '" + run_modes +
                                      "': give each mode once, comma-separated, none empty");
        }
      }
      run_mode = modes.front();
    }
    if (!run_mode.empty()) {
      settings.ocg.mode = run_mode;
      settings.ocg.Check();
    }
    const std::string base_output = output;
    if (!modes.empty()) output = base_output + "/" + modes.front();
    // Every input is read and checked before the first frame (the detections of every
    // frame to process included), and the output folder is tried for writing, so no bad
    // input ends a run after the whole sequence.
    const ocg::ImageSequence sequence = ocg::ReadSequence(sequence_path, format);
    std::size_t frames = sequence.images.size();
    if (max_frames > 0) frames = std::min(frames, static_cast<std::size_t>(max_frames));
    if (frames == 0) {
      throw std::invalid_argument("no frames to process: '" + sequence.list +
                                  "' lists no image (only comments or blank lines)");
    }
    ocg::CheckCameraFitsImage(loaded, sequence.images.front().path);
    std::optional<ocg::EaoDetectionFolder> detection_folder;
    if (!detections.empty()) {
      ocg::DetectionReadOptions read_options;
      read_options.lenient = run_lenient;
      std::vector<std::string> frame_names;
      frame_names.reserve(frames);
      for (std::size_t i = 0; i < frames; ++i)
        frame_names.push_back(sequence.images[i].timestamp_text);
      detection_folder.emplace(detections, frame_names, read_options);
    }
    ocg::CheckWritableFolder(output);
    if (!save_map.empty()) CheckMapFileTarget(save_map);
    ocg::ObjectSlamOptions options;
    for (std::size_t i = 1; i < modes.size(); ++i) {
      options.also_modes.emplace_back(modes[i], base_output + "/" + modes[i]);
      ocg::CheckWritableFolder(options.also_modes.back().second);
    }
    options.vocabulary_path = vocabulary_path;
    options.load_map = load_map;
    options.map_objects = detection_folder.has_value();
    options.stop = &ocg::ProcessRunStop();
    if (!snapshots.empty()) {
      options.snapshots = ocg::ParseSnapshotPolicy(snapshots);
    } else {
      options.snapshots = ocg::SnapshotPolicy{};  // final
      options.snapshots.every_keyframes = settings.viewer.every_keyframes;
    }
    options.snapshot_folder = output + "/snapshots";
    const std::string groundtruth_path = sequence_path + "/groundtruth.txt";
    if (format == "tum" && std::filesystem::exists(groundtruth_path))
      options.groundtruth = ocg::ReadTumTrajectory(groundtruth_path);
    ocg::ObjectSlam slam(settings, options);
    if (!load_map.empty()) {
      std::cout << "ocg_slam: session " << slam.Session() << " of the map " << load_map
                << " (relocalizing in it)\n";
    }
    std::cout << "ocg_slam: " << frames << " frames of " << sequence_path << ", vocabulary "
              << slam.VocabularyFile() << " (" << slam.VocabularyWords() << " words, loaded in "
              << slam.VocabularyLoadSeconds() << " s), "
              << (slam.Sequential() ? "sequential" : "threaded") << " mode\n";
    const std::vector<ocg::Detection> no_detections;
    ocg::ProgressLine progress("frames", frames);
    StatusLines status_lines(progress_seconds, progress.enabled());
    std::vector<std::string> image_paths;
    image_paths.reserve(frames);
    for (std::size_t i = 0; i < frames; ++i) image_paths.push_back(sequence.images[i].path);
    const std::size_t depth = read_ahead >= 0 ? static_cast<std::size_t>(read_ahead)
                                              : ocg::ImageReadAhead::AutomaticDepth();
    // Read ahead, the reader thread extracts the ORB features too: half of tracking's
    // CPU then runs while the previous frame is tracked. Without a reader thread tracking
    // extracts them itself (the same features).
    ocg::ImageReadAhead::Prepare extract;
    if (depth > 0) {
      extract = [extractor = slam.FeatureExtractor()](const cv::Mat& image) -> std::any {
        return std::make_shared<const ocg::ExtractedFeatures>(extractor(image));
      };
    }
    std::optional<ocg::LiveFeed> live;
    ocg::ImageReadAhead::Skip replaced;
    if (realtime) {
      std::vector<double> timestamps;
      timestamps.reserve(frames);
      for (std::size_t i = 0; i < frames; ++i) timestamps.push_back(sequence.images[i].timestamp);
      live.emplace(std::move(timestamps));
      replaced = [&live](std::size_t index) { return live->Replaced(index); };
    }
    ocg::ImageReadAhead images(std::move(image_paths), cv::IMREAD_GRAYSCALE, depth, extract,
                               replaced);
    const auto track = [&](std::size_t i) {
      const ocg::TimedImage& image = sequence.images[i];
      ocg::ImageReadAhead::Frame frame = images.NextFrame();
      if (frame.image.empty())  // LiveFeed::Replaced said it would never be delivered
        throw std::logic_error("image " + std::to_string(i) + " was skipped but is due");
      ocg::FrameSource source{TimestampInSeconds(image.timestamp_text, format), image.path, {}};
      if (frame.prepared.has_value()) {
        source.features =
            std::any_cast<std::shared_ptr<const ocg::ExtractedFeatures>>(frame.prepared);
      }
      slam.Track(
          frame.image, image.timestamp,
          detection_folder ? detection_folder->ForFrame(image.timestamp_text) : no_detections,
          source);
      progress.Update(i + 1, [&slam] { return DescribeStatus(slam.Status()); });
      status_lines.Update(i + 1, frames, slam);
    };
    // From the first frame on, a signal stops the run cleanly (RunStop): no frame after
    // the one in hand, then everything is written as at the end.
    StopOnSignals();
    if (live) {
      images.WaitForNext();  // the camera starts once the system has its first image
      std::size_t images_taken = 0;
      while (!slam.StopRequested()) {
        const std::optional<std::size_t> due = live->Next();
        if (!due) break;
        // Images the live camera replaced before tracking was ready are lost (and were
        // not decoded, unless read ahead before the camera replaced them).
        for (; images_taken < *due; ++images_taken) images.Next();
        track(*due);
        ++images_taken;
      }
    } else {
      for (std::size_t i = 0; i < frames && !slam.StopRequested(); ++i) track(i);
    }
    progress.Finish();
    if (slam.StopRequested()) {
      std::cout << "stopped by a signal after " << slam.FramesGiven() << " of " << frames
                << " frames: finishing the map, then writing every output\n";
    }
    if (live) {
      std::cout << "real time: " << live->Dropped().size() << " of " << frames
                << " frames dropped (a live camera had replaced them before tracking was "
                   "ready)\n";
    }
    slam.Shutdown();
    // A map file that cannot be written (the disk filled during the run) loses none of the
    // run's files: they are written all the same, then the error is reported.
    std::optional<std::string> save_error;
    if (!save_map.empty()) {
      try {
        slam.SaveMap(save_map);
      } catch (const std::exception& error) {
        save_error = error.what();
      }
    }
    const nlohmann::json report =
        slam.Save(output, {sequence_path, settings_path, detections,
                           detection_folder ? detection_folder->FilesMatched() : 0,
                           live ? live->Report() : nlohmann::json()});
    if (save_error)
      throw ocg::FileError("--save-map: " + *save_error + " (the run's files are in " + output +
                           ")");
    if (report.contains("objects")) {
      const nlohmann::json& section = report["objects"];
      std::cout << "objects: " << section["objects_created"] << " created, "
                << section["objects_live"] << " live at the end, " << section["keyframes"]
                << " OCG keyframes (mode " << settings.ocg.mode << ")\n";
    }
    if (modes.size() > 1)
      std::cout << "the same SLAM run's objects in the other modes: " << base_output << "/{"
                << run_modes << "}\n";
    std::cout << "tracked " << report["frames_tracked"] << " of " << frames << " frames (first at "
              << report["first_tracked_frame"] << "), lost " << report["frames_lost"]
              << ", relocalized " << report["relocalizations"] << ", resets "
              << report["map_resets"] << ", loops closed " << report["loop_closing"]["loops"].size()
              << "; " << report["keyframes"] << " keyframes, " << report["map_points"]
              << " points; tracking median "
              << report["timing"]["tracking_per_frame"]["median_ms"].get<double>() << " ms/frame\n"
              << "wrote " << output
              << "/KeyFrameTrajectory.txt, CameraTrajectory.txt, map_points.ply, run.json"
              << (report.contains("objects")
                      ? ", objects.json, changes.json, ocg.json, ocg_observations.jsonl"
                      : "")
              << "\n";
    if (report["session"].contains("message")) {
      spdlog::warn("{}", report["session"]["message"].get<std::string>());
    } else if (!load_map.empty()) {
      std::cout << "session " << slam.Session() << ": relocalized in " << load_map << " after "
                << report["session"]["frames_until_relocalized"] << " frame(s)\n";
    }
    if (!save_map.empty()) std::cout << "wrote the map file " << save_map << "\n";
    if (report["initialization"].contains("message"))
      spdlog::warn("{}", report["initialization"]["message"].get<std::string>());
    if (stop_signal != 0)
      std::cout << "the run was stopped by a signal: run.json says interrupted\n";
  });
  // A stopped run wrote everything, but did not see all its frames: scripts must know.
  return code == 0 && stop_signal != 0 ? 128 + stop_signal : code;
}
