// ocg_slam: monocular SLAM on a TUM or EuRoC sequence; writes the keyframe and camera
// trajectories (TUM format) and run.json (docs/slam.md). `ocg_slam objects` builds the
// object map from a given trajectory and detections alone (docs/objects.md).

#include <spdlog/spdlog.h>
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <thread>
#include <utility>

#include "cli_common.h"
#include "ocg/app/settings.h"
#include "ocg/core/file_io.h"
#include "ocg/core/settings_file.h"
#include "ocg/core/statistics.h"
#include "ocg/eval/trajectory_error.h"
#include "ocg/io/detections.h"
#include "ocg/io/point_cloud.h"
#include "ocg/io/sequence.h"
#include "ocg/io/trajectory.h"
#include "ocg/objects/map_cues.h"
#include "ocg/objects/object_mapper.h"
#include "ocg/slam/initialization_report.h"
#include "ocg/slam/system.h"
#include "ocg/viewer/frame_view.h"
#include "ocg/viewer/snapshots.h"

namespace {

nlohmann::json Timing(const std::vector<double>& seconds) {
  return {{"count", seconds.size()},
          {"median_ms", 1000.0 * ocg::Quantile(seconds, 0.5)},
          {"p95_ms", 1000.0 * ocg::Quantile(seconds, 0.95)},
          {"max_ms",
           seconds.empty() ? 0.0 : 1000.0 * *std::max_element(seconds.begin(), seconds.end())}};
}

// EuRoC names images by nanoseconds; trajectories are written in seconds (TUM format),
// with every digit kept: "1403715273262142976" -> "1403715273.262142976".
std::string TimestampInSeconds(const std::string& text, const std::string& format) {
  if (format != "euroc" || text.size() <= 9 ||
      text.find_first_not_of("0123456789") != std::string::npos) {
    return text;
  }
  return text.substr(0, text.size() - 9) + "." + text.substr(text.size() - 9);
}

// Writes the object map's files (objects.json, changes.json, ocg.json,
// ocg_observations.jsonl) into folder; returns the counts run.json reports of it.
nlohmann::json WriteObjectMap(const ocg::ObjectMapper& mapper, const std::string& folder) {
  ocg::WriteFileAtomically(folder + "/objects.json", mapper.ObjectsJson());
  ocg::WriteFileAtomically(folder + "/changes.json", mapper.ChangesJson());
  ocg::WriteFileAtomically(folder + "/ocg.json", mapper.GraphJson());
  ocg::WriteFileAtomically(folder + "/ocg_observations.jsonl", mapper.ObservationsJsonl());
  const ocg::ObjectLayerStats stats = mapper.Stats();
  return {{"detections_used", stats.detections_used},
          {"detections_matched", stats.detections_matched},
          {"objects_created", stats.objects_created},
          {"objects_live", mapper.LiveObjectCount()}};
}

struct ObjectsCommand {
  std::string trajectory, detections, settings, frames, output, mode;
  bool lenient = false;
};

// The frames to process: the image list's timestamps, or the detection files' names.
std::vector<std::pair<std::string, double>> FrameTimestamps(const ObjectsCommand& command) {
  std::vector<std::pair<std::string, double>> frames;
  if (!command.frames.empty()) {
    for (const ocg::TimedImage& image : ocg::ReadTumImageList(command.frames, ".")) {
      frames.emplace_back(image.timestamp_text, image.timestamp);
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
    frames.emplace_back(stem, timestamp);
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

  ocg::ObjectMapper mapper(settings.objects, settings.ocg, settings.camera.model, true);
  mapper.RecordObservations();
  ocg::ProgressLine progress("frames", frames.size());
  const auto start = std::chrono::steady_clock::now();
  std::int64_t used = 0, without_pose = 0, keyframes = 0;
  std::vector<double> frame_seconds;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const auto& [text, timestamp] = frames[i];
    const std::optional<ocg::SE3>& T_cw = poses[i];
    if (!T_cw) {
      ++without_pose;
      continue;
    }
    const auto frame_start = std::chrono::steady_clock::now();
    mapper.AddFrame(used, timestamp, *T_cw, detections.ForFrame(text));
    if (used % settings.objects.keyframe_interval == 0)
      mapper.AddKeyframe(keyframes++, timestamp, *T_cw);
    frame_seconds.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - frame_start).count());
    ++used;
    progress.Update(i + 1);
  }
  progress.Finish();
  mapper.Finish();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const ocg::ObjectLayerStats stats = mapper.Stats();
  nlohmann::json report = {{"command", "objects"},
                           {"trajectory", command.trajectory},
                           {"detections", command.detections},
                           {"detection_files_matched", detections.FilesMatched()},
                           {"settings", command.settings},
                           {"ocg_mode", settings.ocg.mode},
                           {"frames", frames.size()},
                           {"frames_used", used},
                           {"frames_without_pose", without_pose},
                           {"keyframes", keyframes},
                           {"wall_seconds", seconds},
                           {"timing", {{"objects_per_frame", Timing(frame_seconds)}}}};
  report.update(WriteObjectMap(mapper, command.output));
  ocg::WriteFileAtomically(command.output + "/run.json", report.dump(2) + "\n");
  std::cout << used << " frames (" << without_pose << " without a pose skipped), " << keyframes
            << " keyframes; " << stats.objects_created << " objects created, "
            << mapper.LiveObjectCount() << " live at the end; " << seconds << " s\n"
            << "wrote " << command.output
            << "/objects.json, changes.json, ocg.json, ocg_observations.jsonl, run.json\n";
}

// The object layer inside a SLAM run: every tracked frame's detections with its pose and
// tracked map points; at each SLAM keyframe (after its bundle adjustment) the objects
// follow the optimized poses and the supporting plane. The OCG gets every
// Objects.keyframe_interval-th tracked frame, as in pose-given mode, not SLAM's keyframes:
// it counts doubt in keyframes, and SLAM's keyframe rate follows the camera's motion
// (every 3 frames on the 10 Hz smoke preset, every 9 at 30 Hz), which would make one
// setting remove objects three times sooner on one sequence than on another.
class ObjectLayer {
 public:
  // keep_first_removal: keep the objects as they were just before the OCG's first removal
  // (for the before/after snapshots; a copy of the object list at every OCG keyframe
  // until then).
  // folder: the run's detections, read before the first frame (none: no object layer).
  ObjectLayer(const ocg::Settings& settings, std::string detections,
              std::optional<ocg::EaoDetectionFolder> folder, bool sequential,
              bool keep_first_removal)
      : settings_(settings),
        detections_(std::move(detections)),
        folder_(std::move(folder)),
        sequential_(sequential),
        keep_first_removal_(keep_first_removal) {
    if (Enabled()) Start();
  }
  bool Enabled() const { return folder_.has_value(); }

  void AddFrame(const ocg::System& system, const ocg::TrackingResult& result, std::int64_t frame,
                const ocg::TimedImage& image) {
    if (!Enabled()) return;
    const auto start = std::chrono::steady_clock::now();
    if (result.reset) {
      // The SLAM map the objects were built in is gone; so are they.
      spdlog::warn("frame {}: the SLAM map was reset: the object map starts over", frame);
      ++resets_;
      Start();
    }
    if (!result.T_cw) return;
    std::vector<ocg::PointObservation> points;
    points.reserve(result.points.size());
    for (const ocg::TrackedPoint& point : result.points)
      points.push_back({point.id, point.pixel, point.position});
    last_association_ = mapper_->AddFrame(frame, image.timestamp, *result.T_cw,
                                          folder_->ForFrame(image.timestamp_text), &points);
    if (result.new_keyframe) Follow(system);
    if (tracked_frames_++ % settings_.objects.keyframe_interval == 0) {
      // The map as it was just before the OCG's first removal, for the before/after
      // snapshots (exact in sequential mode; a keyframe late when the OCG has a thread).
      std::vector<ocg::ObjectView> before;
      if (keep_first_removal_ && !removal_seen_) before = mapper_->Views();
      const std::int64_t removed = mapper_->Stats().objects_removed;
      mapper_->AddKeyframe(keyframes_++, image.timestamp, *result.T_cw);
      if (!removal_seen_ && mapper_->Stats().objects_removed > removed) {
        removal_seen_ = true;
        if (keep_first_removal_) first_removal_ = std::move(before);
      }
    }
    seconds_.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }

  // The objects for the viewer (none without detections) and their up direction.
  std::vector<ocg::ObjectView> Views() const {
    return Enabled() ? mapper_->Views() : std::vector<ocg::ObjectView>{};
  }
  std::optional<Eigen::Vector3d> Up() const {
    if (!Enabled()) return std::nullopt;
    return mapper_->Up();
  }
  // The detections of the last frame given, with the objects they were associated to.
  std::vector<ocg::FrameDetection> LastFrameDetections() const {
    std::vector<ocg::FrameDetection> detections;
    for (const ocg::ObjectDetection& detection : last_association_.detections)
      detections.push_back({detection.box, detection.class_id, detection.confidence, 0});
    for (const auto& [index, id] : last_association_.matched) {
      if (index >= 0) detections[static_cast<std::size_t>(index)].object_id = id;
    }
    return detections;
  }
  // Once: the objects just before the OCG's first removal, if there was one.
  std::optional<std::vector<ocg::ObjectView>> TakeFirstRemoval() {
    return std::exchange(first_removal_, std::nullopt);
  }

  // After SLAM has finished: the objects take the final poses, the OCG its last keyframe.
  void Finish(const ocg::System& system) {
    if (!Enabled()) return;
    Follow(system);
    mapper_->Finish();
  }

  // Writes the object outputs; returns run.json's "objects" section.
  nlohmann::json Write(const std::string& output) const {
    nlohmann::json section = WriteObjectMap(*mapper_, output);
    const ocg::ObjectLayerStats stats = mapper_->Stats();
    std::cout << "objects: " << stats.objects_created << " created, " << mapper_->LiveObjectCount()
              << " live at the end, " << keyframes_ << " OCG keyframes (mode " << settings_.ocg.mode
              << ")\n";
    section.update({{"detections", detections_},
                    {"detection_files_matched", folder_->FilesMatched()},
                    {"ocg_mode", settings_.ocg.mode},
                    {"keyframes", keyframes_},
                    {"object_map_resets", resets_},
                    {"supporting_plane_inliers", stats.plane_inliers},
                    {"up", {stats.up.x(), stats.up.y(), stats.up.z()}},
                    {"timing", {{"objects_per_frame", Timing(seconds_)}}}});
    return section;
  }

 private:
  void Start() {
    mapper_ = std::make_unique<ocg::ObjectMapper>(settings_.objects, settings_.ocg,
                                                  settings_.camera.model, sequential_);
    mapper_->RecordObservations();
    keyframes_ = 0;
    tracked_frames_ = 0;
    last_association_ = {};
  }

  void Follow(const ocg::System& system) {
    ocg::SlamMapView view;
    view.frame_poses = system.FramePoses();
    view.map_points = system.MapPointPositions(&view.map_point_ids);
    view.camera_rotations = system.KeyFrameRotations();
    mapper_->FollowSlamMap(view, settings_.system.seed + static_cast<std::uint64_t>(keyframes_));
  }

  const ocg::Settings& settings_;
  std::string detections_;
  std::optional<ocg::EaoDetectionFolder> folder_;
  bool sequential_;
  std::unique_ptr<ocg::ObjectMapper> mapper_;
  std::int64_t keyframes_ = 0;
  std::int64_t tracked_frames_ = 0;
  int resets_ = 0;
  ocg::FrameAssociation last_association_;
  std::optional<std::vector<ocg::ObjectView>> first_removal_;
  bool keep_first_removal_;
  bool removal_seen_ = false;
  std::vector<double> seconds_;
};

// The run's PNG snapshots (docs/viewer.md): the map from three viewpoints and the last
// frame at the end, the map and the frame every N SLAM keyframes when asked, and the map
// just before the OCG's first removal (with the final map, a before/after pair).
class RunSnapshots {
 public:
  RunSnapshots(const ocg::Settings& settings, ocg::SnapshotPolicy policy, const std::string& output,
               std::vector<ocg::StampedPose> groundtruth)
      : policy_(policy),
        writer_(output + "/snapshots", settings.viewer),
        camera_(settings.camera.model),
        groundtruth_(std::move(groundtruth)) {
    if (policy_.Enabled()) writer_.RemoveOldSnapshots();
  }

  void AfterFrame(const ocg::System& system, ObjectLayer& objects,
                  const ocg::TrackingResult& result, const ocg::TimedImage& image) {
    if (result.T_cw) {
      last_image_ = image.path;
      last_pose_ = *result.T_cw;
    }
    if (!policy_.Enabled()) return;
    const auto start = std::chrono::steady_clock::now();
    if (const auto before = objects.TakeFirstRemoval()) {
      ocg::MapScene scene = Scene(system, objects, false);
      scene.objects = *before;
      Record(
          writer_.WriteMapViews(scene, "before_first_removal",
                                {ocg::MapViewpoint::kThreeQuarter, ocg::MapViewpoint::kObjects}));
    }
    if (result.new_keyframe && policy_.every_keyframes > 0 &&
        ++keyframes_ % policy_.every_keyframes == 0) {
      char prefix[32];
      std::snprintf(prefix, sizeof prefix, "keyframe_%05d", keyframes_);
      Record(writer_.WriteMapViews(Scene(system, objects, false), prefix,
                                   {ocg::MapViewpoint::kThreeQuarter}));
      WriteFrame(objects, std::string(prefix) + "_frame");
    }
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  // The final snapshots; returns run.json's "snapshots" section.
  nlohmann::json Finish(const ocg::System& system, const ObjectLayer& objects) {
    if (!policy_.Enabled()) return nullptr;
    const auto start = std::chrono::steady_clock::now();
    Record(writer_.WriteMapViews(Scene(system, objects, true), "final",
                                 {ocg::MapViewpoint::kFollow, ocg::MapViewpoint::kTopDown,
                                  ocg::MapViewpoint::kThreeQuarter, ocg::MapViewpoint::kObjects}));
    WriteFrame(objects, "final_frame");
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return {{"folder", writer_.folder()}, {"files", written_}, {"seconds", seconds_}};
  }

 private:
  ocg::MapScene Scene(const ocg::System& system, const ObjectLayer& objects,
                      bool with_groundtruth) const {
    ocg::MapScene scene;
    scene.points = system.MapPointPositions();
    for (const ocg::StampedPose& pose : system.KeyFrameTrajectory())
      scene.keyframes.push_back(pose.T_wc);
    const std::vector<ocg::StampedPose> trajectory = system.CameraTrajectory();
    for (const ocg::StampedPose& pose : trajectory)
      scene.trajectory.push_back(pose.T_wc.translation());
    scene.objects = objects.Views();
    if (!last_image_.empty()) scene.current_camera = last_pose_.Inverse();
    scene.up = objects.Up().value_or(ocg::CameraUpPrior(system.KeyFrameRotations()));
    if (with_groundtruth && !groundtruth_.empty()) {
      try {
        // The ground truth in the map's frame: the ATE alignment, inverted.
        const ocg::Sim3 map_from_truth =
            ocg::ComputeAte(groundtruth_, trajectory, {}).reference_from_estimate.Inverse();
        for (const ocg::StampedPose& pose : groundtruth_)
          scene.groundtruth.push_back(map_from_truth * pose.T_wc.translation());
      } catch (const std::invalid_argument& error) {
        spdlog::warn("snapshots: no ground truth drawn: {}", error.what());
      }
    }
    return scene;
  }

  void WriteFrame(const ObjectLayer& objects, const std::string& name) {
    if (last_image_.empty()) return;
    const cv::Mat image = cv::imread(last_image_, cv::IMREAD_COLOR);
    if (image.empty()) throw ocg::FileError("cannot read image '" + last_image_ + "'");
    const Eigen::Vector3d up = objects.Up().value_or(Eigen::Vector3d::UnitZ());
    written_.push_back(
        writer_.WriteImage(ocg::RenderFrameView(image, objects.LastFrameDetections(),
                                                objects.Views(), last_pose_, camera_, up),
                           name));
  }

  void Record(const std::vector<std::string>& paths) {
    written_.insert(written_.end(), paths.begin(), paths.end());
  }

  ocg::SnapshotPolicy policy_;
  ocg::SnapshotWriter writer_;
  ocg::PinholeCamera camera_;
  std::vector<ocg::StampedPose> groundtruth_;
  std::string last_image_;
  ocg::SE3 last_pose_;
  int keyframes_ = 0;
  double seconds_ = 0.0;
  std::vector<std::string> written_;
};

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
  run->add_option("--settings", settings_path, "settings file (ours or ORB-SLAM2's)")
      ->required()
      ->check(CLI::ExistingFile);
  run->add_option("--sequence", sequence_path, "sequence folder")
      ->required()
      ->check(CLI::ExistingDirectory);
  run->add_option("--format", format, "tum or euroc")
      ->capture_default_str()
      ->check(CLI::IsMember({"tum", "euroc"}));
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
  run->add_option("--mode", run_mode,
                  "OCG.mode override for the object layer (off, visibility, paper, ...)");
  run->add_flag("--realtime", realtime,
                "feed images at the pace of their timestamps (never drops frames)");

  auto* objects = app.add_subcommand(
      "objects",
      "pose-given mode: build and maintain the object map from a trajectory and detections, no "
      "images (writes objects.json, changes.json, ocg.json, run.json)");
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
  objects->add_flag("--lenient", objects_command.lenient,
                    "skip malformed detection lines with a warning instead of failing");

  return ocg::tools::RunTool(app, argc, argv, log_level, [&] {
    if (objects->parsed()) {
      RunObjects(objects_command);
      return;
    }
    const ocg::LoadedSettings loaded =
        ocg::LoadSettings(settings_path, ocg::CameraNeed::kIntrinsics);
    ocg::Settings settings = loaded.settings;
    if (!run_mode.empty()) {
      settings.ocg.mode = run_mode;
      settings.ocg.Check();
    }
    // Every input is read and checked before the first frame (the detections of every
    // frame to process included), and the output folder is tried for writing, so no bad
    // input ends a run after the whole sequence.
    const ocg::ImageSequence sequence = format == "tum" ? ocg::ReadTumSequence(sequence_path)
                                                        : ocg::ReadEurocSequence(sequence_path);
    std::size_t frames = sequence.images.size();
    if (max_frames > 0) frames = std::min(frames, static_cast<std::size_t>(max_frames));
    if (frames == 0) {
      throw std::invalid_argument("no frames to process: '" + sequence.list +
                                  "' lists no image (only comments or blank lines)");
    }
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
    ocg::VocabularyOptions vocabulary_options = settings.vocabulary;
    if (!vocabulary_path.empty()) vocabulary_options.path = vocabulary_path;
    const std::string vocabulary_file = vocabulary_options.Resolve();
    const auto load_start = std::chrono::steady_clock::now();
    const ocg::Vocabulary vocabulary = ocg::Vocabulary::Load(vocabulary_file);
    const double load_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - load_start).count();
    const ocg::SystemConfig config = ocg::MakeSystemConfig(settings);
    std::cout << "ocg_slam: " << frames << " frames of " << sequence_path << ", vocabulary "
              << vocabulary_file << " (" << vocabulary.WordCount() << " words, loaded in "
              << load_seconds << " s), " << (config.sequential ? "sequential" : "threaded")
              << " mode\n";
    ocg::SnapshotPolicy snapshot_policy;
    if (!snapshots.empty()) {
      snapshot_policy = ocg::ParseSnapshotPolicy(snapshots);
    } else {
      snapshot_policy.every_keyframes = settings.viewer.every_keyframes;
    }
    ocg::System system(config, vocabulary);
    ObjectLayer objects_layer(settings, detections, std::move(detection_folder), config.sequential,
                              snapshot_policy.Enabled());
    const std::string groundtruth_path = sequence_path + "/groundtruth.txt";
    RunSnapshots run_snapshots(settings, snapshot_policy, output,
                               format == "tum" && std::filesystem::exists(groundtruth_path)
                                   ? ocg::ReadTumTrajectory(groundtruth_path)
                                   : std::vector<ocg::StampedPose>{});
    ocg::ProgressLine progress("frames", frames);
    const auto wall_start = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < frames; ++i) {
      const ocg::TimedImage& image = sequence.images[i];
      if (realtime) {
        const double due = image.timestamp - sequence.images[0].timestamp;
        std::this_thread::sleep_until(wall_start +
                                      std::chrono::duration_cast<std::chrono::nanoseconds>(
                                          std::chrono::duration<double>(due)));
      }
      const cv::Mat gray = cv::imread(image.path, cv::IMREAD_GRAYSCALE);
      if (gray.empty()) throw ocg::FileError("cannot read image '" + image.path + "'");
      const ocg::TrackingResult result = system.TrackImage(
          gray, image.timestamp, TimestampInSeconds(image.timestamp_text, format));
      objects_layer.AddFrame(system, result, static_cast<std::int64_t>(i), image);
      run_snapshots.AfterFrame(system, objects_layer, result, image);
      progress.Update(i + 1);
    }
    progress.Finish();
    system.Shutdown();
    objects_layer.Finish(system);
    const double wall_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

    ocg::WriteTumTrajectory(output + "/KeyFrameTrajectory.txt", system.KeyFrameTrajectory());
    ocg::WriteTumTrajectory(output + "/CameraTrajectory.txt", system.CameraTrajectory());
    ocg::WritePlyPoints(output + "/map_points.ply", system.MapPointPositions());
    int tracked = 0, lost = 0, relocalized = 0, uninitialized = 0;
    std::vector<double> tracking_seconds, mapping_seconds;
    int first_tracked = -1;
    for (std::size_t i = 0; i < system.Frames().size(); ++i) {
      const ocg::FrameRecord& record = system.Frames()[i];
      if (record.state == ocg::TrackingState::kOk) {
        ++tracked;
        if (first_tracked < 0) first_tracked = static_cast<int>(i);
      }
      if (record.state == ocg::TrackingState::kLost) ++lost;
      if (record.state == ocg::TrackingState::kNotInitialized) ++uninitialized;
      if (record.relocalized) ++relocalized;
      tracking_seconds.push_back(record.tracking_seconds);
      if (record.local_mapping_seconds > 0.0)
        mapping_seconds.push_back(record.local_mapping_seconds);
    }
    const ocg::LocalMappingStats mapping = system.MappingStats();
    nlohmann::json report = {{"sequence", sequence_path},
                             {"settings", settings_path},
                             {"vocabulary", vocabulary_file},
                             {"mode", config.sequential ? "sequential" : "threaded"},
                             {"frames", frames},
                             {"frames_tracked", tracked},
                             {"frames_lost", lost},
                             {"frames_before_initialization", uninitialized},
                             {"first_tracked_frame", first_tracked},
                             {"relocalizations", relocalized},
                             {"map_resets", system.Resets()},
                             {"keyframes", system.KeyFrameCount()},
                             {"map_points", system.MapPointCount()},
                             {"points_created", mapping.points_created},
                             {"points_culled", mapping.points_culled},
                             {"keyframes_culled", mapping.keyframes_culled},
                             {"wall_seconds", wall_seconds},
                             {"timing",
                              {{"tracking_per_frame", Timing(tracking_seconds)},
                               {"local_mapping_per_keyframe", Timing(mapping_seconds)},
                               {"local_ba_per_keyframe", Timing(mapping.ba_seconds)}}},
                             {"camera",
                              {{"fx", config.camera.fx},
                               {"fy", config.camera.fy},
                               {"cx", config.camera.cx},
                               {"cy", config.camera.cy},
                               {"width", config.camera.width},
                               {"height", config.camera.height}}},
                             {"orb",
                              {{"features", config.orb.features},
                               {"scale_factor", config.orb.scale_factor},
                               {"levels", config.orb.levels}}},
                             {"seed", settings.system.seed}};
    nlohmann::json loops = nlohmann::json::array();
    for (const ocg::LoopEvent& loop : system.LoopStats().loops) {
      loops.push_back({{"keyframe", loop.keyframe},
                       {"matched_keyframe", loop.matched},
                       {"timestamp", loop.timestamp},
                       {"sim3_inliers", loop.sim3_inliers},
                       {"loop_matches", loop.loop_matches},
                       {"scale", loop.scale},
                       {"correction", loop.correction},
                       {"points_fused", loop.points_fused},
                       {"seconds", loop.seconds}});
    }
    // A run without a map writes empty trajectories: say why, there and in run.json.
    const ocg::InitializationAttempts& initialization = system.Initialization();
    report["initialized"] = first_tracked >= 0;
    nlohmann::json failures = nlohmann::json::object();
    for (const auto& [reason, count] : initialization.reasons) failures[reason] = count;
    report["initialization"] = {{"frames_tried", initialization.frames},
                                {"most_frequent_failure", initialization.MostFrequentReason()},
                                {"failures", failures}};
    const std::string never_initialized =
        first_tracked < 0 ? ocg::NeverInitializedMessage(initialization) : "";
    if (!never_initialized.empty()) report["initialization"]["message"] = never_initialized;
    report["loop_closing"] = {
        {"enabled", settings.loop_closing.enabled},
        {"candidates_checked", system.LoopStats().candidates_checked},
        {"loops", loops},
        {"global_adjustments", system.LoopStats().global_adjustments},
        {"global_adjustment_seconds", system.LoopStats().global_adjustment_seconds},
        {"followed_global_adjustment", system.LoopStats().followed_global_adjustment}};
    if (objects_layer.Enabled()) report["objects"] = objects_layer.Write(output);
    report["snapshots"] = run_snapshots.Finish(system, objects_layer);
    ocg::WriteFileAtomically(output + "/run.json", report.dump(2) + "\n");
    std::cout << "tracked " << tracked << " of " << frames << " frames (first at " << first_tracked
              << "), lost " << lost << ", relocalized " << relocalized << ", resets "
              << system.Resets() << ", loops closed " << system.LoopStats().loops.size() << "; "
              << system.KeyFrameCount() << " keyframes, " << system.MapPointCount()
              << " points; tracking median " << 1000.0 * ocg::Quantile(tracking_seconds, 0.5)
              << " ms/frame\n"
              << "wrote " << output
              << "/KeyFrameTrajectory.txt, CameraTrajectory.txt, map_points.ply, run.json"
              << (objects_layer.Enabled()
                      ? ", objects.json, changes.json, ocg.json, ocg_observations.jsonl"
                      : "")
              << "\n";
    if (!never_initialized.empty()) spdlog::warn("{}", never_initialized);
  });
}
