#include "ocg/slam/system.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <stdexcept>

#include "ocg/core/cpu_time.h"
#include "ocg/slam/map_file.h"

namespace ocg {
namespace {

double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

StampedPose MakePose(double timestamp, const std::string& text, const SE3& T_cw) {
  StampedPose pose;
  pose.timestamp = timestamp;
  pose.timestamp_text = text;
  pose.T_wc = T_cw.Inverse();
  return pose;
}

// The decimals with which timestamp prints as text ("%.*f"), or -1 when none does.
std::int8_t DecimalsOf(double timestamp, const std::string& text) {
  const std::size_t point = text.find('.');
  const int decimals = point == std::string::npos ? 0 : static_cast<int>(text.size() - point - 1);
  if (decimals > 12 || text.size() > 40) return -1;
  char printed[64];
  std::snprintf(printed, sizeof printed, "%.*f", decimals, timestamp);
  return text == printed ? static_cast<std::int8_t>(decimals) : std::int8_t{-1};
}

}  // namespace

System::System(const SystemConfig& config, const Vocabulary& vocabulary)
    : config_(config), vocabulary_(vocabulary), database_(vocabulary.WordCount()) {
  config_.camera.Check();
  auto sink = [this](const KeyFramePtr& keyframe) {
    if (!config_.sequential) {
      local_mapping_->Insert(keyframe);
      return false;
    }
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = ThreadCpuSeconds();
    local_mapping_->ProcessKeyFrame(keyframe);
    const bool loop_closed = loop_closing_->ProcessKeyFrame(keyframe);
    pending_mapping_seconds_ += Seconds(start);
    pending_mapping_cpu_seconds_ += ThreadCpuSeconds() - cpu_start;
    return loop_closed;
  };
  auto idle = [this] { return config_.sequential || local_mapping_->Idle(); };
  tracking_ = std::make_unique<Tracking>(
      config_.camera, config_.fps, config_.orb, config_.matcher, config_.initializer,
      config_.tracking, TrackingDependencies{&vocabulary_, &database_, &map_}, sink, idle);
  local_mapping_ =
      std::make_unique<LocalMapping>(config_.camera, tracking_->pyramid(), config_.matcher,
                                     config_.local_mapping, &map_, &database_);
  loop_closing_ =
      std::make_unique<LoopClosing>(config_.camera, tracking_->pyramid(), config_.matcher,
                                    config_.loop_closing, &map_, &database_, config_.seed);
  if (!config_.sequential) {
    local_mapping_->SetKeyFrameMapped(
        [this](const KeyFramePtr& keyframe) { loop_closing_->Insert(keyframe); });
    loop_closing_->Start();
    local_mapping_->Start();
  }
}

System::~System() {
  try {
    Shutdown();
  } catch (...) {
    // Reported by an explicit Shutdown(); a destructor must not throw.
  }
}

TrackingResult System::TrackImage(const cv::Mat& image, double timestamp,
                                  const std::string& timestamp_text,
                                  const ExtractedFeatures* features) {
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = ThreadCpuSeconds();
  pending_mapping_seconds_ = 0.0;
  pending_mapping_cpu_seconds_ = 0.0;
  TrackingResult result = tracking_->Track(image, timestamp, timestamp_text, features);
  if (result.reset || result.new_map) {
    resets_ += result.reset ? 1 : 0;
    new_maps_ += result.new_map ? 1 : 0;
    if (!config_.sequential) {  // drain the queues and join, in the order keyframes flow
      local_mapping_->Stop();
      loop_closing_->Stop();
    }
    // A new map keeps the one left in the atlas; a reset erases it.
    tracking_->Reset(result.new_map);
    local_mapping_->Reset();
    loop_closing_->Reset();
    if (!config_.sequential) {
      loop_closing_->Start();
      local_mapping_->Start();
    }
    if (result.reset) {
      std::lock_guard<std::mutex> lock(map_.mutex());
      for (FrameRecord& record : frames_) {  // that map is gone
        if (record.tracked && !map_.GetKeyFrame(record.reference)) record.tracked = false;
      }
    }
  }
  FrameRecord record;
  record.timestamp = timestamp;
  record.text_decimals = DecimalsOf(timestamp, timestamp_text);
  if (record.text_decimals < 0) timestamp_texts_[frames_.size()] = timestamp_text;
  record.state = result.state;
  record.relocalized = result.relocalized;
  record.new_keyframe = result.new_keyframe;
  if (pending_mapping_seconds_ > 0.0) timings_.local_mapping.Add(pending_mapping_seconds_);
  timings_.tracking.Add(Seconds(start) - pending_mapping_seconds_);
  timings_.tracking_cpu.Add(ThreadCpuSeconds() - cpu_start - pending_mapping_cpu_seconds_);
  timings_.map_lock_wait.Add(result.map_lock_wait_seconds);
  if (after_tracking_) after_tracking_();
  // One look at the map for the frame's record: in threaded mode the loop closing thread
  // may have moved it (a merge: into another map) since tracking placed the frame, so the
  // frame is placed again as the map now stands (Tracking::LastFramePoseNow), and the map,
  // the merge flag and the reference keyframe are read in that same state.
  const std::unique_lock<std::mutex> lock = map_.LockForTracking();
  record.map = map_.current_map();
  result.merged = map_.merges() != merges_seen_;
  merges_seen_ = map_.merges();
  if (result.T_cw && tracking_->MapMovedSinceLastFrame()) {
    result.T_cw = tracking_->LastFramePoseNow();
    for (TrackedPoint& point : result.points) {  // what the object layer places objects on
      const auto found = map_.points().find(point.id);
      if (found != map_.points().end()) point.position = found->second->position;
    }
  }
  if (result.T_cw) {
    // The reference is the current map's newest keyframe.
    KeyFramePtr reference;
    for (auto it = map_.keyframes().rbegin(); it != map_.keyframes().rend(); ++it) {
      if (!it->second->bad && it->second->map == record.map) {
        reference = it->second;
        break;
      }
    }
    if (reference) {
      record.tracked = true;
      record.reference = reference->id;
      record.T_c_reference = *result.T_cw * reference->T_cw.Inverse();
    }
  }
  frames_.push_back(record);
  return result;
}

std::function<ExtractedFeatures(const cv::Mat&)> System::MakeFeatureExtractor() const {
  auto extractor = std::make_shared<OrbExtractor>(config_.orb);
  const PinholeCamera camera = config_.camera;
  return [extractor, camera](const cv::Mat& image) { return extractor->Extract(image, camera); };
}

bool System::MappingIdle() const {
  return config_.sequential || (local_mapping_->Idle() && loop_closing_->Idle());
}

void System::Shutdown() {
  if (shut_down_) return;
  shut_down_ = true;
  try {
    local_mapping_->Stop();
  } catch (...) {
    try {
      loop_closing_->Stop();
    } catch (...) {
      // The local mapping failure comes first; this one is its consequence or later.
    }
    throw;
  }
  loop_closing_->Stop();
}

std::vector<StampedPose> System::KeyFrameTrajectory() const {
  return KeyFrameTrajectory(MainMap());
}

std::vector<StampedPose> System::CameraTrajectory() const { return CameraTrajectory(MainMap()); }

int System::CurrentMap() const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  return map_.current_map();
}

std::vector<int> System::FrameMapsLocked() const {
  std::vector<int> maps(frames_.size(), -1);
  for (std::size_t i = 0; i < frames_.size(); ++i) {
    if (!frames_[i].tracked) continue;
    // A culled reference keyframe stays in the map, tagged as the map it was in.
    if (const KeyFramePtr reference = map_.GetKeyFrame(frames_[i].reference))
      maps[i] = reference->map;
  }
  return maps;
}

std::vector<int> System::FrameMaps() const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  return FrameMapsLocked();
}

std::vector<MapSummary> System::Maps() const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  std::vector<MapSummary> maps(static_cast<std::size_t>(map_.map_count()));
  for (std::size_t m = 0; m < maps.size(); ++m) {
    maps[m].index = static_cast<int>(m);
    maps[m].current = maps[m].index == map_.current_map();
    maps[m].keyframes = map_.LiveKeyFrameCount(maps[m].index);
  }
  const std::vector<int> frame_maps = FrameMapsLocked();
  for (std::size_t i = 0; i < frame_maps.size(); ++i) {
    if (frame_maps[i] < 0) continue;
    MapSummary& summary = maps[static_cast<std::size_t>(frame_maps[i])];
    if (summary.frames_tracked == 0) summary.first_frame = i;
    summary.last_frame = i;
    ++summary.frames_tracked;
  }
  for (const auto& [id, point] : map_.points()) {
    if (point->map >= 0 && point->map < static_cast<int>(maps.size()))
      ++maps[static_cast<std::size_t>(point->map)].map_points;
  }
  for (const MapMerge& merge : AllMerges()) {
    MapSummary& summary = maps[static_cast<std::size_t>(merge.merged_map)];
    summary.merged_into = merge.into_map;
    summary.merged_at_frame = merge.frame;
    summary.merge_scale = merge.scale;
  }
  return maps;
}

int System::MainMap() const {
  const std::vector<MapSummary> maps = Maps();
  int main = CurrentMap();
  std::size_t most = maps[static_cast<std::size_t>(main)].frames_tracked;
  for (const MapSummary& summary : maps) {
    if (summary.frames_tracked > most) {
      most = summary.frames_tracked;
      main = summary.index;
    }
  }
  return main;
}

std::vector<StampedPose> System::KeyFrameTrajectory(int map) const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  std::vector<StampedPose> poses;
  for (const auto& [id, keyframe] : map_.keyframes()) {
    if (!keyframe->bad && keyframe->map == map)
      poses.push_back(MakePose(keyframe->timestamp, keyframe->timestamp_text, keyframe->T_cw));
  }
  return poses;
}

std::optional<SE3> System::FramePoseLocked(const FrameRecord& record,
                                           KeyFrameId* live_keyframe) const {
  // The relative pose was measured in the units of the map the frame was tracked in: a
  // merge of that map since scales it (PoseFromAnchor), as it scaled the keyframe's map.
  const std::optional<AnchoredPose> pose = PoseFromAnchor(
      map_, Anchor{map_.GetKeyFrame(record.reference), record.T_c_reference, record.map, 0},
      live_keyframe);
  if (!pose) return std::nullopt;
  return pose->T_cw;
}

std::vector<StampedPose> System::CameraTrajectory(int map) const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  const std::vector<int> frame_maps = FrameMapsLocked();
  std::vector<StampedPose> poses;
  for (std::size_t i = 0; i < frames_.size(); ++i) {
    if (frame_maps[i] != map) continue;
    const FrameRecord& record = frames_[i];
    if (const std::optional<SE3> T_cw = FramePoseLocked(record))
      poses.push_back(MakePose(record.timestamp, TimestampText(i), *T_cw));
  }
  return poses;
}

std::vector<std::optional<SE3>> System::FramePoses() const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  const std::vector<int> frame_maps = FrameMapsLocked();
  std::vector<std::optional<SE3>> poses(frames_.size());
  for (std::size_t i = 0; i < frames_.size(); ++i) {
    const FrameRecord& record = frames_[i];
    if (frame_maps[i] != map_.current_map()) continue;
    poses[i] = FramePoseLocked(record);
  }
  return poses;
}

std::vector<std::optional<SE3>> System::FramePoses(const std::vector<std::size_t>& frames,
                                                   std::vector<std::uint64_t>* anchors) const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  std::vector<std::optional<SE3>> poses(frames.size());
  if (anchors != nullptr) anchors->assign(frames.size(), 0);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (frames[i] >= frames_.size()) continue;
    const FrameRecord& record = frames_[frames[i]];
    if (!record.tracked) continue;
    // As FrameMapsLocked: the frame is placed in its reference keyframe's map now.
    const KeyFramePtr reference = map_.GetKeyFrame(record.reference);
    if (!reference || reference->map != map_.current_map()) continue;
    KeyFrameId anchor = 0;
    poses[i] = FramePoseLocked(record, &anchor);
    if (anchors != nullptr) (*anchors)[i] = anchor;
  }
  return poses;
}

std::string System::TimestampText(std::size_t frame) const {
  const FrameRecord& record = frames_.at(frame);
  if (record.text_decimals < 0) return timestamp_texts_.at(frame);
  char printed[64];
  std::snprintf(printed, sizeof printed, "%.*f", static_cast<int>(record.text_decimals),
                record.timestamp);
  return printed;
}

const ExtractedFeatures* System::LastFrameFeatures() const {
  return tracking_->LastFrameFeatures();
}

std::vector<Eigen::Vector3d> System::MapPointPositions(std::vector<MapPointId>* ids,
                                                       std::vector<Descriptor>* descriptors) const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  std::vector<Eigen::Vector3d> positions;
  positions.reserve(map_.points().size());
  if (ids != nullptr) ids->clear();
  if (descriptors != nullptr) descriptors->clear();
  for (const auto& [id, point] : map_.points()) {
    if (point->bad || point->map != map_.current_map()) continue;
    positions.push_back(point->position);
    if (ids != nullptr) ids->push_back(id);
    if (descriptors != nullptr) descriptors->push_back(point->descriptor);
  }
  return positions;
}

MapChanges System::MapChangesSince(std::optional<std::uint64_t> version) const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  return ChangesSince(map_, version);
}

void System::SetMapJournalPointTolerance(double tolerance) {
  std::lock_guard<std::mutex> lock(map_.mutex());
  map_.journal().SetPointTolerance(tolerance);
}

std::vector<KeyFramePtr> System::KeyFrames() const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  std::vector<KeyFramePtr> keyframes;
  for (const auto& [id, keyframe] : map_.keyframes()) {
    if (!keyframe->bad && keyframe->map == map_.current_map()) keyframes.push_back(keyframe);
  }
  return keyframes;
}

std::optional<LoopEvent> System::RecognizePlace(const KeyFramePtr& keyframe,
                                                std::size_t max_candidates) const {
  std::vector<KeyFramePtr> candidates;
  {
    std::lock_guard<std::mutex> lock(map_.mutex());
    for (const BowQueryResult& result : database_.Query(keyframe->bow, max_candidates, 1, {})) {
      const KeyFramePtr candidate = map_.GetKeyFrame(static_cast<KeyFrameId>(result.id));
      if (candidate && !candidate->bad) candidates.push_back(candidate);
    }
  }
  return loop_closing_->Recognize(keyframe, candidates);
}

std::vector<Eigen::Matrix3d> System::KeyFrameRotations() const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  std::vector<Eigen::Matrix3d> rotations;
  for (const auto& [id, keyframe] : map_.keyframes()) {
    if (!keyframe->bad && keyframe->map == map_.current_map())
      rotations.push_back(keyframe->T_cw.Inverse().rotation());
  }
  return rotations;
}

std::size_t System::KeyFrameCount() const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  return map_.LiveKeyFrameCount(map_.current_map());
}

std::size_t System::MapPointCount() const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  if (map_.map_count() == 1) return map_.points().size();
  return static_cast<std::size_t>(
      std::count_if(map_.points().begin(), map_.points().end(),
                    [this](const auto& entry) { return entry.second->map == map_.current_map(); }));
}

std::vector<MapMerge> System::AllMerges() const {
  std::vector<MapMerge> merges = loaded_merges_;
  for (const LoopEvent& merge : loop_closing_->Stats().merges)
    merges.push_back({merge.merged_map, merge.into_map, merge.frame, merge.scale});
  return merges;
}

void System::SaveMap(std::ostream& out) const { ocg::SaveMap(map_, out, AllMerges()); }

std::size_t System::AtlasKeyFrameCount() const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  return map_.LiveKeyFrameCount();
}

void System::LoadMap(std::istream& in, std::uint64_t frames_before, MapFileFormat format) {
  if (!frames_.empty()) {
    throw std::logic_error("System::LoadMap: a map can only be loaded before the first frame");
  }
  loaded_merges_ = ocg::LoadMap(in, &map_, tracking_->pyramid().levels(), format);
  std::uint64_t first_frame_id = frames_before;
  {
    std::lock_guard<std::mutex> lock(map_.mutex());
    for (const auto& [id, keyframe] : map_.keyframes()) {
      first_frame_id = std::max(first_frame_id, keyframe->frame_id + 1);
      if (!keyframe->bad) database_.Add(static_cast<int>(id), keyframe->bow);
    }
    map_.journal().Everything();
  }
  tracking_->StartInLoadedMap(first_frame_id);
  map_loaded_ = true;
}

const InitializationAttempts& System::Initialization() const {
  return tracking_->initialization_attempts();
}

}  // namespace ocg
