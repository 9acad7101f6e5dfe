#include "ocg/objects/object_map.h"

#include <algorithm>
#include <optional>
#include <set>

#include "ocg/objects/candidate_tracker.h"
#include "ocg/objects/detection_association.h"
#include "ocg/objects/map_hygiene.h"
#include "ocg/objects/object_restore.h"

namespace ocg {

ObjectMap::ObjectMap(ObjectsOptions options, PinholeCamera camera)
    : options_(std::move(options)), camera_(camera), R_wg_(GravityFrame(options_.up)) {
  options_.Check();
  SetEvidence(EvidenceProvidersFor(OcgModes{}));
}

void ObjectMap::SetEvidence(std::vector<std::unique_ptr<EvidenceProvider>> providers) {
  evidence_ = std::move(providers);
  point_evidence_ = nullptr;
  for (const auto& provider : evidence_) {
    if (const auto* points = dynamic_cast<const PointPresenceEvidence*>(provider.get()))
      point_evidence_ = points;
  }
}

const ObjectMap::PointPresenceStats& ObjectMap::point_presence_stats() const {
  static const PointPresenceStats kNone;
  return point_evidence_ != nullptr ? point_evidence_->stats() : kNone;
}

FrameAssociation ObjectMap::AddFrame(std::int64_t frame, double timestamp, const SE3& T_cw,
                                     const std::vector<ObjectDetection>& detections,
                                     const std::vector<PointObservation>* points) {
  current_frame_ = frame;
  for (const auto& provider : evidence_) provider->AddFrame(points);
  FrameAssociation result;
  result.detections = detections;
  std::vector<MapObject*> entities;
  for (auto& entry : objects_) entities.push_back(&entry.second);
  const std::size_t object_count = entities.size();
  for (auto& entry : candidates_) entities.push_back(&entry.second);
  std::vector<std::vector<const PointObservation*>> box_points(detections.size());
  if (points != nullptr) {
    for (std::size_t d = 0; d < detections.size(); ++d)
      box_points[d] = PointsInBox(*points, detections[d].box, options_.point_box_shrink);
  }
  const ObjectMapContext context = Context();
  const std::vector<int> assignment =
      AssociateDetections(entities, object_count, detections, box_points, points != nullptr, frame,
                          T_cw, session_, context);
  CandidateTracker candidates(&candidates_, &next_candidate_id_, context);
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
    MapObject* entity = assignment[d] >= 0
                            ? entities[static_cast<std::size_t>(assignment[d])]
                            : candidates.AcrossGap(detection, frame, timestamp, T_cw, session_);
    if (entity == nullptr) {
      const ObjectId started = next_candidate_id_;
      candidates.Start(sighting, box_points[d]);
      PointsJoined(candidates_.at(started), box_points[d]);
      ++result.new_candidates;
      continue;
    }
    entity->sightings.Add(sighting, static_cast<std::size_t>(options_.max_sightings));
    AddPointVotes(*entity, box_points[d]);
    PointsJoined(*entity, box_points[d]);
    BoundPoints(*entity, options_.max_object_points);
    entity->last_frame = frame;
    entity->last_timestamp = timestamp;
    if (entity->id > 0) {
      result.matched.emplace_back(static_cast<int>(d), entity->id);
      observed_since_keyframe_[entity->id] = frame;
      if (!NoteChanges(*entity, 1)) continue;  // Objects.reestimate_share
      if (!detection.truncated && Estimate(*entity)) {
        geometry_changed_[entity->id] = true;
        unestimated_.erase(entity->id);
      } else {
        unestimated_.insert(entity->id);  // its votes or sightings changed: see FollowMap
      }
    }
  }
  candidates.Update(frame, timestamp, [&](MapObject& candidate) {
    Promote(candidate, frame, &result);
    return true;
  });
  return result;
}

void ObjectMap::Promote(MapObject& candidate, std::int64_t frame, FrameAssociation* result) {
  if (const std::optional<ObjectId> host = JoinCandidate(candidate, frame)) {
    result->joined.push_back(*host);
    return;
  }
  MapObject object = std::move(candidate);
  object.id = next_object_id_++;
  IndexEntity(object);  // its counted points under its new id
  observed_since_keyframe_[object.id] = frame;
  geometry_changed_[object.id] = true;
  result->promoted.push_back(object.id);
  result->matched.emplace_back(-1, object.id);
  objects_.emplace(object.id, std::move(object));
}

std::optional<ObjectId> ObjectMap::JoinCandidate(MapObject& candidate, std::int64_t frame) {
  if (!options_.join_candidates) return std::nullopt;
  MapObject* host = HostOf(candidate, objects_, Context());
  if (host == nullptr) return std::nullopt;
  AbsorbInto(*host, candidate);
  Estimate(*host);
  observed_since_keyframe_[host->id] = frame;
  geometry_changed_[host->id] = true;
  return host->id;
}

void ObjectMap::JoinWaitingCandidates() {
  if (!options_.join_candidates) return;
  for (auto it = candidates_.begin(); it != candidates_.end();) {
    MapObject& candidate = it->second;
    MapObject* host = current_frame_ - candidate.last_frame > options_.candidate_max_missed_frames
                          ? HostOf(candidate, objects_, Context())
                          : nullptr;
    if (host == nullptr) {
      ++it;
      continue;
    }
    // Its boxes are old: the host was not observed now (the OCG's evidence is the present).
    AbsorbInto(*host, candidate);
    Estimate(*host);
    geometry_changed_[host->id] = true;
    it = candidates_.erase(it);
  }
}

void ObjectMap::AbsorbInto(MapObject& into, const MapObject& from) {
  // The points the joined votes make counted in into: FollowMap had not followed into's
  // copy (its position may be old), so it reads them at its next call, and those kept
  // enter the index under into's id (the points into counted before are there already; a
  // repeated id is pruned when read).
  std::vector<std::uint64_t> counted;
  for (const auto& [id, point] : from.points) {
    const auto kept = into.points.find(id);
    const int before = kept == into.points.end() ? 0 : kept->second.votes;
    if (before < options_.min_point_votes && before + point.votes >= options_.min_point_votes)
      counted.push_back(id);
  }
  Absorb(into, from, options_.max_sightings);
  BoundPoints(into, options_.max_object_points);
  fresh_points_.insert(fresh_points_.end(), counted.begin(), counted.end());
  if (!point_index_valid_) return;
  for (const std::uint64_t id : counted) {
    if (into.points.count(id) > 0) point_entities_[id].push_back(into.id);
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
    const std::function<const Descriptor*(std::uint64_t point)>& descriptor_of_point,
    const std::vector<std::int64_t>* frames, const std::vector<ChangedPoint>* changed_points) {
  // Incremental (a keyframe's changes): the objects whose sightings or points moved are
  // estimated again, the others only once the up direction turned by more than
  // kUpTurnForAll since they all were.
  const bool incremental = frames != nullptr;
  // The objects whose inputs moved, with how many moved (sightings re-posed, points).
  std::map<ObjectId, int> moved;
  // A point moves the entity when ObjectPointIds may count it (enough votes, within reach
  // of the cuboid's centre before or after). The point takes the map point's state:
  // position (null: gone from the map, and from the entity) and descriptor (null: keeps
  // its own).
  const auto follow_point = [&](MapObject& entity, ObjectPoints::const_iterator point,
                                const Eigen::Vector3d* position, const Descriptor* descriptor) {
    const double reach = entity.cuboid.size.maxCoeff();
    const auto counts = [&](const ObjectPoint& kept, const Eigen::Vector3d& at) {
      return kept.votes >= options_.min_point_votes &&
             (!entity.has_cuboid || (at - entity.cuboid.centre).norm() <= reach);
    };
    if (position == nullptr) {
      const bool entity_moved = counts(point->second, point->second.position);
      entity.points.erase(point);
      return entity_moved;
    }
    if (descriptor != nullptr) entity.points.SetDescriptor(point, *descriptor);
    // Incremental: a point that moved less than Objects.follow_tolerance keeps the
    // position the object was estimated with (the copy lags the map by less than that).
    const double shift = (*position - point->second.position).norm();
    if (incremental && shift <= options_.follow_tolerance) return false;
    const bool entity_moved = shift > 0.0 && (counts(point->second, point->second.position) ||
                                              counts(point->second, *position));
    entity.points.Move(point, *position);
    return entity_moved;
  };
  // A point's state by the callbacks.
  const auto follow_point_by_id = [&](MapObject& entity, ObjectPoints::const_iterator point) {
    const std::optional<Eigen::Vector3d> position = position_of_point(point->first);
    const Descriptor* descriptor =
        position && descriptor_of_point ? descriptor_of_point(point->first) : nullptr;
    return follow_point(entity, point, position ? &*position : nullptr, descriptor);
  };
  for (auto* entities : {&objects_, &candidates_}) {
    for (auto& [id, entity] : *entities) {
      int entity_moved = 0;
      if (frames == nullptr) {
        for (ObjectSighting& sighting : entity.sightings) {
          if (const std::optional<SE3> pose = pose_of_frame(sighting.frame)) sighting.T_cw = *pose;
        }
      } else {
        entity.sightings.VisitFrames(*frames, [&](std::int64_t frame, auto first, auto last) {
          const std::optional<SE3> pose = pose_of_frame(frame);
          if (!pose) return;
          for (auto sighting = first; sighting != last; ++sighting) {
            sighting->T_cw = *pose;
            ++entity_moved;
          }
        });
      }
      if (changed_points == nullptr) {
        for (auto point = entity.points.begin(); point != entity.points.end();) {
          const auto next = std::next(point);
          if (follow_point_by_id(entity, point)) ++entity_moved;
          point = next;
        }
      }
      if (entities == &objects_ && entity_moved > 0) moved[id] += entity_moved;
    }
  }
  if (changed_points != nullptr) {
    // Only the points that changed in the map, and those an entity counts since the last
    // call (their map point may have moved since their last vote), found through the
    // point -> entities index (counted points only).
    if (!point_index_valid_) IndexPoints();
    // The changed points with their states, then the fresh ones not among them (in id
    // order, each once, as the changed ones are).
    std::vector<ChangedPoint> visit = *changed_points;
    std::sort(fresh_points_.begin(), fresh_points_.end());
    fresh_points_.erase(std::unique(fresh_points_.begin(), fresh_points_.end()),
                        fresh_points_.end());
    std::vector<std::optional<Eigen::Vector3d>> fresh_positions;
    fresh_positions.reserve(fresh_points_.size());  // no reallocation: visit points into it
    for (const std::uint64_t id : fresh_points_) {
      const auto changed = std::lower_bound(
          changed_points->begin(), changed_points->end(), id,
          [](const ChangedPoint& point, std::uint64_t key) { return point.id < key; });
      if (changed != changed_points->end() && changed->id == id) continue;
      fresh_positions.push_back(position_of_point(id));
      const std::optional<Eigen::Vector3d>& position = fresh_positions.back();
      visit.push_back({id, position ? &*position : nullptr,
                       position && descriptor_of_point ? descriptor_of_point(id) : nullptr});
    }
    std::sort(visit.begin(), visit.end(),
              [](const ChangedPoint& a, const ChangedPoint& b) { return a.id < b.id; });
    for (const ChangedPoint& changed : visit) {
      const auto indexed = point_entities_.find(changed.id);
      if (indexed == point_entities_.end()) continue;
      std::vector<ObjectId>& ids = indexed->second;
      std::sort(ids.begin(), ids.end());
      ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
      std::vector<ObjectId> holding;
      for (const ObjectId id : ids) {
        auto& entities = id > 0 ? objects_ : candidates_;
        const auto entity = entities.find(id);
        if (entity == entities.end()) continue;  // merged, dropped, removed or promoted
        const auto point = entity->second.points.find(changed.id);
        if (point == entity->second.points.end()) continue;  // bounded away
        if (follow_point(entity->second, point, changed.position, changed.descriptor) && id > 0)
          ++moved[id];
        if (changed.position != nullptr) holding.push_back(id);  // else it left the entity
      }
      if (holding.empty()) {
        point_entities_.erase(indexed);
      } else {
        ids = std::move(holding);
      }
    }
  }
  fresh_points_.clear();
  const Eigen::Vector3d up = R_wg_.col(2);
  const bool all = !incremental || !up_at_estimates_ ||
                   std::acos(std::clamp(up.dot(*up_at_estimates_), -1.0, 1.0)) > kUpTurnForAll;
  if (all) up_at_estimates_ = up;
  for (auto& [id, object] : objects_) {
    if (!all && unestimated_.count(id) == 0) {
      const auto moves = moved.find(id);
      if (moves == moved.end() || !NoteChanges(object, moves->second)) continue;
    }
    const Cuboid before = object.cuboid;
    // The OCG hears of a change only when it matters (1% of the object's size).
    if (Estimate(object) &&
        ((object.cuboid.centre - before.centre).norm() > 0.01 * before.size.maxCoeff() ||
         (object.cuboid.size - before.size).norm() > 0.01 * before.size.maxCoeff())) {
      geometry_changed_[id] = true;
    }
  }
  unestimated_.clear();
}

bool ObjectMap::Estimate(MapObject& object) {
  object.changes_since_estimate = 0;
  object.sightings_at_estimate = object.sightings.size();
  return Reestimate(object, false, Context());
}

bool ObjectMap::NoteChanges(MapObject& object, int changes) const {
  object.changes_since_estimate += changes;
  return object.changes_since_estimate > 0 &&
         object.changes_since_estimate >=
             options_.reestimate_share * static_cast<double>(object.sightings_at_estimate);
}

void ObjectMap::EstimatePending() {
  for (auto& [id, object] : objects_) {
    if (object.changes_since_estimate > 0 && Estimate(object)) geometry_changed_[id] = true;
  }
}

void ObjectMap::IndexPoints() {
  point_entities_.clear();
  for (const auto* entities : {&objects_, &candidates_}) {
    for (const auto& [id, entity] : *entities) {
      for (const auto& [point, kept] : entity.points) {
        if (kept.votes >= options_.min_point_votes) point_entities_[point].push_back(id);
      }
    }
  }
  point_index_valid_ = true;
}

void ObjectMap::IndexEntity(const MapObject& entity) {
  if (!point_index_valid_) return;
  for (const auto& [point, kept] : entity.points) {
    if (kept.votes >= options_.min_point_votes) point_entities_[point].push_back(entity.id);
  }
}

void ObjectMap::PointsJoined(const MapObject& entity,
                             const std::vector<const PointObservation*>& box_points) {
  for (const PointObservation* point : box_points) {
    const auto kept = entity.points.find(point->id);
    // Counted from this vote on (AddPointVotes adds one): before, FollowMap need not
    // follow it.
    if (kept == entity.points.end() || kept->second.votes != options_.min_point_votes) continue;
    fresh_points_.push_back(point->id);
    if (point_index_valid_) point_entities_[point->id].push_back(entity.id);
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
  MergeDuplicates(keyframe_id, timestamp, merges);
  DropUnsupported(keyframe_id, timestamp, merges);

  KeyframeObservation observation;
  observation.keyframe_id = keyframe_id;
  observation.timestamp = timestamp;
  observation.T_cw = T_cw;
  observation.camera = camera_;
  observation.restored = restored;
  const ObjectMapContext context = Context();
  const KeyframeEvidence evidence{
      objects_, observed_since_keyframe_, geometry_changed_, session_first_frame_, T_cw, frame,
      context};
  for (const auto& provider : evidence_) provider->Fill(evidence, &observation);
  for (const ObjectChange& change : *merges) observation.forgotten.push_back(change.object_id);
  observed_since_keyframe_.clear();
  geometry_changed_.clear();
  return observation;
}

void ObjectMap::MergeDuplicates(std::int64_t keyframe_id, double timestamp,
                                std::vector<ObjectChange>* merges) {
  // Merge() erases an object and so invalidates the iterators: find one pair, merge it,
  // then look again (merges are rare).
  while (const auto pair = FindDuplicate(objects_, Context())) {
    MarkPartialViews(objects_.at(pair->second), objects_.at(pair->first), Context());
    Merge(pair->first, pair->second, keyframe_id, timestamp, merges);
  }
}

void ObjectMap::DropUnsupported(std::int64_t keyframe_id, double timestamp,
                                std::vector<ObjectChange>* merges) {
  for (auto it = objects_.begin(); it != objects_.end();) {
    MapObject& object = it->second;
    ++object.keyframes_in_map;
    if (!TooLittleEvidence(object, options_)) {
      ++it;
      continue;
    }
    const ObjectChange change = ChangeOf("dropped", keyframe_id, timestamp, object, session_);
    changes_.push_back(change);
    merges->push_back(change);
    observed_since_keyframe_.erase(object.id);
    geometry_changed_.erase(object.id);
    it = objects_.erase(it);
  }
}

void ObjectMap::Merge(ObjectId kept, ObjectId absorbed, std::int64_t keyframe_id, double timestamp,
                      std::vector<ObjectChange>* merges) {
  MapObject& into = objects_.at(kept);
  MapObject& from = objects_.at(absorbed);
  ObjectChange change = ChangeOf("merged", keyframe_id, timestamp, from, session_);
  change.merged_into = kept;
  AbsorbInto(into, from);
  Estimate(into);
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
    const MapObject* found = StandInFor(it->second.object, objects_, Context());
    if (found == nullptr) {
      ++it;
      continue;
    }
    const ObjectId id = it->second.object.id, recreated_as = found->id;
    const double removed_at = it->second.removed_at;
    // Its points missed the map's changes while it was away: FollowMap reads them all.
    for (const auto& [point, kept] : it->second.object.points) fresh_points_.push_back(point);
    IndexEntity(it->second.object);  // its entries were pruned while it was away
    objects_.emplace(id, std::move(it->second.object));
    it = removed_.erase(it);
    Merge(id, recreated_as, keyframe_id, timestamp, merges);
    ObjectChange change = ChangeOf("restored", keyframe_id, timestamp, objects_.at(id), session_);
    change.recreated_as = recreated_as;
    change.removed_at = removed_at;
    changes_.push_back(change);
    restored.push_back(id);
  }
  return restored;
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
  // Only objects last seen in an earlier session are paired by their boxes
  // (ForEachBetweenSessionCandidate): the others keep their counts and their coloured
  // sightings alone, so a long run that keeps seeing objects moved does not keep every
  // removed one's boxes.
  if (!kept.sightings.empty() && kept.sightings.back().session == session_)
    kept.sightings.ForgetSightings(session_);
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

SessionObjects ObjectMap::SessionView() const {
  return {objects_, removed_in_run_, session_, session_first_frame_};
}

SeenAsClass ObjectMap::SeenAsClassThisSession() const { return SeenAsClassIn(SessionView()); }

std::map<ObjectId, std::vector<Descriptor>> ObjectMap::BoxAppearances(
    const KeyframeFeatureMap& keyframes, const BoxAppearanceOptions& options,
    int max_distance) const {
  return BoxAppearancesOf(SessionView(), keyframes, options, max_distance, Context());
}

int ObjectMap::SetSightingColours(std::int64_t frame, const cv::Mat& bgr,
                                  const ColourSignatureOptions& options) {
  options.Check();
  int set = 0;
  for (auto& [id, object] : objects_) set += SetSightingColoursOf(object, frame, bgr, options);
  for (auto& [id, object] : removed_in_run_)
    set += SetSightingColoursOf(object, frame, bgr, options);
  // A candidate's sightings too: the object it becomes keeps them, and a newcomer's colours
  // then go back to its first keyframes, not only to those after it became an object.
  for (auto& [id, candidate] : candidates_)
    set += SetSightingColoursOf(candidate, frame, bgr, options);
  return set;
}

std::map<ObjectId, ColourHistogram> ObjectMap::ColourAppearances(int min_signatures) const {
  return ColourAppearancesOf(SessionView(), min_signatures);
}

}  // namespace ocg
