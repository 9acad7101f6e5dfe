#pragma once
// The object map: detections associated frame by frame to map objects and candidates,
// candidates promoted once they are triangulated, duplicates merged, and removals of the
// OCG applied. Feeds the OCG one KeyframeObservation per keyframe.
//
// The map holds the state (objects, candidates, what changed since the last keyframe, the
// change log) and runs the steps; each rule is a part of its own: association
// (detection_association.h), candidates (candidate_tracker.h), hygiene (map_hygiene.h),
// restore (object_restore.h), the session pairing's appearances (session_appearance.h) and
// the evidence sources, one provider each (evidence_provider.h, point_evidence.h).
//
// Not thread-safe: ObjectMapper serialises every call (see object_mapper.h).

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

#include "ocg/core/camera.h"
#include "ocg/core/lie.h"
#include "ocg/features/descriptor.h"
#include "ocg/objects/box.h"
#include "ocg/objects/box_appearance.h"
#include "ocg/objects/colour_signature.h"
#include "ocg/objects/evidence_provider.h"
#include "ocg/objects/map_cues.h"
#include "ocg/objects/map_diff.h"
#include "ocg/objects/map_object.h"
#include "ocg/objects/object_change.h"
#include "ocg/objects/objects_options.h"
#include "ocg/objects/point_evidence.h"
#include "ocg/objects/point_presence.h"
#include "ocg/objects/session_appearance.h"
#include "ocg/ocg/change_detector.h"
#include "ocg/ocg/observation.h"

namespace ocg {

struct MapFileAccess;  // map files (src/app/object_map_file.cc) save and restore the state

// An object as viewers and reports show it: live or removed, with its OCG state.
struct ObjectView {
  ObjectId id = 0;
  int class_id = 0;
  Cuboid cuboid;
  int state = 0;         // OCG state 1-4; 0 before the object's first keyframe
  bool removed = false;  // left the map (the change log's last cuboid)
};

struct FrameAssociation {
  std::vector<ObjectDetection> detections;  // the frame's detections after filtering
  // (detection index, object id) for map objects; candidates are not listed.
  std::vector<std::pair<int, ObjectId>> matched;
  int new_candidates = 0;
  std::vector<ObjectId> promoted;  // candidates that became map objects in this frame
  // Candidates that turned out to be a map object seen again and joined it in this frame
  // (Objects.join_candidates): the ids of those map objects.
  std::vector<ObjectId> joined;
};

class ObjectMap {
 public:
  ObjectMap(ObjectsOptions options, PinholeCamera camera);

  // Associates this frame's (filtered) detections, updates the objects that got one,
  // starts, promotes and drops candidates. points: the SLAM map points tracked in the
  // frame, when there is a SLAM map; they add two association cues (the share of the
  // box's points that are the object's, and the share inside its point set's bounds).
  FrameAssociation AddFrame(std::int64_t frame, double timestamp, const SE3& T_cw,
                            const std::vector<ObjectDetection>& detections,
                            const std::vector<PointObservation>* points = nullptr);

  // A new up direction (the supporting plane's normal): cuboids are re-estimated at
  // the next UpdatePoses() or sighting.
  void SetUp(const Eigen::Vector3d& up);
  // Bundle adjustment or a loop correction moved the cameras and the points: every
  // sighting takes its frame's current pose (frames without one keep theirs), every
  // object point its map point's position (points gone from the map, culled or fused
  // into another, leave the object), and the objects are re-estimated.
  // descriptor_of_point (optional; null result: none known) refreshes the points'
  // descriptors.
  // pose_of_frame is asked for SightingFrames() alone; with frames (sorted, each once: the
  // only frames pose_of_frame knows) only for those, found in each object's sightings by
  // bisection, so a keyframe that moved a few frames visits a few sightings.
  // changed_points (with frames): the map points that changed, with their state now
  // (sorted by id, each once); only those are followed, and the points that joined an
  // entity since the last call, whose state position_of_point and descriptor_of_point
  // give.
  struct ChangedPoint {
    std::uint64_t id = 0;
    const Eigen::Vector3d* position = nullptr;  // world; null: the point is gone
    const Descriptor* descriptor = nullptr;     // null: not known
  };
  void FollowMap(
      const std::function<std::optional<SE3>(std::int64_t frame)>& pose_of_frame,
      const std::function<std::optional<Eigen::Vector3d>(std::uint64_t point)>& position_of_point,
      const std::function<const Descriptor*(std::uint64_t point)>& descriptor_of_point = {},
      const std::vector<std::int64_t>* frames = nullptr,
      const std::vector<ChangedPoint>* changed_points = nullptr);

  // The frames of the sightings the objects and candidates keep, sorted, each once.
  std::vector<std::int64_t> SightingFrames() const;

  // The OCG's input for a keyframe at the last added frame: the map objects detected in
  // any frame since the previous keyframe, with the geometry of those that changed.
  // Hygiene first: merges duplicates and drops objects with too few sightings (returned
  // in merges; the OCG is told to forget them through the observation).
  // frame (SLAM runs, OCG.mode "points"): the keyframe's features, searched for the
  // points of the objects not detected (PresentByPoints).
  KeyframeObservation MakeKeyframeObservation(std::int64_t keyframe_id, double timestamp,
                                              const SE3& T_cw, std::vector<ObjectChange>* merges,
                                              const FrameFeatureSearch* frame = nullptr);

  // The OCG declared the object an outlier: it leaves the map and enters the change log
  // (with restore on, it is kept aside for Objects.restore_window seconds).
  void Remove(const RemovalEvent& event);
  // OCG.mode "restore": removed objects found again at their place are brought back at
  // the next keyframe (MakeKeyframeObservation: a "restored" change, the object found
  // there merged into it, the OCG told through observation.restored).
  void SetRestore(bool restore) { restore_ = restore; }
  // The evidence sources asked at each keyframe, in order (EvidenceProvidersFor the OCG's
  // modes); without a call: "observed" and "updates" alone.
  void SetEvidence(std::vector<std::unique_ptr<EvidenceProvider>> providers);
  // OCG.mode "points": the evidence's counts so far (all 0 without it).
  using PointPresenceStats = ocg::PointPresenceStats;
  const PointPresenceStats& point_presence_stats() const;

  const std::map<ObjectId, MapObject>& objects() const { return objects_; }
  std::size_t CandidateCount() const { return candidates_.size(); }
  const std::vector<ObjectChange>& changes() const { return changes_; }
  // ObjectAppearance of every live object and of every object removed in this run (as it
  // was when removed; the appearance of removals made by the runs that wrote a loaded map
  // file is not kept), by id. Objects without descriptors are left out.
  std::map<ObjectId, std::vector<Descriptor>> Appearances() const;
  // When this session saw each live object and each object removed in this run as its
  // class (SeenAsClass, map_diff.h); the in-session move pairing of changes.json reads it.
  SeenAsClass SeenAsClassThisSession() const;
  // The box appearance (box_appearance.h) of the objects a between-session pairing weighs,
  // by id: those removed in this run and last seen in an earlier session, and the live
  // ones seen in this session alone (a later session only). Each without what its place
  // shows in the other sessions' keyframes (earlier sessions' of an object new here, this
  // session's of a removed one): there the place held something else. keyframes: every
  // keyframe of every session, with frames numbered as the sightings. Objects with no
  // descriptor left are left out.
  std::map<ObjectId, std::vector<Descriptor>> BoxAppearances(const KeyframeFeatureMap& keyframes,
                                                             const BoxAppearanceOptions& options,
                                                             int max_distance) const;
  // Sets the colour signature (BoxColourSignature of bgr, the image of frame) of every
  // sighting made at frame, of the live objects, the candidates and those removed in this
  // run.
  // Returns how many were given one.
  int SetSightingColours(std::int64_t frame, const cv::Mat& bgr,
                         const ColourSignatureOptions& options);
  // The mean colour (MeanColour) of the live objects and of those removed in this run, by
  // id, each from its sightings that have a colour (an object removed in this run keeps
  // this session's: SightingHistory::ForgetSightings); objects with fewer than
  // min_signatures of them are left out.
  std::map<ObjectId, ColourHistogram> ColourAppearances(int min_signatures) const;
  const ObjectsOptions& options() const { return options_; }
  const PinholeCamera& camera() const { return camera_; }
  const Eigen::Matrix3d& gravity_frame() const { return R_wg_; }
  // The session whose frames AddFrame() is given from now on (0 in a run that loaded no
  // map file), starting at first_frame. Detections of earlier frames not yet handed to
  // the OCG were made in the earlier session, after its last keyframe: the next keyframe,
  // days later elsewhere, does not report them as observed (it did, and so reset the
  // doubt of objects moved between the sessions).
  void StartSession(int session, std::int64_t first_frame);
  // Estimates every object with changes still waiting for their share
  // (Objects.reestimate_share): called before a run's outputs are read.
  void EstimatePending();

 private:
  friend struct MapFileAccess;
  ObjectMapContext Context() const { return {options_, camera_, R_wg_}; }
  // Reestimate() of a map object (not a candidate); its changes are counted from 0 again.
  bool Estimate(MapObject& object);
  // Counts changes more changed inputs of object; true once it is due for an estimate
  // (Objects.reestimate_share).
  bool NoteChanges(MapObject& object, int changes) const;
  SessionObjects SessionView() const;
  // A candidate whose rays met in frame: joins the map object it is (JoinCandidate) or
  // becomes one.
  void Promote(MapObject& candidate, std::int64_t frame, FrameAssociation* result);
  // A candidate about to be promoted that is a map object seen again (its boxes fit the
  // object's projection: Objects.join_candidates) joins it; returns the object's id.
  std::optional<ObjectId> JoinCandidate(MapObject& candidate, std::int64_t frame);
  // Candidates waiting for a box across a gap (not detected for more than
  // candidate_max_missed_frames) whose boxes fit a map object's projection join it: the
  // boxes a hard object got before it was mapped (issue 18: a vase found in runs seconds
  // apart, mapped from a later run, then dropped for too few sightings).
  void JoinWaitingCandidates();
  // Hygiene at a keyframe: merges every pair FindDuplicate finds; drops the objects with
  // too little evidence (TooLittleEvidence). Each change into merges.
  void MergeDuplicates(std::int64_t keyframe_id, double timestamp,
                       std::vector<ObjectChange>* merges);
  void DropUnsupported(std::int64_t keyframe_id, double timestamp,
                       std::vector<ObjectChange>* merges);
  void Merge(ObjectId kept, ObjectId absorbed, std::int64_t keyframe_id, double timestamp,
             std::vector<ObjectChange>* merges);
  // Brings back the removed objects a map object now stands in for; returns their ids.
  std::vector<ObjectId> RestoreRemoved(std::int64_t keyframe_id, double timestamp,
                                       std::vector<ObjectChange>* merges);

  ObjectsOptions options_;
  PinholeCamera camera_;
  Eigen::Matrix3d R_wg_;
  // FollowMap's incremental mode: the up direction every object was last estimated with
  // (none: not yet), and how far (radians) up may turn before all are estimated again.
  std::optional<Eigen::Vector3d> up_at_estimates_;
  // The objects whose sightings or point votes changed since they were last estimated.
  std::set<ObjectId> unestimated_;
  // FollowMap's changed points: the entities holding each point with at least
  // Objects.min_point_votes votes (ids of objects and candidates; stale ids, of entities
  // merged, dropped or promoted since, are skipped and pruned when read); built from every
  // entity when not valid (the first call, a loaded map), then kept up to date: a
  // promotion, a join, a merge or a restore adds the entity's counted points under its id
  // (rebuilding it at each cost a revisited room's many joins a growing share of a
  // keyframe). A point with fewer votes is counted nowhere (ObjectPointIds), so
  // its position and descriptor are not followed: an entity holds many such points (the
  // background in its boxes), and AddPointVotes gives a point its position now at each vote.
  std::unordered_map<std::uint64_t, std::vector<ObjectId>> point_entities_;
  bool point_index_valid_ = false;
  // The points counted by an entity since the last FollowMap (whose map point may have
  // moved after they were last given a position).
  std::vector<std::uint64_t> fresh_points_;
  void IndexPoints();
  // A valid index takes entity's counted points under its id.
  void IndexEntity(const MapObject& entity);
  // After AddPointVotes: the box's points new to entity enter the index.
  void PointsJoined(const MapObject& entity,
                    const std::vector<const PointObservation*>& box_points);
  // Absorb, with the points bounded (Objects.max_object_points) and the index redone.
  void AbsorbInto(MapObject& into, const MapObject& from);
  static constexpr double kUpTurnForAll = 0.1 * 3.14159265358979323846 / 180.0;
  std::map<ObjectId, MapObject> objects_;
  std::map<ObjectId, MapObject> candidates_;                  // negative ids
  std::map<ObjectId, std::int64_t> observed_since_keyframe_;  // id -> last frame
  std::map<ObjectId, bool> geometry_changed_;
  std::vector<ObjectChange> changes_;
  bool restore_ = false;
  // The evidence sources, asked in this order at each keyframe; point_evidence_: the
  // "points" one among them, else null.
  std::vector<std::unique_ptr<EvidenceProvider>> evidence_;
  const PointPresenceEvidence* point_evidence_ = nullptr;
  struct RemovedObject {
    MapObject object;
    double removed_at = 0.0;  // timestamp
  };
  std::map<ObjectId, RemovedObject> removed_;  // restore on: removed within the window
  std::map<ObjectId, std::vector<Descriptor>> removed_appearance_;  // Appearances()
  // Objects removed in this run, with their sightings and last cuboid (no points), for
  // BoxAppearances(). Not kept in map files: a session pairs only its own removals.
  std::map<ObjectId, MapObject> removed_in_run_;
  ObjectId next_object_id_ = 1;
  ObjectId next_candidate_id_ = -1;
  int session_ = 0;
  std::int64_t session_first_frame_ = 0;
  std::int64_t current_frame_ = 0;  // of the last AddFrame()
};

// objects.json (SPEC 5): the live objects with their cuboid and OCG state.
std::string ObjectsJson(const ObjectMap& map, const std::vector<ObjectStatus>& states);
// The live objects as the change log's revision reads them (ReviseChangeLog): what
// objects.json says of each, in id order.
std::vector<ObjectRecord> LiveObjectRecords(const ObjectMap& map);

}  // namespace ocg
