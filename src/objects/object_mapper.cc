#include "ocg/objects/object_mapper.h"

#include <algorithm>
#include <map>

#include "ocg/core/cpu_time.h"
#include "ocg/core/statistics.h"
#include "ocg/objects/change_log.h"
#include "ocg/ocg/replay_format.h"

namespace ocg {

ObjectMapper::ObjectMapper(ObjectsOptions objects, OcgOptions ocg, PinholeCamera camera,
                           bool sequential)
    : map_(std::move(objects), camera), manager_(ocg, sequential) {
  map_.SetRestore(ocg.modes().restore);
  map_.SetEvidence(EvidenceProvidersFor(ocg.modes()));
  // Runs on the OCG's thread (in sequential mode inside Submit()): never hold map_mutex_
  // while submitting.
  manager_.SetRemovalCallback([this](const KeyframeResult& result) {
    std::lock_guard<std::mutex> lock(map_mutex_);
    for (const RemovalEvent& event : result.removed) map_.Remove(event);
    stats_.objects_removed += static_cast<std::int64_t>(result.removed.size());
  });
}

ObjectMapper::~ObjectMapper() {
  try {
    manager_.Shutdown();
  } catch (...) {
    // A worker error was already reported by Finish(); a destructor must not throw.
  }
}

FrameAssociation ObjectMapper::AddFrame(std::int64_t frame, double timestamp, const SE3& T_cw,
                                        const std::vector<Detection>& detections,
                                        const std::vector<PointObservation>* points,
                                        const cv::Mat& colour) {
  std::lock_guard<std::mutex> lock(map_mutex_);
  const std::vector<ObjectDetection> usable =
      FilterDetections(detections, map_.options(), map_.camera());
  FrameAssociation association = map_.AddFrame(frame, timestamp, T_cw, usable, points);
  if (!colour.empty() && !association.detections.empty()) {
    const double start = ThreadCpuSeconds();
    ++stats_.colour_images;
    stats_.colour_sightings += map_.SetSightingColours(frame, colour, ColourSignatureOptions{});
    stats_.colour_cpu_seconds += ThreadCpuSeconds() - start;
  }
  ++stats_.frames;
  stats_.detections_used += static_cast<std::int64_t>(usable.size());
  stats_.detections_matched +=
      static_cast<std::int64_t>(association.matched.size() - association.promoted.size());
  stats_.objects_created += static_cast<std::int64_t>(association.promoted.size());
  return association;
}

void ObjectMapper::FollowSlamMap(const SlamMapChanges& changes, std::uint64_t seed) {
  const ObjectsOptions& options = map_.options();
  follow_work_ = SlamFollowWork{};
  follow_work_.points_changed = changes.points.size();
  changed_since_fit_ += slam_map_.Apply(changes);
  const Eigen::Vector3d prior = slam_map_.CameraUpPrior();
  if (changes.everything || !plane_fitted_ ||
      static_cast<double>(changed_since_fit_) >=
          options.plane_refit_share * static_cast<double>(points_at_fit_)) {
    const std::vector<Eigen::Vector3d> positions = slam_map_.Positions();
    plane_ = FindSupportingPlane(positions, prior, options.plane_max_tilt_deg,
                                 options.plane_inlier_share, options.plane_iterations, seed);
    plane_fitted_ = true;
    points_at_fit_ = positions.size();
    changed_since_fit_ = 0;
    follow_work_.plane_points = positions.size();
    follow_work_.plane_refit = true;
  }
  const SupportingPlane& plane = plane_;
  const std::unordered_map<std::uint64_t, SlamMapCopy::Point>& points = slam_map_.points();
  std::lock_guard<std::mutex> lock(map_mutex_);
  Eigen::Vector3d up = prior;
  if (plane.valid) {
    // Objects stand on the plane or on surfaces parallel to it: their bottoms (in the
    // current gravity frame) refine its tilt. Levels: within half an object's height.
    std::vector<Eigen::Vector3d> bottoms;
    std::vector<double> heights;
    const Eigen::Vector3d current_up = map_.gravity_frame().col(2);
    for (const auto& [id, object] : map_.objects()) {
      if (!object.has_cuboid) continue;
      bottoms.push_back(object.cuboid.centre - 0.5 * object.cuboid.size.z() * current_up);
      heights.push_back(object.cuboid.size.z());
    }
    up =
        heights.empty() ? plane.normal : RefineUpWithBottoms(plane, bottoms, 0.5 * Median(heights));
  }
  stats_.plane_inliers = plane.valid ? plane.inliers : 0;
  stats_.up = up;
  map_.SetUp(up);
  std::vector<std::int64_t> frames;
  frames.reserve(changes.frame_poses.size());
  for (const auto& [frame, pose] : changes.frame_poses) frames.push_back(frame);
  // Of the map's points, those that changed, with their states: the objects follow them
  // alone (the whole map when it started over).
  std::vector<ObjectMap::ChangedPoint> changed_points;
  changed_points.reserve(changes.points.size());
  for (const SlamMapChanges::Point& point : changes.points) {
    changed_points.push_back({point.id, point.position ? &*point.position : nullptr,
                              point.position ? &point.descriptor : nullptr});
  }
  std::stable_sort(changed_points.begin(), changed_points.end(),
                   [](const ObjectMap::ChangedPoint& a, const ObjectMap::ChangedPoint& b) {
                     return a.id < b.id;
                   });
  map_.FollowMap(
      [&changes](std::int64_t frame) -> std::optional<SE3> {
        const auto found = changes.frame_poses.find(frame);
        if (found == changes.frame_poses.end()) return {};
        return found->second;
      },
      [&points](std::uint64_t point) -> std::optional<Eigen::Vector3d> {
        const auto found = points.find(point);
        if (found == points.end()) return {};
        return found->second.position;
      },
      [&points](std::uint64_t point) -> const Descriptor* {
        const auto found = points.find(point);
        return found == points.end() ? nullptr : &found->second.descriptor;
      },
      changes.everything ? nullptr : &frames, changes.everything ? nullptr : &changed_points);
}

std::vector<std::int64_t> ObjectMapper::SightingFrames() const {
  std::lock_guard<std::mutex> lock(map_mutex_);
  return map_.SightingFrames();
}

std::map<ObjectId, std::vector<Descriptor>> ObjectMapper::Appearances() const {
  std::lock_guard<std::mutex> lock(map_mutex_);
  return map_.Appearances();
}

SeenAsClass ObjectMapper::SeenAsClassThisSession() const {
  std::lock_guard<std::mutex> lock(map_mutex_);
  return map_.SeenAsClassThisSession();
}

std::map<ObjectId, std::vector<Descriptor>> ObjectMapper::BoxAppearances(
    const KeyframeFeatureMap& keyframes, const BoxAppearanceOptions& options,
    int max_distance) const {
  std::lock_guard<std::mutex> lock(map_mutex_);
  return map_.BoxAppearances(keyframes, options, max_distance);
}

std::map<ObjectId, ColourHistogram> ObjectMapper::ColourAppearances(int min_signatures) const {
  std::lock_guard<std::mutex> lock(map_mutex_);
  return map_.ColourAppearances(min_signatures);
}

void ObjectMapper::AddKeyframe(std::int64_t keyframe_id, double timestamp, const SE3& T_cw,
                               const FrameFeatureSearch* frame) {
  KeyframeObservation observation;
  {
    std::lock_guard<std::mutex> lock(map_mutex_);
    std::vector<ObjectChange> merges;
    observation = map_.MakeKeyframeObservation(keyframe_id, timestamp, T_cw, &merges, frame);
    ++stats_.keyframes;
    if (record_observations_) observations_jsonl_.Append(ObservationToJson(observation) + "\n");
  }
  manager_.Submit(std::move(observation));
}

void ObjectMapper::StartSession(int session, std::int64_t first_frame) {
  manager_.StartSession();
  std::lock_guard<std::mutex> lock(map_mutex_);
  map_.StartSession(session, first_frame);
}

void ObjectMapper::Finish() {
  // A successor of another colour is another object, not this one carried: colours less
  // alike than the change log's min_colour_similarity (its pairing refuses such a pair too,
  // unless descriptors vouch for it; those are not gathered here).
  const AppearanceOptions appearance;
  std::map<ObjectId, ColourHistogram> colours;
  {
    std::lock_guard<std::mutex> lock(map_mutex_);
    colours = map_.ColourAppearances(appearance.min_colour_signatures);
  }
  manager_.EndSession([&](ObjectId object, ObjectId successor) {
    const std::optional<double> similarity = ColourSimilarityOf(colours, object, successor);
    return !similarity || *similarity >= appearance.min_colour_similarity;
  });
  manager_.Shutdown();
  // The outputs tell every sighting (Objects.reestimate_share lets estimates wait).
  std::lock_guard<std::mutex> lock(map_mutex_);
  map_.EstimatePending();
}

ObjectMap::PointPresenceStats ObjectMapper::PointPresenceStats() const {
  std::lock_guard<std::mutex> lock(map_mutex_);
  return map_.point_presence_stats();
}

std::string ObjectMapper::ObjectsJson() const {
  const std::vector<ObjectStatus> states = manager_.Snapshot();
  std::lock_guard<std::mutex> lock(map_mutex_);
  return ocg::ObjectsJson(map_, states);
}

std::vector<ObjectChange> ObjectMapper::Changes() const {
  std::lock_guard<std::mutex> lock(map_mutex_);
  return map_.changes();
}

std::vector<ObjectRecord> ObjectMapper::LiveObjects() const {
  std::lock_guard<std::mutex> lock(map_mutex_);
  return LiveObjectRecords(map_);
}

std::string ObjectMapper::ObservationsJsonl() const {
  std::lock_guard<std::mutex> lock(map_mutex_);
  return observations_jsonl_.Text();
}

std::string ObjectMapper::GraphJson() const { return manager_.GraphJson(); }

ObjectLayerStats ObjectMapper::Stats() const {
  std::lock_guard<std::mutex> lock(map_mutex_);
  return stats_;
}

std::vector<ObjectView> ObjectMapper::Views() const {
  std::map<ObjectId, int> states;
  for (const ObjectStatus& status : manager_.Snapshot())
    states[status.id] = static_cast<int>(status.state);
  std::lock_guard<std::mutex> lock(map_mutex_);
  std::vector<ObjectView> views;
  for (const auto& [id, object] : map_.objects()) {
    if (!object.has_cuboid) continue;
    const auto state = states.find(id);
    views.push_back(
        {id, object.class_id, object.cuboid, state == states.end() ? 0 : state->second, false});
  }
  for (const ObjectChange& change : map_.changes()) {
    // A restored object is live again: its removal is history.
    if (change.type == "removed" && map_.objects().count(change.object_id) == 0)
      views.push_back({change.object_id, change.class_id, change.cuboid, 5, true});
  }
  return views;
}

Eigen::Vector3d ObjectMapper::Up() const {
  std::lock_guard<std::mutex> lock(map_mutex_);
  return map_.gravity_frame().col(2);
}

std::size_t ObjectMapper::LiveObjectCount() const {
  std::lock_guard<std::mutex> lock(map_mutex_);
  return map_.objects().size();
}

}  // namespace ocg
