#include "ocg/app/object_slam.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "object_layer.h"
#include "ocg/core/cpu_time.h"
#include "ocg/core/file_io.h"
#include "ocg/core/map_file.h"
#include "ocg/core/settings_file.h"
#include "ocg/core/statistics.h"
#include "ocg/features/vocabulary.h"
#include "ocg/io/point_cloud.h"
#include "ocg/slam/initialization_report.h"
#include "ocg/slam/system.h"
#include "run_progress.h"
#include "run_snapshots.h"
#include "session_file.h"

namespace ocg {

namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

nlohmann::json LoopClosingSection(const Settings& settings, const LoopClosingStats& stats) {
  nlohmann::json loops = nlohmann::json::array();
  for (const LoopEvent& loop : stats.loops) {
    loops.push_back({{"keyframe", loop.keyframe},
                     {"matched_keyframe", loop.matched},
                     {"timestamp", loop.timestamp},
                     {"sim3_inliers", loop.sim3_inliers},
                     {"loop_matches", loop.loop_matches},
                     {"scale", loop.scale},
                     {"correction", loop.correction},
                     {"points_fused", loop.points_fused},
                     {"seconds", loop.seconds},
                     {"map_lock_held_seconds", loop.map_lock_held_seconds},
                     {"map_lock_longest_hold_seconds", loop.map_lock_longest_hold_seconds}});
  }
  return {{"enabled", settings.loop_closing.enabled},
          {"candidates_checked", stats.candidates_checked},
          {"loops", loops},
          {"global_adjustments", stats.global_adjustments},
          {"global_adjustment_seconds", stats.global_adjustment_seconds},
          {"followed_global_adjustment", stats.followed_global_adjustment}};
}

// Runs one part of reading a map file whose envelope was sound: what fails now is a file
// written by a build with the same format version but another layout (or a bug).
template <class Read>
auto ReadMapPart(const std::string& path, const char* part, Read read) {
  try {
    return read();
  } catch (const MapFileError&) {
    throw;
  } catch (const std::exception& error) {
    throw MapFileError("map file '" + path + "': cannot read its " + part + " (" + error.what() +
                       "): the file is damaged or was written by an incompatible build");
  }
}

}  // namespace

class ObjectSlam::Impl {
 public:
  Impl(const Settings& settings, Vocabulary vocabulary, const ObjectSlamOptions& options)
      : settings_(settings),
        vocabulary_(std::move(vocabulary)),
        config_(MakeSystemConfig(settings_)),
        system_(config_, vocabulary_),
        objects_(settings_, options.map_objects, options.snapshots.Enabled()),
        snapshots_(settings_, options.snapshots, options.snapshot_folder, options.groundtruth),
        stop_(options.stop) {
    for (const auto& [mode, folder] : options.also_modes) {
      auto settings_of_mode = std::make_unique<Settings>(settings_);
      settings_of_mode->ocg.mode = mode;
      also_.push_back({std::move(settings_of_mode), nullptr, folder});
      also_.back().objects =
          std::make_unique<app_detail::ObjectLayer>(*also_.back().settings, true, false);
    }
    // The object layers are the journal's readers: the map need not tell them of moves
    // below their tolerance. They read at the same keyframes (in sequential mode, the same
    // map): another mode's layer sees what a run of its own would.
    if (options.map_objects || !also_.empty())
      system_.SetMapJournalPointTolerance(settings_.objects.follow_tolerance);
  }

  std::optional<SE3> Track(const cv::Mat& image, double timestamp,
                           const std::vector<Detection>& detections, const FrameSource& source) {
    if (!started_) {
      started_ = true;
      start_ = Clock::now();
    }
    cv::Mat gray = image;
    if (image.type() == CV_8UC3) cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
    const TrackingResult result =
        system_.TrackImage(gray, timestamp, source.timestamp_text, source.features.get());
    // Read in colour only if a layer asks (an OCG keyframe with detections), once for all.
    app_detail::FrameColourImage colour(source.image_path, image);
    objects_.AddFrame(system_, result, frames_, timestamp, detections, colour);
    if (result.T_cw && !first_tracked_) first_tracked_ = frames_;
    for (AlsoMode& also : also_)
      also.objects->AddFrame(system_, result, frames_, timestamp, detections, colour);
    snapshots_.AfterFrame(system_, objects_, result, image, source.image_path);
    ++frames_;
    pose_ = result.T_cw;
    last_timestamp_ = timestamp;
    last_frame_ = {result.state, result.T_cw, result.new_keyframe, result.relocalized,
                   result.inliers};
    const double seconds = SecondsSince(start_);
    // Between frames: what the run freed goes back to the system (app_detail::ReleaseFreeHeap).
    heap_release_.MaybeRelease(seconds);
    if (progress_.Due(seconds)) progress_.Add(Status());
    return result.T_cw;
  }

  void Shutdown() {
    interrupted_ = stop_ != nullptr && stop_->Requested();
    system_.Shutdown();
    objects_.Finish(system_);
    for (AlsoMode& also : also_) also.objects->Finish(system_);
    wall_seconds_ = started_ ? SecondsSince(start_) : 0.0;
    if (started_) progress_.Add(Status());
  }

  RunStatus Status() const {
    RunStatus status;
    status.seconds = started_ ? SecondsSince(start_) : 0.0;
    status.frames = static_cast<std::size_t>(frames_);
    status.keyframes = system_.KeyFrameCount();
    status.map_points = system_.MapPointCount();
    status.objects = objects_.LiveObjectCount();
    status.resident_bytes = app_detail::ResidentMemoryBytes();
    status.heap_bytes = app_detail::HeapInUseBytes();
    return status;
  }

  nlohmann::json Save(const std::string& folder, const RunDescription& description,
                      const std::string& vocabulary_file) {
    // SLAM's part is the same in every folder: taken from the map once.
    const std::vector<StampedPose> keyframes = system_.KeyFrameTrajectory();
    const std::vector<StampedPose> cameras = system_.CameraTrajectory();
    const std::vector<Eigen::Vector3d> points = system_.MapPointPositions();
    const nlohmann::json slam_report = Report(description, vocabulary_file);
    // One folder's files but run.json, whose content it returns.
    const auto write_folder = [&](const std::string& into, app_detail::ObjectLayer& layer) {
      WriteTumTrajectory(into + "/KeyFrameTrajectory.txt", keyframes);
      WriteTumTrajectory(into + "/CameraTrajectory.txt", cameras);
      // Several maps: each one's frames in a file of its own (run.json's "maps").
      const std::vector<MapSummary> maps = system_.Maps();
      for (std::size_t m = 0; maps.size() > 1 && m < maps.size(); ++m) {
        const std::string name = "/CameraTrajectory_map" + std::to_string(maps[m].index) + ".txt";
        WriteTumTrajectory(into + name, system_.CameraTrajectory(maps[m].index));
      }
      WritePlyPoints(into + "/map_points.ply", points);
      nlohmann::json report = slam_report;
      if (layer.Enabled()) {
        nlohmann::json section = layer.Write(into);
        section["detections"] = description.detections;
        section["detection_files_matched"] = description.detection_files_matched;
        report["objects"] = std::move(section);
      }
      return report;
    };
    nlohmann::json report = write_folder(folder, objects_);
    report["snapshots"] = snapshots_.Finish(system_, objects_);
    WriteFileAtomically(folder + "/run.json", report.dump(2) + "\n");
    for (AlsoMode& also : also_) {
      WriteFileAtomically(also.folder + "/run.json",
                          write_folder(also.folder, *also.objects).dump(2) + "\n");
    }
    return report;
  }

  // The rest of a map file's payload after its session record: the SLAM map, then the
  // object layer's state when it holds one.
  void ContinueMap(std::istream& in, const app_detail::SessionRecord& record,
                   const std::string& path, std::uint32_t file_version) {
    ReadMapPart(path, "SLAM map", [&] {
      system_.LoadMap(in, record.frames,
                      file_version >= 5 ? MapFileFormat::kAtlas : MapFileFormat::kSingleMap);
      return 0;
    });
    session_ = record.sessions;
    frame_offset_ = record.frames;
    loaded_map_ = path;
    loaded_keyframes_ = system_.AtlasKeyFrameCount();
    app_detail::CheckNotEmpty(loaded_keyframes_, path);  // files before version 4
    if (record.has_objects && objects_.Enabled()) {
      ReadMapPart(path, "object map", [&] {
        objects_.LoadState(in, session_, frame_offset_, file_version);
        return 0;
      });
    } else {
      objects_.StartSession(session_, frame_offset_);
      if (record.has_objects) {
        spdlog::warn(
            "map file '{}' holds objects, but this run maps none (no detections): a "
            "map saved from it will hold none",
            path);
      }
    }
  }

  void SaveMap(const std::string& path, const std::string& vocabulary_file) {
    // A map without a keyframe holds no place a later session could relocalize in.
    if (system_.AtlasKeyFrameCount() == 0) {
      throw MapFileError("not writing the map file '" + path +
                         "': the map is empty (no keyframe: the run never initialized, see "
                         "run.json's initialization)");
    }
    app_detail::SessionRecord record;
    record.settings_source = settings_.source;
    try {
      record.settings_text = ReadTextFile(settings_.source);
    } catch (const FileError&) {
      record.settings_text.clear();  // settings made in code (Python), not read from a file
    }
    record.camera = settings_.camera.model;
    record.vocabulary_words = vocabulary_.WordCount();
    record.vocabulary_file = vocabulary_file;
    record.orb = settings_.orb;
    record.vocabulary_fingerprint = app_detail::VocabularyFingerprint(vocabulary_);
    record.keyframes = system_.AtlasKeyFrameCount();
    record.sessions = session_ + 1;
    record.frames = frame_offset_ + frames_;
    record.has_objects = objects_.Enabled();
    std::ostringstream out;
    app_detail::SaveSessionRecord(record, out);
    system_.SaveMap(out);
    if (objects_.Enabled()) objects_.SaveState(out);
    WriteMapFile(path, app_detail::kMapFileKind, app_detail::kMapFileVersion, out.str());
    saved_map_ = path;
  }

  // An object layer of options.also_modes: its settings (the layer keeps a reference).
  struct AlsoMode {
    std::unique_ptr<Settings> settings;
    std::unique_ptr<app_detail::ObjectLayer> objects;
    std::string folder;
  };

  const Settings settings_;
  Vocabulary vocabulary_;
  SystemConfig config_;
  System system_;
  app_detail::ObjectLayer objects_;
  app_detail::RunSnapshots snapshots_;
  std::vector<AlsoMode> also_;
  std::int64_t frames_ = 0;
  std::optional<std::int64_t> first_tracked_;  // frames before the first with a pose
  int session_ = 0;
  std::int64_t frame_offset_ = 0;  // frames of the earlier sessions
  std::string loaded_map_, saved_map_;
  std::size_t loaded_keyframes_ = 0;
  std::optional<SE3> pose_;
  double last_timestamp_ = 0.0;  // of the last frame given (frames_ > 0)
  FrameReport last_frame_;
  bool started_ = false;
  Clock::time_point start_;
  double wall_seconds_ = 0.0;
  const RunStop* stop_;
  bool interrupted_ = false;  // the stop was requested before Shutdown()
  app_detail::ProgressSeries progress_;
  app_detail::HeapRelease heap_release_;

 private:
  // run.json's "maps": every map of the run (docs/slam.md "Lost tracking and new maps").
  nlohmann::json MapsSection() const {
    nlohmann::json maps = nlohmann::json::array();
    const int main = system_.MainMap();
    for (const MapSummary& map : system_.Maps()) {
      maps.push_back({{"map", map.index},
                      {"main", map.index == main},
                      {"current", map.current},
                      {"frames_tracked", map.frames_tracked},
                      {"first_frame", map.first_frame},
                      {"last_frame", map.last_frame},
                      {"keyframes", map.keyframes},
                      {"map_points", map.map_points},
                      {"merged_into", map.merged_into}});
      if (map.merged_into >= 0) {
        maps.back()["merged_at_frame"] = map.merged_at_frame;
        maps.back()["merge_scale"] = map.merge_scale;
      }
    }
    return maps;
  }

  // run.json's "merges": each merge of a map into another, in the order they happened.
  nlohmann::json MergesSection() const {
    nlohmann::json merges = nlohmann::json::array();
    for (const LoopEvent& merge : system_.Merges()) {
      merges.push_back({{"map", merge.merged_map},
                        {"into", merge.into_map},
                        {"frame", merge.frame},
                        {"keyframe", merge.keyframe},
                        {"matched_keyframe", merge.matched},
                        {"scale", merge.scale},
                        {"sim3_inliers", merge.sim3_inliers},
                        {"matches", merge.loop_matches},
                        {"points_fused", merge.points_fused},
                        {"seconds", merge.seconds}});
    }
    return merges;
  }

  nlohmann::json Report(const RunDescription& description, const std::string& vocabulary_file) {
    int tracked = 0, lost = 0, relocalized = 0, uninitialized = 0;
    int first_tracked = -1;
    for (std::size_t i = 0; i < system_.Frames().size(); ++i) {
      const FrameRecord& record = system_.Frames()[i];
      if (record.state == TrackingState::kOk) {
        ++tracked;
        if (first_tracked < 0) first_tracked = static_cast<int>(i);
      }
      if (record.state == TrackingState::kLost) ++lost;
      if (record.state == TrackingState::kNotInitialized) ++uninitialized;
      if (record.relocalized) ++relocalized;
    }
    const DurationSummary& tracking_seconds = system_.Timings().tracking;
    const DurationSummary& tracking_cpu_seconds = system_.Timings().tracking_cpu;
    const DurationSummary& mapping_seconds = system_.Timings().local_mapping;
    const DurationSummary& lock_wait_seconds = system_.Timings().map_lock_wait;
    const LocalMappingStats mapping = system_.MappingStats();
    nlohmann::json report = {{"sequence", description.sequence},
                             {"settings", description.settings},
                             {"vocabulary", vocabulary_file},
                             {"mode", config_.sequential ? "sequential" : "threaded"},
                             {"frames", static_cast<std::size_t>(frames_)},
                             {"interrupted", interrupted_},
                             {"frames_tracked", tracked},
                             {"frames_lost", lost},
                             {"frames_before_initialization", uninitialized},
                             {"first_tracked_frame", first_tracked},
                             {"relocalizations", relocalized},
                             {"map_resets", system_.Resets()},
                             {"new_maps", system_.NewMaps()},
                             {"maps", MapsSection()},
                             {"maps_merged", system_.Merges().size()},
                             {"merges", MergesSection()},
                             {"keyframes", system_.KeyFrameCount()},
                             {"map_points", system_.MapPointCount()},
                             {"points_created", mapping.points_created},
                             {"points_culled", mapping.points_culled},
                             {"keyframes_culled", mapping.keyframes_culled},
                             {"local_adjustments_dropped", mapping.local_adjustments_dropped},
                             {"wall_seconds", wall_seconds_},
                             {"timing",
                              {{"tracking_per_frame", app_detail::Timing(tracking_seconds)},
                               {"local_mapping_per_keyframe", app_detail::Timing(mapping_seconds)},
                               {"local_ba_per_keyframe", app_detail::Timing(mapping.ba_seconds)}}},
                             {"camera",
                              {{"fx", config_.camera.fx},
                               {"fy", config_.camera.fy},
                               {"cx", config_.camera.cx},
                               {"cy", config_.camera.cy},
                               {"width", config_.camera.width},
                               {"height", config_.camera.height}}},
                             {"orb",
                              {{"features", config_.orb.features},
                               {"scale_factor", config_.orb.scale_factor},
                               {"levels", config_.orb.levels}}},
                             {"seed", settings_.system.seed}};
    if (!description.feed.is_null()) report["feed"] = description.feed;
    if (!description.reader.is_null()) report["reader"] = description.reader;
    // What the map lock costs (threaded mode; docs/slam.md "Threads and determinism").
    nlohmann::json& timing = report["timing"];
    timing["tracking_map_lock_wait_per_frame"] = app_detail::Timing(lock_wait_seconds);
    // CPU times: what the run costs, comparable between runs on a loaded machine. The
    // process total covers every thread (image reader, loop closing, global adjustment
    // included) from the start of the process to the report.
    timing["tracking_cpu_per_frame"] = app_detail::Timing(tracking_cpu_seconds);
    timing["tracking_cpu_per_frame"]["total_s"] = tracking_cpu_seconds.sum();
    timing["process_cpu_s"] = ProcessCpuSeconds();
    timing["local_mapping_thread_per_keyframe"] = app_detail::Timing(mapping.keyframe_seconds);
    timing["local_mapping_map_lock_held_per_keyframe"] =
        app_detail::Timing(mapping.map_lock_held_seconds);
    // CPU time of the local mapping thread: comparable between runs on a loaded machine.
    timing["local_mapping_cpu_per_keyframe"] = app_detail::Timing(mapping.keyframe_cpu_seconds);
    timing["local_mapping_cpu_per_keyframe"]["total_s"] = mapping.keyframe_cpu_seconds.sum();
    timing["local_ba_cpu_per_keyframe"] = app_detail::Timing(mapping.ba_cpu_seconds);
    timing["local_ba_cpu_per_keyframe"]["total_s"] = mapping.ba_cpu_seconds.sum();
    // Threaded local mapping catching up (docs/slam.md "Threads and determinism").
    report["local_adjustments_skipped"] = mapping.local_adjustments_skipped;
    report["local_adjustments_interrupted"] = mapping.local_adjustments_interrupted;
    report["local_mapping_yields_to_tracking"] = mapping.map_lock_yields;
    std::vector<double> ba_iterations(mapping.ba_iterations.begin(), mapping.ba_iterations.end());
    report["local_ba_iterations"] = {
        {"median", Median(ba_iterations)},
        {"total", std::accumulate(ba_iterations.begin(), ba_iterations.end(), 0.0)}};
    // A run without a map writes empty trajectories: say why, there and in run.json.
    const InitializationAttempts& initialization = system_.Initialization();
    report["initialized"] = first_tracked >= 0;
    nlohmann::json failures = nlohmann::json::object();
    for (const auto& [reason, count] : initialization.reasons) failures[reason] = count;
    report["initialization"] = {{"frames_tried", initialization.frames},
                                {"most_frequent_failure", initialization.MostFrequentReason()},
                                {"failures", failures}};
    // A session in a loaded map does not initialize: session.message says why it did not
    // relocalize instead.
    const std::string never_initialized =
        first_tracked < 0 && !system_.MapLoaded() ? NeverInitializedMessage(initialization) : "";
    if (!never_initialized.empty()) report["initialization"]["message"] = never_initialized;
    report["loop_closing"] = LoopClosingSection(settings_, system_.LoopStats());
    report["session"] = SessionSection();
    report["progress"] = progress_.Json();
    return report;
  }

  // run.json's "session": which session of which map this run was; after a loaded map,
  // the frames it took to relocalize in it ("never": it kept trying to the end and made
  // no map of its own).
  nlohmann::json SessionSection() const {
    nlohmann::json section = {
        {"index", session_},
        {"map_loaded", loaded_map_.empty() ? nullptr : nlohmann::json(loaded_map_)},
        {"map_saved", saved_map_.empty() ? nullptr : nlohmann::json(saved_map_)},
        {"frames_before", frame_offset_}};
    if (!loaded_map_.empty()) {
      section["keyframes_loaded"] = loaded_keyframes_;
      section["frames_until_relocalized"] =
          first_tracked_ ? nlohmann::json(*first_tracked_) : nlohmann::json("never");
      if (!first_tracked_) {
        section["message"] = "never relocalized in " + loaded_map_ + " in " +
                             std::to_string(frames_) +
                             " frame(s): no frame showed a place its keyframes hold (the run "
                             "kept trying and made no map of its own)";
      }
    }
    return section;
  }
};

ObjectSlam::ObjectSlam(const Settings& settings, ObjectSlamOptions options) {
  // Checked before the vocabulary is loaded and SLAM started: a bad option fails at once.
  if (!options.also_modes.empty() && (!options.map_objects || !settings.system.sequential)) {
    throw SettingsError(
        "more than one OCG mode in one run needs detections and System.sequential: true "
        "(in threaded mode the object layers would not see the same SLAM states)");
  }
  for (const auto& also : options.also_modes) {
    OcgOptions ocg = settings.ocg;
    ocg.mode = also.first;
    ocg.Check();
  }
  if (!options.also_modes.empty() && !options.load_map.empty()) {
    throw SettingsError(
        "more than one OCG mode in one run cannot continue a map file (--load-map): the map "
        "file holds one object layer");
  }
  // The map file before the vocabulary: a wrong file fails now, not seconds later. It is
  // streamed from the file: only its header is read before it is known to be a map file.
  std::unique_ptr<MapFileReader> map_file;
  std::optional<app_detail::SessionRecord> record;
  const std::string& map_path = options.load_map;
  if (!map_path.empty()) {
    map_file = std::make_unique<MapFileReader>(map_path, app_detail::kMapFileKind,
                                               app_detail::kMapFileVersion,
                                               app_detail::kOldestMapFileVersion);
    record = ReadMapPart(map_path, "session record", [&] {
      return app_detail::LoadSessionRecord(map_file->payload(), map_file->version());
    });
    app_detail::CheckSameCamera(*record, settings, map_path);
    app_detail::CheckSameOrbPyramid(*record, settings, map_path);
    if (map_file->version() >= 4) app_detail::CheckNotEmpty(record->keyframes, map_path);
  }
  VocabularyOptions vocabulary = settings.vocabulary;
  if (!options.vocabulary_path.empty()) vocabulary.path = options.vocabulary_path;
  vocabulary_file_ = vocabulary.Resolve();
  const auto start = Clock::now();
  Vocabulary loaded = Vocabulary::Load(vocabulary_file_);
  vocabulary_seconds_ = SecondsSince(start);
  if (record) app_detail::CheckSameVocabulary(*record, loaded, vocabulary_file_, map_path);
  impl_ = std::make_unique<Impl>(settings, std::move(loaded), options);
  if (record) impl_->ContinueMap(map_file->payload(), *record, map_path, map_file->version());
}

ObjectSlam::~ObjectSlam() {
  try {
    Shutdown();
  } catch (const std::exception&) {
    // A worker's failure was the caller's to see through Shutdown(); a destructor must
    // not throw.
  }
}

std::optional<SE3> ObjectSlam::Track(const cv::Mat& image, double timestamp,
                                     const std::vector<Detection>& detections,
                                     const FrameSource& source) {
  if (shut_down_) {
    throw std::logic_error(
        "ObjectSlam::Track: the system was shut down; make a new ObjectSlam for another "
        "sequence");
  }
  if (image.empty() || image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3)) {
    throw std::invalid_argument(
        "ObjectSlam::Track: the image must be 8-bit grey (HxW) or BGR (HxWx3), not empty; got " +
        std::to_string(image.rows) + "x" + std::to_string(image.cols) + " with " +
        std::to_string(image.channels()) + " channel(s) of depth code " +
        std::to_string(image.depth()));
  }
  // The rule the frame lists' readers apply (io/time_order.h), for every caller: a time
  // that is not a number, or not later than the last frame's, gives the trajectories a
  // step back in time and one time two poses.
  if (!std::isfinite(timestamp)) {
    throw std::invalid_argument(
        "ObjectSlam::Track: the timestamp must be a finite number of "
        "seconds, got " +
        std::to_string(timestamp));
  }
  if (impl_->frames_ > 0 && !(timestamp > impl_->last_timestamp_)) {
    // Every digit (%.17g): TUM times (1.3e9 s) differ from the tenth digit on.
    char message[200];
    std::snprintf(message, sizeof(message),
                  "ObjectSlam::Track: frame times must increase strictly: %.17g is not later "
                  "than the last frame's %.17g",
                  timestamp, impl_->last_timestamp_);
    throw std::invalid_argument(message);
  }
  return impl_->Track(image, timestamp, detections, source);
}

FrameReport ObjectSlam::LastFrame() const { return impl_->last_frame_; }

std::function<ExtractedFeatures(const cv::Mat&)> ObjectSlam::FeatureExtractor() const {
  return impl_->system_.MakeFeatureExtractor();
}

void ObjectSlam::Shutdown() {
  if (shut_down_) return;
  shut_down_ = true;
  impl_->Shutdown();
}

bool ObjectSlam::StopRequested() const {
  return impl_->stop_ != nullptr && impl_->stop_->Requested();
}
RunStatus ObjectSlam::Status() const { return impl_->Status(); }
std::optional<SE3> ObjectSlam::Pose() const { return impl_->pose_; }
std::string ObjectSlam::Objects() const { return impl_->objects_.Objects(); }
std::string ObjectSlam::Changes() const { return impl_->objects_.Changes(); }
std::vector<StampedPose> ObjectSlam::KeyFrameTrajectory() const {
  return impl_->system_.KeyFrameTrajectory();
}
std::vector<StampedPose> ObjectSlam::CameraTrajectory() const {
  return impl_->system_.CameraTrajectory();
}
std::size_t ObjectSlam::FramesGiven() const { return static_cast<std::size_t>(impl_->frames_); }
std::size_t ObjectSlam::VocabularyWords() const { return impl_->vocabulary_.WordCount(); }
bool ObjectSlam::Sequential() const { return impl_->config_.sequential; }

void ObjectSlam::SaveMap(const std::string& path) {
  if (!shut_down_) {
    throw std::logic_error(
        "ObjectSlam::SaveMap: call Shutdown() first (the map is still changing)");
  }
  impl_->SaveMap(path, vocabulary_file_);
}

int ObjectSlam::Session() const { return impl_->session_; }

nlohmann::json ObjectSlam::Save(const std::string& folder, const RunDescription& description) {
  if (!shut_down_) {
    throw std::logic_error("ObjectSlam::Save: call Shutdown() first (the map is still changing)");
  }
  return impl_->Save(folder, description, vocabulary_file_);
}

}  // namespace ocg
