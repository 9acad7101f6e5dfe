#include "ocg/objects/object_map.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>

#include "ocg/core/coco.h"
#include "ocg/core/cpu_time.h"
#include "ocg/objects/assignment.h"
#include "ocg/objects/cuboid_json.h"
#include "ocg/objects/object_geometry.h"

namespace ocg {
namespace {

constexpr double kCandidatePenalty = 0.05;  // a map object wins a tie against a candidate

// Every n-th element so that at most limit remain, first and last kept.
std::vector<std::size_t> Thinned(std::size_t count, std::size_t limit) {
  std::vector<std::size_t> indices;
  if (count <= limit) {
    for (std::size_t i = 0; i < count; ++i) indices.push_back(i);
    return indices;
  }
  for (std::size_t k = 0; k < limit; ++k) indices.push_back(k * (count - 1) / (limit - 1));
  return indices;
}

// Whether a box that fits a projected cuboid so counts as a view of that object. A partial
// view counts only for an object of the box's class: a box inside a larger object's
// projection is as often a smaller object of another class in front of it.
bool CountsAsFit(BoxFit fit, bool same_class) {
  return fit == BoxFit::kWhole || (fit == BoxFit::kPartial && same_class);
}

// Whether stand_in's untruncated boxes fit object's projected cuboid (FitOfBox: whole, or
// partial views when of one class; for at least share of them): its detections fit object,
// at object's depth and size, wherever their own rays met.
bool SeenAsProjectionOf(const MapObject& stand_in, const MapObject& object, double min_iou,
                        double share, const Eigen::Matrix3d& R_wg, const PinholeCamera& camera) {
  const auto usable = std::count_if(stand_in.sightings.begin(), stand_in.sightings.end(),
                                    [](const ObjectSighting& s) { return !s.truncated; });
  // Most pairs fail at their first boxes: stop once too many missed.
  const double allowed_misses = (1.0 - share) * static_cast<double>(usable);
  int misses = 0;
  for (const ObjectSighting& sighting : stand_in.sightings) {
    if (sighting.truncated) continue;
    const std::optional<Box2> projected = ProjectCuboid(object.cuboid, R_wg, sighting.T_cw, camera);
    const BoxFit fit = projected ? FitOfBox(sighting.box, *projected, min_iou) : BoxFit::kNone;
    const bool covered = CountsAsFit(fit, stand_in.class_id == object.class_id);
    if (!covered && ++misses > allowed_misses) return false;
  }
  return usable > 0;
}

// How each sighting of track fits object's projected cuboid (truncated ones: kNone).
std::vector<BoxFit> FitsOfTrack(const MapObject& track, const MapObject& object, double min_iou,
                                const Eigen::Matrix3d& R_wg, const PinholeCamera& camera) {
  std::vector<BoxFit> fits;
  for (const ObjectSighting& sighting : track.sightings) {
    const std::optional<Box2> projected =
        sighting.truncated ? std::nullopt
                           : ProjectCuboid(object.cuboid, R_wg, sighting.T_cw, camera);
    fits.push_back(projected ? FitOfBox(sighting.box, *projected, min_iou) : BoxFit::kNone);
  }
  return fits;
}

// Whether a and b were detected in one frame with boxes that tell two objects apart. Boxes
// overlapping by duplicate_box_iou or more (the detector's second box on one object, which
// the non-maximum suppression let through) do not: each fed its own object, and one
// such frame kept the object's two halves apart for good.
bool SeenTogether(const MapObject& a, const MapObject& b, double duplicate_box_iou) {
  auto i = a.sightings.begin();
  auto j = b.sightings.begin();
  while (i != a.sightings.end() && j != b.sightings.end()) {
    if (i->frame == j->frame) {
      if (IntersectionOverUnion(i->box, j->box) < duplicate_box_iou) return true;
      ++i;
      ++j;
    } else if (i->frame < j->frame) {
      ++i;
    } else {
      ++j;
    }
  }
  return false;
}

Eigen::Vector3d WorldExtent(const Cuboid& cuboid, const Eigen::Matrix3d& R_wg) {
  Eigen::Vector3d low = Eigen::Vector3d::Constant(1e300), high = -low;
  for (const Eigen::Vector3d& corner : CuboidCorners(cuboid, R_wg)) {
    low = low.cwiseMin(corner);
    high = high.cwiseMax(corner);
  }
  return high - low;
}

// The share of the smaller box's volume inside the other (world-axis boxes from centre and
// extent); 0 when either is flat.
double OverlapShare(const Eigen::Vector3d& centre_a, const Eigen::Vector3d& extent_a,
                    const Eigen::Vector3d& centre_b, const Eigen::Vector3d& extent_b) {
  const Eigen::Vector3d low = (centre_a - 0.5 * extent_a).cwiseMax(centre_b - 0.5 * extent_b);
  const Eigen::Vector3d high = (centre_a + 0.5 * extent_a).cwiseMin(centre_b + 0.5 * extent_b);
  const double smaller = std::min(extent_a.prod(), extent_b.prod());
  if (smaller <= 0.0 || (high - low).minCoeff() <= 0.0) return 0.0;
  return (high - low).prod() / smaller;
}

// A change-log entry of the object as it is now.
ObjectChange ChangeOf(const char* type, std::int64_t keyframe_id, double timestamp,
                      const MapObject& object, int session) {
  ObjectChange change;
  change.type = type;
  change.keyframe_id = keyframe_id;
  change.timestamp = timestamp;
  change.object_id = object.id;
  change.class_id = object.class_id;
  change.cuboid = object.cuboid;
  change.sightings = object.sightings.total();
  change.session = session;
  return change;
}

bool SeenInOneSession(const MapObject& a, const MapObject& b) {
  return a.sightings.SharesASessionWith(b.sightings);
}

void AddPointVotes(MapObject& object, const std::vector<const PointObservation*>& box_points) {
  for (const PointObservation* point : box_points) {
    ObjectPoint& entry = object.points[point->id];
    ++entry.votes;
    entry.position = point->position;
  }
}

// Another record of the same object, from: its sightings (in frame order) and point votes
// join into's, whose class becomes its sightings' majority. Geometry is left to the caller.
// max_sightings: Objects.max_sightings.
void Absorb(MapObject& into, const MapObject& from, int max_sightings) {
  into.sightings.Merge(from.sightings, static_cast<std::size_t>(max_sightings));
  for (const auto& [id, point] : from.points) {
    ObjectPoint& entry = into.points[id];
    if (entry.votes == 0) entry.position = point.position;
    entry.votes += point.votes;
  }
  into.class_id = into.sightings.MajorityClass();
  into.first_frame = std::min(into.first_frame, from.first_frame);
  into.first_timestamp = std::min(into.first_timestamp, from.first_timestamp);
  into.last_frame = std::max(into.last_frame, from.last_frame);
  into.last_timestamp = std::max(into.last_timestamp, from.last_timestamp);
}

}  // namespace

std::vector<std::uint64_t> ObjectPointIds(const MapObject& object, int min_votes) {
  // Where the boxes' rays meet says which of the points in them are on the object: the
  // background behind it can hold most of them when the camera moves little.
  const double reach = object.has_cuboid ? object.cuboid.size.maxCoeff() : 0.0;
  std::vector<std::uint64_t> voted_ids;
  std::vector<Eigen::Vector3d> voted;
  for (const auto& [id, point] : object.points) {
    if (point.votes < min_votes) continue;
    if (object.has_cuboid && (point.position - object.cuboid.centre).norm() > reach) continue;
    voted_ids.push_back(id);
    voted.push_back(point.position);
  }
  const RobustBounds bounds = RobustPointBounds(voted, 3.0);
  if (!bounds.valid) return voted_ids;
  std::vector<std::uint64_t> kept;
  for (std::size_t i = 0; i < voted.size(); ++i) {
    if (bounds.Contains(voted[i])) kept.push_back(voted_ids[i]);
  }
  return kept;
}

bool PresentByPoints(const MapObject& object, const std::vector<std::uint64_t>& tracked,
                     const SE3& T_cw, const PinholeCamera& camera, const ObjectsOptions& options,
                     const FrameFeatureSearch* frame) {
  const bool searchable = frame != nullptr && frame->features != nullptr;
  if (tracked.empty() && !searchable) return false;
  int in_image = 0;
  int seen = 0;
  std::vector<PointToFind> to_find;
  for (std::uint64_t id : ObjectPointIds(object, options.min_point_votes)) {
    const ObjectPoint& point = object.points.at(id);
    const Eigen::Vector3d in_camera = T_cw * point.position;
    if (in_camera.z() <= 0.0 || !camera.IsInImage(camera.ProjectUndistorted(in_camera))) continue;
    ++in_image;
    if (std::binary_search(tracked.begin(), tracked.end(), id)) {
      ++seen;
    } else if (searchable && point.descriptor) {
      to_find.push_back({point.position, *point.descriptor});
    }
  }
  if (!to_find.empty()) seen += SearchPointsInFrame(to_find, T_cw, camera, *frame).found;
  return seen >= options.presence_min_points && seen >= options.presence_min_share * in_image;
}

std::vector<Eigen::Vector3d> ObjectPointSet(const MapObject& object, int min_votes) {
  std::vector<Eigen::Vector3d> positions;
  for (std::uint64_t id : ObjectPointIds(object, min_votes))
    positions.push_back(object.points.at(id).position);
  return positions;
}

std::vector<Descriptor> ObjectAppearance(const MapObject& object, int min_votes) {
  std::vector<Descriptor> descriptors;
  for (std::uint64_t id : ObjectPointIds(object, min_votes)) {
    const ObjectPoint& point = object.points.at(id);
    if (point.descriptor) descriptors.push_back(*point.descriptor);
  }
  return descriptors;
}

// An object's points as an association cue: how many are its own and the bounds of its
// point set.
struct ObjectMap::PointCue {
  int own_points = 0;
  RobustBounds bounds;
};

bool ObjectMap::HoldsOwnPoint(const MapObject& object,
                              const std::vector<const PointObservation*>& box_points) const {
  const double reach = object.cuboid.size.maxCoeff();  // as ObjectPointSet: on the object
  for (const PointObservation* point : box_points) {
    const auto own = object.points.find(point->id);
    if (own != object.points.end() && own->second.votes >= options_.min_point_votes &&
        (own->second.position - object.cuboid.centre).norm() <= reach) {
      return true;
    }
  }
  return false;
}

ObjectMap::ObjectMap(ObjectsOptions options, PinholeCamera camera)
    : options_(std::move(options)), camera_(camera), R_wg_(GravityFrame(options_.up)) {
  options_.Check();
}

double ObjectMap::AssociationScore(const MapObject& object, const ObjectDetection& detection,
                                   std::int64_t frame, const SE3& T_cw,
                                   const std::vector<const PointObservation*>& box_points,
                                   const PointCue* object_points) const {
  if (object.has_cuboid) {
    // Geometry first: the ray through the box centre must pass near the object's centre.
    // Without this gate a detection of the same class close by (the object's new place
    // after a move) keeps matching through the predicted box and feeds the old object.
    const Ray ray = PixelRay(detection.box.Centre(), T_cw, camera_);
    const bool in_front = (object.cuboid.centre - ray.origin).dot(ray.direction) > 0;
    if (!in_front || DistanceToRay(object.cuboid.centre, ray) >
                         options_.max_ray_distance * object.cuboid.size.maxCoeff()) {
      return 0.0;
    }
  }
  const ObjectSighting& last = object.sightings.back();
  if (object.has_cuboid && last.session < session_ && object_points != nullptr &&
      box_points.size() >= 3 && object_points->own_points >= 5 &&
      !HoldsOwnPoint(object, box_points)) {
    // Found again in a later session: between the visits an object of its class may have
    // been put down anywhere along this view's ray, and one view has no depth, so the
    // projected cuboid matches it just as well. The map points relocalized with the map
    // decide: an object that stayed shows some of its own in its box.
    return 0.0;
  }
  double sum = 0.0;
  int cues = 0;
  if (frame - last.frame <= options_.predicted_box_frames) {
    Box2 predicted = last.box;
    if (object.has_cuboid) {
      // Move the last box with the centre's projection and scale it with its depth.
      const Eigen::Vector3d before = last.T_cw * object.cuboid.centre;
      const Eigen::Vector3d now = T_cw * object.cuboid.centre;
      if (before.z() > 1e-3 && now.z() > 1e-3) {
        const Eigen::Vector2d shift =
            camera_.ProjectUndistorted(now) - camera_.ProjectUndistorted(before);
        const double scale = before.z() / now.z();
        const Eigen::Vector2d centre = last.box.Centre() + shift;
        const double half_width = 0.5 * last.box.Width() * scale;
        const double half_height = 0.5 * last.box.Height() * scale;
        predicted = {centre.x() - half_width, centre.y() - half_height, centre.x() + half_width,
                     centre.y() + half_height};
      }
    }
    sum += IntersectionOverUnion(predicted, detection.box);
    ++cues;
  }
  if (object.has_cuboid) {
    const std::optional<Box2> projected = ProjectCuboid(object.cuboid, R_wg_, T_cw, camera_);
    const double overlap = projected ? IntersectionOverUnion(*projected, detection.box) : 0.0;
    // Found again after a gap, with nothing but the cuboid to go by: the detection must
    // cover it well, or an object of the class put down nearby would be taken for it.
    if (cues == 0 && overlap < options_.min_reacquire_iou) return 0.0;
    sum += overlap;
    ++cues;
  }
  // Map points: the box holds the object's own points, and they lie where its points do.
  // Too few on either side says nothing (untextured objects, a new object).
  if (object_points != nullptr && box_points.size() >= 3 && object_points->own_points >= 5) {
    int shared = 0, inside = 0;
    for (const PointObservation* point : box_points) {
      const auto own = object.points.find(point->id);
      shared += own != object.points.end() && own->second.votes >= options_.min_point_votes;
      inside += object_points->bounds.Contains(point->position) ? 1 : 0;
    }
    const double count = static_cast<double>(box_points.size());
    sum += shared / count + inside / count;
    cues += 2;
  }
  return cues > 0 ? sum / cues : 0.0;
}

FrameAssociation ObjectMap::AddFrame(std::int64_t frame, double timestamp, const SE3& T_cw,
                                     const std::vector<ObjectDetection>& detections,
                                     const std::vector<PointObservation>* points) {
  current_frame_ = frame;
  last_tracked_points_.clear();
  if (point_presence_ && points != nullptr) {  // read by the 'points' evidence alone
    for (const PointObservation& point : *points) last_tracked_points_.push_back(point.id);
    std::sort(last_tracked_points_.begin(), last_tracked_points_.end());
  }
  FrameAssociation result;
  result.detections = detections;
  std::vector<MapObject*> entities;
  for (auto& entry : objects_) entities.push_back(&entry.second);
  const std::size_t object_count = entities.size();
  for (auto& entry : candidates_) entities.push_back(&entry.second);

  std::vector<std::vector<const PointObservation*>> box_points(detections.size());
  if (points != nullptr) {
    for (std::size_t d = 0; d < detections.size(); ++d) {
      box_points[d] = PointsInBox(*points, detections[d].box, options_.point_box_shrink);
    }
  }
  // Built on first use: only entities of a detected class need theirs.
  std::vector<std::optional<PointCue>> point_cues(entities.size());
  const auto point_cue = [&](std::size_t e) -> const PointCue* {
    if (points == nullptr) return nullptr;
    if (!point_cues[e]) {
      PointCue cue;
      for (const auto& [id, point] : entities[e]->points)
        cue.own_points += point.votes >= options_.min_point_votes ? 1 : 0;
      cue.bounds = RobustPointBounds(ObjectPointSet(*entities[e], options_.min_point_votes), 3.0);
      point_cues[e] = std::move(cue);
    }
    return &*point_cues[e];
  };

  Eigen::MatrixXd cost =
      Eigen::MatrixXd::Constant(static_cast<Eigen::Index>(detections.size()),
                                static_cast<Eigen::Index>(entities.size()), kForbiddenCost);
  for (std::size_t d = 0; d < detections.size(); ++d) {
    for (std::size_t e = 0; e < entities.size(); ++e) {
      if (entities[e]->class_id != detections[d].class_id) continue;
      const double score =
          AssociationScore(*entities[e], detections[d], frame, T_cw, box_points[d], point_cue(e));
      if (score < options_.min_association_score) continue;
      cost(static_cast<Eigen::Index>(d), static_cast<Eigen::Index>(e)) =
          1.0 - score + (e >= object_count ? kCandidatePenalty : 0.0);
    }
  }
  const std::vector<int> assignment = SolveAssignment(cost);

  for (std::size_t d = 0; d < detections.size(); ++d) {
    const ObjectDetection& detection = detections[d];
    const ObjectSighting sighting{frame,
                                  T_cw,
                                  detection.box,
                                  detection.truncated,
                                  BesideAMoreConfidentBoxOfItsClass(detections, d),
                                  detection.class_id,
                                  session_,
                                  std::nullopt,
                                  timestamp};
    MapObject* across_gap = nullptr;
    if (assignment[d] < 0) across_gap = CandidateAcrossGap(detection, frame, timestamp, T_cw);
    if (assignment[d] < 0 && across_gap == nullptr) {
      MapObject candidate;
      candidate.id = next_candidate_id_--;
      candidate.class_id = detection.class_id;
      candidate.sightings.Add(sighting, static_cast<std::size_t>(options_.max_sightings));
      AddPointVotes(candidate, box_points[d]);
      candidate.first_frame = candidate.last_frame = frame;
      candidate.first_timestamp = candidate.last_timestamp = timestamp;
      candidates_.emplace(candidate.id, std::move(candidate));
      ++result.new_candidates;
      continue;
    }
    MapObject& entity =
        across_gap != nullptr ? *across_gap : *entities[static_cast<std::size_t>(assignment[d])];
    entity.sightings.Add(sighting, static_cast<std::size_t>(options_.max_sightings));
    AddPointVotes(entity, box_points[d]);
    entity.last_frame = frame;
    entity.last_timestamp = timestamp;
    if (entity.id > 0) {
      result.matched.emplace_back(static_cast<int>(d), entity.id);
      observed_since_keyframe_[entity.id] = frame;
      if (!detection.truncated && Reestimate(entity, false)) geometry_changed_[entity.id] = true;
    }
  }

  for (auto it = candidates_.begin(); it != candidates_.end();) {
    MapObject& candidate = it->second;
    // A candidate waits for a box across a detector gap for candidate_gap_seconds (with 0,
    // the first frame after candidate_max_missed_frames ends it, as before).
    if (frame - candidate.last_frame > options_.candidate_max_missed_frames &&
        timestamp - candidate.last_timestamp > options_.candidate_gap_seconds) {
      it = candidates_.erase(it);
      continue;
    }
    if (candidate.last_frame == frame && Reestimate(candidate, true)) {
      if (const std::optional<ObjectId> host = JoinCandidate(candidate, frame)) {
        result.joined.push_back(*host);
        it = candidates_.erase(it);
        continue;
      }
      MapObject object = std::move(candidate);
      object.id = next_object_id_++;
      observed_since_keyframe_[object.id] = frame;
      geometry_changed_[object.id] = true;
      result.promoted.push_back(object.id);
      result.matched.emplace_back(-1, object.id);
      objects_.emplace(object.id, std::move(object));
      it = candidates_.erase(it);
      continue;
    }
    ++it;
  }
  return result;
}

bool ObjectMap::PredictsSharply(const std::vector<BoxView>& track, const Eigen::Vector3d& point,
                                const SE3& T_cw) const {
  double spread = 0.0, nearest = 180.0;
  for (const BoxView& view : track) {
    spread = std::max(spread, ParallaxDeg(point, view.T_cw, track.back().T_cw));
    nearest = std::min(nearest, ParallaxDeg(point, view.T_cw, T_cw));
  }
  return nearest <= std::max(options_.candidate_min_parallax_deg, spread);
}

MapObject* ObjectMap::CandidateAcrossGap(const ObjectDetection& detection, std::int64_t frame,
                                         double timestamp, const SE3& T_cw) {
  if (options_.candidate_gap_seconds <= 0 || detection.truncated) return nullptr;
  MapObject* best = nullptr;
  double best_fit = 0.0;
  for (auto& [id, candidate] : candidates_) {
    // Candidates with a predicted box had their chance in the assignment.
    if (candidate.class_id != detection.class_id || candidate.last_frame >= frame ||
        frame - candidate.last_frame <= options_.predicted_box_frames ||
        timestamp - candidate.last_timestamp > options_.candidate_gap_seconds) {
      continue;
    }
    // Its untruncated boxes of this session (an earlier session's place may hold another
    // object now), thinned as for a triangulation; the last one is kept.
    std::vector<BoxView> usable;
    for (const ObjectSighting& sighting : candidate.sightings) {
      if (!sighting.truncated && sighting.session == session_)
        usable.push_back({sighting.T_cw, sighting.box});
    }
    if (usable.empty()) continue;
    std::vector<BoxView> track;
    for (std::size_t index : Thinned(usable.size(), static_cast<std::size_t>(options_.max_rays)))
      track.push_back(usable[index]);
    const TrackFit fit = FitOfBoxToTrack(track, {T_cw, detection.box}, camera_,
                                         options_.min_reacquire_iou, options_.min_inlier_share);
    if (fit.iou <= best_fit || !PredictsSharply(track, fit.point, T_cw)) continue;
    best_fit = fit.iou;
    best = &candidate;
  }
  return best;
}

MapObject* ObjectMap::HostOf(MapObject& candidate) {
  const auto usable = std::count_if(candidate.sightings.begin(), candidate.sightings.end(),
                                    [](const ObjectSighting& s) { return !s.truncated; });
  if (usable == 0) return nullptr;
  // The host: its class before any other (a class flip is the rarer story), then the
  // largest share of fitting boxes.
  MapObject* host = nullptr;
  std::vector<BoxFit> host_fits;
  std::pair<bool, double> best{false, options_.min_inlier_share};
  for (auto& [id, object] : objects_) {
    if (!object.has_cuboid || SeenTogether(candidate, object, options_.duplicate_box_iou)) continue;
    const bool same_class = object.class_id == candidate.class_id;
    // As in the keyframe hygiene: another class is the same object misnamed only when
    // one session saw both; across sessions it is what was put at the old one's place.
    if (!same_class && !SeenInOneSession(candidate, object)) continue;
    std::vector<BoxFit> fits =
        FitsOfTrack(candidate, object, options_.min_reacquire_iou, R_wg_, camera_);
    const double share = static_cast<double>(std::count_if(
                             fits.begin(), fits.end(),
                             [same_class](BoxFit fit) { return CountsAsFit(fit, same_class); })) /
                         static_cast<double>(usable);
    const std::pair<bool, double> rank{same_class, share};
    if (share >= options_.min_inlier_share && rank >= best) {
      best = rank;
      host = &object;
      host_fits = std::move(fits);
    }
  }
  if (host == nullptr) return nullptr;
  for (std::size_t i = 0; i < candidate.sightings.size(); ++i) {
    if (host_fits[i] == BoxFit::kPartial) candidate.sightings[i].truncated = true;
  }
  return host;
}

void ObjectMap::MarkPartialViews(MapObject& stand_in, const MapObject& object) const {
  if (!object.has_cuboid) return;
  const std::vector<BoxFit> fits =
      FitsOfTrack(stand_in, object, options_.min_reacquire_iou, R_wg_, camera_);
  for (std::size_t i = 0; i < stand_in.sightings.size(); ++i) {
    if (fits[i] == BoxFit::kPartial) stand_in.sightings[i].truncated = true;
  }
}

std::optional<ObjectId> ObjectMap::JoinCandidate(MapObject& candidate, std::int64_t frame) {
  if (!options_.join_candidates) return std::nullopt;
  MapObject* host = HostOf(candidate);
  if (host == nullptr) return std::nullopt;
  Absorb(*host, candidate, options_.max_sightings);
  Reestimate(*host, false);
  observed_since_keyframe_[host->id] = frame;
  geometry_changed_[host->id] = true;
  return host->id;
}

void ObjectMap::JoinWaitingCandidates() {
  if (!options_.join_candidates) return;
  for (auto it = candidates_.begin(); it != candidates_.end();) {
    MapObject& candidate = it->second;
    MapObject* host = current_frame_ - candidate.last_frame > options_.candidate_max_missed_frames
                          ? HostOf(candidate)
                          : nullptr;
    if (host == nullptr) {
      ++it;
      continue;
    }
    // Its boxes are old: the host was not observed now (the OCG's evidence is the present).
    Absorb(*host, candidate, options_.max_sightings);
    Reestimate(*host, false);
    geometry_changed_[host->id] = true;
    it = candidates_.erase(it);
  }
}

void ObjectMap::StartSession(int session, std::int64_t first_frame) {
  session_ = session;
  session_first_frame_ = first_frame;
}

void ObjectMap::SetUp(const Eigen::Vector3d& up) { R_wg_ = GravityFrame(up); }

void ObjectMap::FollowMap(
    const std::function<std::optional<SE3>(std::int64_t frame)>& pose_of_frame,
    const std::function<std::optional<Eigen::Vector3d>(std::uint64_t point)>& position_of_point,
    const std::function<const Descriptor*(std::uint64_t point)>& descriptor_of_point) {
  for (auto* entities : {&objects_, &candidates_}) {
    for (auto& [id, entity] : *entities) {
      for (ObjectSighting& sighting : entity.sightings) {
        if (const std::optional<SE3> pose = pose_of_frame(sighting.frame)) sighting.T_cw = *pose;
      }
      for (auto point = entity.points.begin(); point != entity.points.end();) {
        const std::optional<Eigen::Vector3d> position = position_of_point(point->first);
        if (!position) {
          point = entity.points.erase(point);
          continue;
        }
        point->second.position = *position;
        if (descriptor_of_point) {
          if (const Descriptor* descriptor = descriptor_of_point(point->first))
            point->second.descriptor = *descriptor;
        }
        ++point;
      }
    }
  }
  for (auto& [id, object] : objects_) {
    const Cuboid before = object.cuboid;
    // The OCG hears of a change only when it matters (1% of the object's size).
    if (Reestimate(object, false) &&
        ((object.cuboid.centre - before.centre).norm() > 0.01 * before.size.maxCoeff() ||
         (object.cuboid.size - before.size).norm() > 0.01 * before.size.maxCoeff())) {
      geometry_changed_[id] = true;
    }
  }
}

std::vector<std::int64_t> ObjectMap::SightingFrames() const {
  std::vector<std::int64_t> frames;
  for (const auto* entities : {&objects_, &candidates_}) {
    for (const auto& [id, entity] : *entities) {
      for (const ObjectSighting& sighting : entity.sightings) frames.push_back(sighting.frame);
    }
  }
  std::sort(frames.begin(), frames.end());
  frames.erase(std::unique(frames.begin(), frames.end()), frames.end());
  return frames;
}

std::optional<double> ObjectMap::PointSetYaw(const MapObject& object) const {
  const std::vector<Eigen::Vector3d> point_set = ObjectPointSet(object, options_.min_point_votes);
  if (static_cast<int>(point_set.size()) < options_.yaw_min_points) return std::nullopt;
  std::vector<Eigen::Vector2d> footprint;
  for (const Eigen::Vector3d& point : point_set)
    footprint.push_back((R_wg_.transpose() * point).head<2>());
  const Rectangle2 rectangle = MinAreaRectangle(footprint);
  const double long_side = std::max(rectangle.length, rectangle.width);
  const double short_side = std::min(rectangle.length, rectangle.width);
  if (!rectangle.valid || long_side < options_.yaw_min_elongation * short_side) return std::nullopt;
  return rectangle.yaw;
}

bool ObjectMap::Reestimate(MapObject& object, bool candidate) const {
  std::vector<const ObjectSighting*> usable;
  for (const ObjectSighting& sighting : object.sightings) {
    // A candidate triangulates from its uncrowded boxes alone: the centre of a box beside a
    // more confident one of its class may be on that object (a detector's second box on
    // it, or a box sliding onto it as the view changes), and its ray then meets the others
    // in front of both (issue 18, fr3: a bottle 1.3 m short, from second boxes on
    // another).
    if (!sighting.truncated && !(candidate && sighting.crowded)) usable.push_back(&sighting);
  }
  if (candidate && static_cast<int>(usable.size()) < options_.candidate_min_observations) {
    return false;
  }
  std::vector<Ray> rays;
  std::vector<const ObjectSighting*> used;
  for (std::size_t index : Thinned(usable.size(), static_cast<std::size_t>(options_.max_rays))) {
    used.push_back(usable[index]);
    rays.push_back(PixelRay(usable[index]->box.Centre(), usable[index]->T_cw, camera_));
  }
  const RayIntersection intersection =
      IntersectRays(rays, 0.01, candidate ? options_.min_inlier_share : 0.5);
  if (!intersection.valid) return false;
  if (candidate && (intersection.inlier_count < options_.candidate_min_observations ||
                    intersection.parallax_deg < options_.candidate_min_parallax_deg)) {
    return false;
  }
  std::vector<BoxView> views;
  for (std::size_t i = 0; i < used.size(); ++i) {
    if (intersection.inliers[i]) views.push_back({used[i]->T_cw, used[i]->box});
  }
  const std::optional<double> yaw = PointSetYaw(object);
  object.cuboid = EstimateCuboid(intersection.point, views, camera_, R_wg_, yaw);
  object.yaw_from_points = yaw.has_value();
  object.has_cuboid = true;
  return true;
}

void ObjectMap::Merge(ObjectId kept, ObjectId absorbed, std::int64_t keyframe_id, double timestamp,
                      std::vector<ObjectChange>* merges) {
  MapObject& into = objects_.at(kept);
  MapObject& from = objects_.at(absorbed);
  ObjectChange change = ChangeOf("merged", keyframe_id, timestamp, from, session_);
  change.merged_into = kept;
  Absorb(into, from, options_.max_sightings);
  Reestimate(into, false);
  geometry_changed_[kept] = true;
  if (observed_since_keyframe_.count(absorbed) > 0) {
    observed_since_keyframe_[kept] =
        std::max(observed_since_keyframe_[kept], observed_since_keyframe_[absorbed]);
  }
  observed_since_keyframe_.erase(absorbed);
  geometry_changed_.erase(absorbed);
  objects_.erase(absorbed);
  changes_.push_back(change);
  if (merges != nullptr) merges->push_back(change);
}

std::vector<ObjectId> ObjectMap::RestoreRemoved(std::int64_t keyframe_id, double timestamp,
                                                std::vector<ObjectChange>* merges) {
  std::vector<ObjectId> restored;
  for (auto it = removed_.begin(); it != removed_.end();) {
    if (timestamp - it->second.removed_at > options_.restore_window) {
      it = removed_.erase(it);
      continue;
    }
    const MapObject& gone = it->second.object;
    // The object standing in for it: its class, first detected after its last sighting
    // (never seen beside it), in its place; the largest overlap wins.
    const MapObject* found = nullptr;
    double best = options_.restore_overlap;
    for (const auto& [id, object] : objects_) {
      if (!object.has_cuboid || object.class_id != gone.class_id ||
          object.first_timestamp <= gone.last_timestamp) {
        continue;
      }
      const double overlap = OverlapShare(gone.cuboid.centre, WorldExtent(gone.cuboid, R_wg_),
                                          object.cuboid.centre, WorldExtent(object.cuboid, R_wg_));
      if (overlap > best) {
        best = overlap;
        found = &object;
      }
    }
    if (found == nullptr) {
      ++it;
      continue;
    }
    const ObjectId id = gone.id, recreated_as = found->id;
    const double removed_at = it->second.removed_at;
    objects_.emplace(id, std::move(it->second.object));
    it = removed_.erase(it);
    Merge(id, recreated_as, keyframe_id, timestamp, merges);
    const MapObject& object = objects_.at(id);
    ObjectChange change = ChangeOf("restored", keyframe_id, timestamp, object, session_);
    change.recreated_as = recreated_as;
    change.removed_at = removed_at;
    changes_.push_back(change);
    restored.push_back(id);
  }
  return restored;
}

void ObjectMap::AddPresentByPoints(const SE3& T_cw, const FrameFeatureSearch* frame,
                                   KeyframeObservation* observation) {
  const double cpu_start = ThreadCpuSeconds();
  const bool searched = frame != nullptr && frame->features != nullptr;
  for (const auto& [id, object] : objects_) {
    if (observed_since_keyframe_.count(id) > 0) continue;
    if (searched) ++point_presence_stats_.objects_searched;
    if (PresentByPoints(object, last_tracked_points_, T_cw, camera_, options_, frame))
      observation->present_by_points.push_back(id);
  }
  if (!searched) return;
  ++point_presence_stats_.keyframes;
  if (!observation->present_by_points.empty()) ++point_presence_stats_.keyframes_with_presence;
  point_presence_stats_.objects_present +=
      static_cast<std::int64_t>(observation->present_by_points.size());
  point_presence_stats_.cpu_seconds += ThreadCpuSeconds() - cpu_start;
}

KeyframeObservation ObjectMap::MakeKeyframeObservation(std::int64_t keyframe_id, double timestamp,
                                                       const SE3& T_cw,
                                                       std::vector<ObjectChange>* merges,
                                                       const FrameFeatureSearch* frame) {
  // Restores first: the object found at a removed one's place is that object, and the
  // hygiene below then treats it as the one object it is.
  std::vector<ObjectChange> hygiene;
  if (merges == nullptr) merges = &hygiene;
  const std::vector<ObjectId> restored = RestoreRemoved(keyframe_id, timestamp, merges);
  JoinWaitingCandidates();
  // Hygiene: the same object mapped twice (a lost association, a box that jumped, a class
  // the detector confused) shows as two objects at one place that were never detected in
  // the same frame. The merged object takes the class most of its sightings have.
  // Merge() erases an object and so invalidates the iterators: find one pair, merge it
  // outside the loops, then look again (merges are rare).
  const auto find_pair = [&]() -> std::optional<std::pair<ObjectId, ObjectId>> {
    for (auto a = objects_.begin(); a != objects_.end(); ++a) {
      for (auto b = std::next(a); b != objects_.end(); ++b) {
        const MapObject& first = a->second;
        const MapObject& second = b->second;
        if (!first.has_cuboid || !second.has_cuboid) continue;
        const double larger = std::max(first.cuboid.size.maxCoeff(), second.cuboid.size.maxCoeff());
        const double smaller =
            std::min(first.cuboid.size.maxCoeff(), second.cuboid.size.maxCoeff());
        // One object seen under two classes has one size: of two classes, the smaller one's
        // (a cup within half a television's width of its centre is a cup beside it).
        const double reach =
            options_.merge_distance * (first.class_id == second.class_id ? larger : smaller);
        const bool one_space =
            first.class_id == second.class_id &&
            OverlapShare(first.cuboid.centre, WorldExtent(first.cuboid, R_wg_),
                         second.cuboid.centre,
                         WorldExtent(second.cuboid, R_wg_)) > options_.merge_overlap;
        bool keep_first = first.sightings.total() >= second.sightings.total();
        if (!one_space) {
          // Most pairs were detected together at some time: the cheap test first.
          if (SeenTogether(first, second, options_.duplicate_box_iou)) continue;
          // Two objects of different classes are one object the detector named twice
          // only when a session saw both. Seen in different sessions, the new one near
          // the old one's place is more likely what was put there between the visits:
          // merged, it would count as the old object seen again and reset its doubt.
          if (first.class_id != second.class_id && !SeenInOneSession(first, second)) continue;
          const auto along_rays = [&](const MapObject& stand_in, const MapObject& object) {
            return options_.merge_along_rays &&
                   SeenAsProjectionOf(stand_in, object, options_.min_reacquire_iou,
                                      options_.min_inlier_share, R_wg_, camera_);
          };
          if (along_rays(second, first)) {
            keep_first = true;
          } else if (along_rays(first, second)) {
            keep_first = false;
          } else if ((first.cuboid.centre - second.cuboid.centre).norm() > reach) {
            continue;
          }
        }
        return std::make_pair(keep_first ? first.id : second.id, keep_first ? second.id : first.id);
      }
    }
    return std::nullopt;
  };
  while (const auto pair = find_pair()) {
    MarkPartialViews(objects_.at(pair->second), objects_.at(pair->first));
    Merge(pair->first, pair->second, keyframe_id, timestamp, merges);
  }

  for (auto it = objects_.begin(); it != objects_.end();) {
    MapObject& object = it->second;
    // Crowded boxes (beside a more confident box of the class) may be the neighbour's: they
    // are no evidence that this object exists (issue 18, fr3: a bottle in mid-air, promoted from 8
    // boxes of two bottles, kept by 13 boxes beside the front bottle's).
    if (++object.keyframes_in_map < options_.probation_keyframes ||
        static_cast<int>(object.sightings.uncrowded()) >= options_.min_sightings) {
      ++it;
      continue;
    }
    const ObjectChange change = ChangeOf("dropped", keyframe_id, timestamp, object, session_);
    changes_.push_back(change);
    if (merges != nullptr) merges->push_back(change);
    observed_since_keyframe_.erase(object.id);
    geometry_changed_.erase(object.id);
    it = objects_.erase(it);
  }

  KeyframeObservation observation;
  observation.keyframe_id = keyframe_id;
  observation.timestamp = timestamp;
  observation.T_cw = T_cw;
  observation.camera = camera_;
  observation.restored = restored;
  for (const auto& [id, frame] : observed_since_keyframe_) {
    if (frame >= session_first_frame_ && objects_.count(id) > 0) observation.observed.push_back(id);
  }
  if (point_presence_) AddPresentByPoints(T_cw, frame, &observation);
  for (const auto& [id, changed] : geometry_changed_) {
    const auto it = objects_.find(id);
    if (it == objects_.end() || !it->second.has_cuboid) continue;
    ObjectGeometryUpdate& update = observation.updates[id];
    update.centroid = it->second.cuboid.centre;
    update.size = WorldExtent(it->second.cuboid, R_wg_);
    update.class_id = it->second.class_id;
  }
  for (const ObjectChange& change : *merges) observation.forgotten.push_back(change.object_id);
  observed_since_keyframe_.clear();
  geometry_changed_.clear();
  return observation;
}

void ObjectMap::Remove(const RemovalEvent& event) {
  const auto it = objects_.find(event.object_id);
  if (it == objects_.end()) return;  // merged away meanwhile
  ObjectChange change =
      ChangeOf("removed", event.keyframe_id, event.timestamp, it->second, session_);
  change.doubt = event.doubt;
  change.last_seen = it->second.last_timestamp;
  change.reason = event.reason;
  changes_.push_back(change);
  std::vector<Descriptor> appearance = ObjectAppearance(it->second, options_.min_point_votes);
  if (!appearance.empty()) removed_appearance_[event.object_id] = std::move(appearance);
  MapObject& kept = removed_in_run_[event.object_id];
  kept.id = it->second.id;
  kept.class_id = it->second.class_id;
  kept.cuboid = it->second.cuboid;
  kept.has_cuboid = it->second.has_cuboid;
  kept.sightings = it->second.sightings;
  // Only objects last seen in an earlier session are paired by their boxes and colours
  // (ForEachBetweenSessionCandidate): the others keep their counts alone, so a long run
  // that keeps seeing objects moved does not keep every removed one's boxes.
  if (!kept.sightings.empty() && kept.sightings.back().session == session_)
    kept.sightings.ForgetSightings();
  observed_since_keyframe_.erase(event.object_id);
  geometry_changed_.erase(event.object_id);
  if (restore_) removed_[event.object_id] = {std::move(it->second), event.timestamp};
  objects_.erase(it);
}

std::map<ObjectId, std::vector<Descriptor>> ObjectMap::Appearances() const {
  std::map<ObjectId, std::vector<Descriptor>> appearances = removed_appearance_;
  for (const auto& [id, object] : objects_) {
    std::vector<Descriptor> appearance = ObjectAppearance(object, options_.min_point_votes);
    if (!appearance.empty()) appearances[id] = std::move(appearance);
  }
  return appearances;
}

SeenAsClass ObjectMap::SeenAsClassThisSession() const {
  SeenAsClass seen;
  const auto add = [&](const MapObject& object) {
    bool earlier = false;
    const SightingHistory::ClassSpan* now = nullptr;
    for (const auto& [key, span] : object.sightings.spans()) {
      if (key.second != object.class_id) continue;
      if (key.first != session_) {
        earlier = true;
      } else {
        now = &span;
      }
    }
    if (now == nullptr) return;
    if (!earlier) seen.first[object.id] = now->first_timestamp;
    seen.last[object.id] = now->last_timestamp;
  };
  for (const auto& [id, object] : objects_) add(object);
  for (const auto& [id, object] : removed_in_run_) add(object);
  return seen;
}

template <typename Visit>
void ObjectMap::ForEachBetweenSessionCandidate(Visit&& visit) const {
  if (session_ == 0) return;
  for (const auto& [id, object] : removed_in_run_) {
    if (!object.sightings.empty() && object.sightings.back().session < session_)
      visit(object, true);
  }
  for (const auto& [id, object] : objects_) {
    if (!object.sightings.empty() && object.sightings.front().session == session_)
      visit(object, false);
  }
}

std::map<ObjectId, std::vector<Descriptor>> ObjectMap::BoxAppearances(
    const KeyframeFeatureMap& keyframes, const BoxAppearanceOptions& options,
    int max_distance) const {
  options.Check();
  std::vector<const KeyframeFeatures*> earlier, now;
  for (const auto& [frame, keyframe] : keyframes)
    (frame < session_first_frame_ ? earlier : now).push_back(&keyframe);
  std::map<ObjectId, std::vector<Descriptor>> appearances;
  const auto add = [&](const MapObject& object,
                       const std::vector<const KeyframeFeatures*>& absent) {
    if (!object.has_cuboid) return;
    std::vector<FrameBox> boxes;
    for (const ObjectSighting& sighting : object.sightings)
      boxes.push_back({sighting.frame, sighting.box});
    std::vector<Descriptor> descriptors = WithoutBackground(
        BoxDescriptors(boxes, object.cuboid, R_wg_, keyframes, options),
        options.place_background ? PlaceDescriptors(object.cuboid, R_wg_, camera_, absent, options)
                                 : std::vector<Descriptor>{},
        max_distance);
    if (!descriptors.empty()) appearances[object.id] = std::move(descriptors);
  };
  ForEachBetweenSessionCandidate(
      [&](const MapObject& object, bool removed) { add(object, removed ? now : earlier); });
  return appearances;
}

int ObjectMap::SetSightingColours(std::int64_t frame, const cv::Mat& bgr,
                                  const ColourSignatureOptions& options) {
  options.Check();
  int set = 0;
  const auto set_in = [&](MapObject& object) {
    for (ObjectSighting& sighting : object.sightings) {
      if (sighting.frame != frame) continue;
      sighting.colour = BoxColourSignature(bgr, sighting.box, options);
      if (sighting.colour) ++set;
    }
  };
  for (auto& [id, object] : objects_) set_in(object);
  for (auto& [id, object] : removed_in_run_) set_in(object);
  return set;
}

std::map<ObjectId, ColourHistogram> ObjectMap::ColourAppearances(int min_signatures) const {
  std::map<ObjectId, ColourHistogram> colours;
  ForEachBetweenSessionCandidate([&](const MapObject& object, bool /*removed*/) {
    std::vector<ColourHistogram> signatures;
    for (const ObjectSighting& sighting : object.sightings) {
      if (sighting.colour) signatures.push_back(*sighting.colour);
    }
    if (static_cast<int>(signatures.size()) < min_signatures) return;
    if (std::optional<ColourHistogram> mean = MeanColour(signatures)) colours[object.id] = *mean;
  });
  return colours;
}

std::string ObjectsJson(const ObjectMap& map, const std::vector<ObjectStatus>& states) {
  std::map<ObjectId, const ObjectStatus*> by_id;
  for (const ObjectStatus& status : states) by_id[status.id] = &status;
  nlohmann::json objects = nlohmann::json::array();
  for (const auto& [id, object] : map.objects()) {
    // Sessions (map files): the first and the last that saw it.
    const auto [first_session, last_session] = object.sightings.SessionRange();
    nlohmann::json entry = {
        {"id", id},
        {"class_id", object.class_id},
        {"class", CocoClassName(object.class_id)},
        {"cuboid", CuboidJson(object.cuboid)},
        {"yaw_from", object.yaw_from_points ? "map points" : "boxes"},
        {"observations", object.sightings.total()},
        {"map_points", ObjectPointSet(object, map.options().min_point_votes).size()},
        {"first_seen", object.first_timestamp},
        {"last_seen", object.last_timestamp},
        {"first_session", first_session},
        {"last_session", last_session},
        {"state", nullptr},
        {"doubt", nullptr}};
    const auto status = by_id.find(id);
    if (status != by_id.end()) {
      entry["state"] = static_cast<int>(status->second->state);
      entry["doubt"] = status->second->doubt;
    }
    objects.push_back(entry);
  }
  const Eigen::Vector3d up = map.gravity_frame().col(2);
  return nlohmann::json({{"format", "ocg-objects"},
                         {"version", 1},
                         {"up", VectorJson(up)},
                         {"objects", objects}})
             .dump(1) +
         "\n";
}

std::string ObjectChangesJson(const std::vector<ObjectChange>& changes) {
  nlohmann::json list = nlohmann::json::array();
  for (const ObjectChange& change : changes) {
    nlohmann::json entry = {{"type", change.type},
                            {"session", change.session},
                            {"keyframe", change.keyframe_id},
                            {"timestamp", change.timestamp},
                            {"object_id", change.object_id},
                            {"class_id", change.class_id},
                            {"class", CocoClassName(change.class_id)},
                            {"centroid", VectorJson(change.cuboid.centre)},
                            {"cuboid", CuboidJson(change.cuboid)},
                            {"observations", change.sightings}};
    if (change.type == "removed") {
      entry["doubt"] = change.doubt;
      entry["last_seen"] = change.last_seen;
      entry["reason"] = change.reason.empty() ? "outlier" : change.reason;
    } else if (change.type == "merged") {
      entry["merged_into"] = change.merged_into;
      entry["reason"] = "duplicate";
    } else if (change.type == "restored") {
      entry["recreated_as"] = change.recreated_as;
      entry["removed_at"] = change.removed_at;
      entry["reason"] = "detected again at its place";
    } else {
      entry["reason"] = "too few sightings";
    }
    list.push_back(entry);
  }
  return nlohmann::json({{"changes", list}}).dump(1) + "\n";
}

}  // namespace ocg
