#include "object_layer.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <utility>

#include "object_map_file.h"
#include "ocg/core/cpu_time.h"
#include "ocg/core/file_io.h"
#include "ocg/core/statistics.h"

namespace ocg::app_detail {
namespace {

// The keyframes in the SLAM map (every session's), as the box appearance reads them.
KeyframeFeatureMap KeyframeFeaturesOf(const System& system) {
  KeyframeFeatureMap keyframes;
  for (const KeyFramePtr& keyframe : system.KeyFrames()) {
    KeyframeFeatures& features = keyframes[static_cast<std::int64_t>(keyframe->frame_id)];
    features.frame = static_cast<std::int64_t>(keyframe->frame_id);
    features.T_cw = keyframe->T_cw;
    features.descriptors = keyframe->features.descriptors;
    for (std::size_t i = 0; i < keyframe->features.size(); ++i) {
      const cv::Point2f& pixel = keyframe->features.keypoints[i].pt;
      features.pixels.emplace_back(pixel.x, pixel.y);
      const MapPointPtr& point = i < keyframe->points.size() ? keyframe->points[i] : nullptr;
      features.points.push_back(point != nullptr && !point->bad
                                    ? std::optional<Eigen::Vector3d>(point->position)
                                    : std::nullopt);
    }
  }
  return keyframes;
}

}  // namespace

bool KeyframeMoved(const KeyFrameState& before, const KeyFrameState& now, double tolerance) {
  // A point one map unit in front of the camera moves by at most the centre's shift plus
  // the turn (radians) times that unit.
  const double turn = Eigen::AngleAxisd(before.R_wc.transpose() * now.R_wc).angle();
  return (now.t_wc - before.t_wc).norm() + turn > tolerance;
}

nlohmann::json Timing(const std::vector<double>& seconds) {
  return {{"count", seconds.size()},
          {"median_ms", 1000.0 * Quantile(seconds, 0.5)},
          {"p95_ms", 1000.0 * Quantile(seconds, 0.95)},
          {"max_ms",
           seconds.empty() ? 0.0 : 1000.0 * *std::max_element(seconds.begin(), seconds.end())}};
}

nlohmann::json Timing(const DurationSummary& seconds) {
  return {{"count", seconds.count()},
          {"median_ms", 1000.0 * seconds.Median()},
          {"p95_ms", 1000.0 * seconds.Quantile(0.95)},
          {"max_ms", 1000.0 * seconds.max()}};
}

nlohmann::json PerKeyframeTiming(const std::vector<double>& cpu_seconds) {
  const std::size_t quarter = cpu_seconds.size() / 4;
  const auto median_ms = [&](std::size_t begin, std::size_t end) {
    return quarter == 0 ? 0.0
                        : 1000.0 * Median(std::vector<double>(
                                       cpu_seconds.begin() + static_cast<std::ptrdiff_t>(begin),
                                       cpu_seconds.begin() + static_cast<std::ptrdiff_t>(end)));
  };
  const double first = median_ms(0, quarter);
  const double last = median_ms(cpu_seconds.size() - quarter, cpu_seconds.size());
  return {{"count", cpu_seconds.size()},
          {"first_quarter_median_ms", first},
          {"last_quarter_median_ms", last},
          {"last_to_first", first > 0.0 ? last / first : 0.0}};
}

std::vector<ChangeEntry> RevisedChangeLog(const ObjectMapper& mapper,
                                          const ChangeLogContext& context) {
  return ReviseChangeLog(mapper.Changes(), mapper.LiveObjects(), context);
}

nlohmann::json WriteObjectMap(const ObjectMapper& mapper, const std::string& folder,
                              const ChangeLogContext& change_log) {
  WriteFileAtomically(folder + "/objects.json", mapper.ObjectsJson());
  WriteFileAtomically(folder + "/changes.json",
                      ChangeLogJson(RevisedChangeLog(mapper, change_log)));
  WriteFileAtomically(folder + "/ocg.json", mapper.GraphJson());
  WriteFileAtomically(folder + "/ocg_observations.jsonl", mapper.ObservationsJsonl());
  const ObjectLayerStats stats = mapper.Stats();
  return {{"detections_used", stats.detections_used},
          {"detections_matched", stats.detections_matched},
          {"objects_created", stats.objects_created},
          {"objects_live", mapper.LiveObjectCount()}};
}

ObjectLayer::ObjectLayer(const Settings& settings, bool enabled, bool keep_first_removal)
    : settings_(settings), enabled_(enabled), keep_first_removal_(keep_first_removal) {
  point_search_.pyramid = MakeScalePyramid(settings_.orb.levels, settings_.orb.scale_factor);
  point_search_.radius = settings_.objects.presence_search_radius;
  point_search_.max_distance = settings_.matcher.loose_distance;
  point_search_.ratio = settings_.matcher.projection_ratio;
  if (enabled_) Start();
}

void ObjectLayer::AddFrame(const System& system, const TrackingResult& result, std::int64_t frame,
                           double timestamp, const std::vector<Detection>& detections,
                           FrameColourImage& colour) {
  if (!enabled_) return;
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = ThreadCpuSeconds();
  if (!session_start_) session_start_ = timestamp;
  if (result.reset || result.new_map || result.switched_map) {
    // The SLAM map the objects were built in is gone (reset) or left behind for a new map
    // or another map of the atlas in coordinates of their own: objects of the old frame
    // cannot be kept in the new one, so the object map starts over.
    spdlog::warn("frame {}: the SLAM map was {}: the object map starts over", frame,
                 result.reset ? "reset" : "left for another map");
    ++resets_;
    Start();
  } else if (result.merged) {
    // The SLAM map the objects are in moved into another map's frame (and scale): their
    // sightings take their frames' new poses and their points' new positions, and each
    // object is estimated again from them, before this frame's detections meet them.
    Follow(system);
  }
  if (!result.T_cw) return;
  std::vector<PointObservation> points;
  points.reserve(result.points.size());
  for (const TrackedPoint& point : result.points)
    points.push_back({point.id, point.pixel, point.position});
  // An OCG keyframe's sightings take their colours as they are made, as in pose-given
  // runs: the same frames, the same image, whatever SLAM culls later.
  const bool ocg_keyframe = tracked_frames_++ % settings_.objects.keyframe_interval == 0;
  const cv::Mat bgr = ocg_keyframe && !detections.empty() ? colours_.ImageFor(colour) : cv::Mat();
  last_association_ =
      mapper_->AddFrame(frame_offset_ + frame, timestamp, *result.T_cw, detections, &points, bgr);
  if (!detections.empty()) new_frames_.push_back(static_cast<std::size_t>(frame));
  if (result.new_keyframe) Follow(system);
  if (ocg_keyframe) {
    // The map as it was just before the OCG's first removal, for the before/after
    // snapshots (exact in sequential mode; a keyframe late when the OCG has a thread).
    std::vector<ObjectView> before;
    if (keep_first_removal_ && !removal_seen_) before = mapper_->Views();
    const std::int64_t removed = mapper_->Stats().objects_removed;
    point_search_.features = system.LastFrameFeatures();
    mapper_->AddKeyframe(keyframes_++, timestamp, *result.T_cw, &point_search_);
    point_search_.features = nullptr;
    if (!removal_seen_ && mapper_->Stats().objects_removed > removed) {
      removal_seen_ = true;
      if (keep_first_removal_) first_removal_ = std::move(before);
    }
  }
  seconds_.Add(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  if (result.new_keyframe) keyframe_cpu_seconds_.push_back(ThreadCpuSeconds() - cpu_start);
}

std::vector<ObjectView> ObjectLayer::Views() const {
  return enabled_ ? mapper_->Views() : std::vector<ObjectView>{};
}

std::size_t ObjectLayer::LiveObjectCount() const {
  return enabled_ ? mapper_->LiveObjectCount() : 0;
}

std::optional<Eigen::Vector3d> ObjectLayer::Up() const {
  if (!enabled_) return std::nullopt;
  return mapper_->Up();
}

std::vector<FrameDetection> ObjectLayer::LastFrameDetections() const {
  return FrameDetectionsOf(last_association_);
}

std::optional<std::vector<ObjectView>> ObjectLayer::TakeFirstRemoval() {
  return std::exchange(first_removal_, std::nullopt);
}

void ObjectLayer::Finish(const System& system) {
  if (!enabled_) return;
  // A loaded object map already follows the loaded SLAM map, which only a tracked frame
  // changes; following it again would move the objects anyway (up and cuboids refine
  // each other a little more at every call).
  if (!loaded_ || tracked_frames_ > loaded_tracked_frames_) Follow(system);
  mapper_->Finish();
  colours_.WarnOfUnreadable();
  // The pairing (ChangeLog()) matches with the default AppearanceOptions too.
  colour_ = mapper_->ColourAppearances(AppearanceOptions{}.min_colour_signatures);
  // Between sessions: the objects' looks in the keyframes' features.
  if (session_ == 0) return;
  box_appearance_ = mapper_->BoxAppearances(KeyframeFeaturesOf(system), BoxAppearanceOptions{},
                                            AppearanceOptions{}.max_distance);
}

std::string ObjectLayer::Objects() const { return enabled_ ? mapper_->ObjectsJson() : ""; }
std::string ObjectLayer::Changes() const {
  return enabled_ ? ChangeLogJson(RevisedChangeLog(*mapper_, ChangeLog())) : "";
}

nlohmann::json ObjectLayer::Write(const std::string& output) const {
  nlohmann::json section = WriteObjectMap(*mapper_, output, ChangeLog());
  const ObjectLayerStats stats = mapper_->Stats();
  section.update({{"ocg_mode", settings_.ocg.mode},
                  {"keyframes", keyframes_},
                  {"object_map_resets", resets_},
                  {"supporting_plane_inliers", stats.plane_inliers},
                  {"colour_signatures", colours_.Report(stats)},
                  {"up", {stats.up.x(), stats.up.y(), stats.up.z()}},
                  {"timing",
                   {{"objects_per_frame", Timing(seconds_)},
                    {"object_layer_per_keyframe", PerKeyframeTiming(keyframe_cpu_seconds_)},
                    {"colour_per_keyframe_image", colours_.Timing(stats)}}},
                  {"slam_map_full_reads", full_map_reads_}});
  if (settings_.ocg.modes().point_presence) {
    const ObjectMap::PointPresenceStats points = mapper_->PointPresenceStats();
    section["point_presence"] = {
        {"keyframes_searched", points.keyframes},
        {"keyframes_with_presence", points.keyframes_with_presence},
        {"objects_searched", points.objects_searched},
        {"objects_present", points.objects_present},
        {"cpu_ms_per_keyframe",
         points.keyframes > 0 ? 1000.0 * points.cpu_seconds / points.keyframes : 0.0}};
  }
  return section;
}

void ObjectLayer::Start() {
  mapper_ = std::make_unique<ObjectMapper>(settings_.objects, settings_.ocg, settings_.camera.model,
                                           settings_.system.sequential);
  mapper_->RecordObservations();
  mapper_->StartSession(session_, frame_offset_);
  keyframes_ = 0;
  tracked_frames_ = 0;
  last_association_ = {};
  map_version_.reset();  // the new mapper's copy of the SLAM map is empty
  follow_every_frame_ = true;
  frames_by_anchor_.clear();
  anchor_read_at_.clear();
  new_frames_.clear();
}

ChangeLogContext ObjectLayer::ChangeLog() const {
  ChangeLogContext context;
  context.session = session_;
  context.session_start = session_start_.value_or(0.0);
  context.appearance = mapper_->Appearances();
  context.seen_as_class = mapper_->SeenAsClassThisSession();
  context.box_appearance = box_appearance_;
  context.colour = colour_;
  context.earlier_changes = earlier_changes_;
  return context;
}

void ObjectLayer::SaveState(std::ostream& out) const {
  // "time" counts from the first frame of the session that reads the log: a later
  // session gives earlier entries none.
  SaveObjectMapper(*mapper_,
                   {keyframes_, tracked_frames_,
                    ChangeLogJson(RevisedChangeLog(*mapper_, ChangeLog()), /*with_time=*/false)},
                   out);
}

void ObjectLayer::LoadState(std::istream& in, int session, std::int64_t frame_offset,
                            std::uint32_t file_version) {
  const ObjectLayerCounters counters = LoadObjectMapper(in, mapper_.get(), file_version);
  if (counters.change_log)
    earlier_changes_ = ParseChangeLog(*counters.change_log, "the map file's change log");
  StartSession(session, frame_offset);
  keyframes_ = counters.keyframes;
  tracked_frames_ = loaded_tracked_frames_ = counters.tracked_frames;
  loaded_ = true;
}

void ObjectLayer::StartSession(int session, std::int64_t frame_offset) {
  session_ = session;
  frame_offset_ = frame_offset;
  follow_every_frame_ = true;
  if (enabled_) mapper_->StartSession(session, frame_offset);
}

void ObjectLayer::PruneAnchoredFrames() {
  const std::vector<std::int64_t> kept = mapper_->SightingFrames();  // sorted
  anchored_frames_ = 0;
  for (auto it = frames_by_anchor_.begin(); it != frames_by_anchor_.end();) {
    std::vector<std::size_t>& frames = it->second;
    frames.erase(std::remove_if(frames.begin(), frames.end(),
                                [&](std::size_t call) {
                                  return !std::binary_search(
                                      kept.begin(), kept.end(),
                                      frame_offset_ + static_cast<std::int64_t>(call));
                                }),
                 frames.end());
    anchored_frames_ += frames.size();
    it = frames.empty() ? frames_by_anchor_.erase(it) : std::next(it);
  }
  anchored_after_pruning_ = anchored_frames_;
}

void ObjectLayer::Follow(const System& system) {
  // What changed in the SLAM map since the last time (all of it the first time). Read
  // before the poses: a change after it is in the next call's answer.
  const MapChanges map = system.MapChangesSince(map_version_);
  map_version_ = map.version;
  SlamMapChanges changes;
  changes.everything = map.everything;
  full_map_reads_ += map.everything ? 1 : 0;
  // The frames whose pose may have changed: every sighting frame after everything moved,
  // else the new ones and those placed from a keyframe that moved or was culled (a frame's
  // pose is its anchor's times a fixed relative pose). The earlier sessions' frames have
  // no pose in this run: their sightings keep theirs.
  std::vector<std::size_t> calls;  // this session's frames, as TrackImage counted them
  const bool every_frame = map.everything || follow_every_frame_;
  if (every_frame) {
    frames_by_anchor_.clear();
    anchor_read_at_.clear();
    anchored_frames_ = 0;
    for (const std::int64_t frame : mapper_->SightingFrames()) {
      if (frame >= frame_offset_) calls.push_back(static_cast<std::size_t>(frame - frame_offset_));
    }
  } else {
    calls = std::move(new_frames_);
  }
  new_frames_.clear();
  follow_every_frame_ = false;
  // A keyframe the journal names counts as moved once it is culled, or its camera moved
  // more than the tolerance since its frames were read: its frames are read again, and it
  // is compared with its pose now from here on. A frame given a pose later, from an anchor
  // that had moved less than the tolerance, is off by at most that much more.
  for (const KeyFrameState& keyframe : map.keyframes) {
    const auto read_at = anchor_read_at_.find(keyframe.id);
    if (keyframe.live && read_at != anchor_read_at_.end() &&
        !KeyframeMoved(read_at->second, keyframe, settings_.objects.follow_tolerance))
      continue;  // its frames keep the poses they were given
    const auto anchored = frames_by_anchor_.find(keyframe.id);
    if (!every_frame && anchored != frames_by_anchor_.end()) {
      calls.insert(calls.end(), anchored->second.begin(), anchored->second.end());
      anchored_frames_ -= anchored->second.size();
      frames_by_anchor_.erase(anchored);
    }
    if (keyframe.live) {
      anchor_read_at_[keyframe.id] = keyframe;
    } else if (read_at != anchor_read_at_.end()) {
      anchor_read_at_.erase(read_at);
    }
  }
  std::vector<std::uint64_t> anchors;
  const std::vector<std::optional<SE3>> poses = system.FramePoses(calls, &anchors);
  for (std::size_t i = 0; i < calls.size(); ++i) {
    if (!poses[i]) continue;
    changes.frame_poses.emplace(frame_offset_ + static_cast<std::int64_t>(calls[i]), *poses[i]);
    frames_by_anchor_[anchors[i]].push_back(calls[i]);
    ++anchored_frames_;
  }
  if (anchored_frames_ > std::max<std::size_t>(1024, 2 * anchored_after_pruning_))
    PruneAnchoredFrames();
  changes.points.reserve(map.points.size());
  for (const MapPointState& point : map.points) {
    changes.points.push_back(
        {point.id, point.live ? std::optional(point.position) : std::nullopt, point.descriptor});
  }
  for (const KeyFrameState& keyframe : map.keyframes) {
    changes.camera_rotations.emplace_back(
        keyframe.id, keyframe.live ? std::optional(keyframe.R_wc) : std::nullopt);
  }
  mapper_->FollowSlamMap(changes, settings_.system.seed + static_cast<std::uint64_t>(keyframes_));
}

}  // namespace ocg::app_detail
