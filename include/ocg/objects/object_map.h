#pragma once
// The object map: detections associated frame by frame to map objects and candidates,
// candidates promoted once they are triangulated, duplicates merged, and removals of the
// OCG applied. Feeds the OCG one KeyframeObservation per keyframe.
//
// Not thread-safe: ObjectMapper serialises every call (see object_mapper.h).

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ocg/core/camera.h"
#include "ocg/core/lie.h"
#include "ocg/features/descriptor.h"
#include "ocg/objects/box.h"
#include "ocg/objects/box_appearance.h"
#include "ocg/objects/colour_signature.h"
#include "ocg/objects/map_cues.h"
#include "ocg/objects/map_diff.h"
#include "ocg/objects/object_geometry.h"
#include "ocg/objects/objects_options.h"
#include "ocg/objects/point_presence.h"
#include "ocg/objects/sighting_history.h"
#include "ocg/ocg/change_detector.h"
#include "ocg/ocg/observation.h"

namespace ocg {

struct MapFileAccess;  // map files (src/app/object_map_file.cc) save and restore the state

// A SLAM map point seen inside an object's boxes (SLAM runs only).
struct ObjectPoint {
  int votes = 0;                                       // boxes it was inside
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // world, when last tracked
  // The map point's ORB descriptor as of the last FollowMap that gave one. Not kept in map
  // files (the SLAM map holds it; the next FollowMap gives it back).
  std::optional<Descriptor> descriptor;
};

// A map object, or a candidate (id < 0) not yet triangulated.
struct MapObject {
  ObjectId id = 0;
  int class_id = 0;  // the most frequent class of its sightings
  // In frame order; beyond Objects.max_sightings a bounded sample with exact counts.
  SightingHistory sightings;
  Cuboid cuboid;
  bool has_cuboid = false;
  bool yaw_from_points = false;  // else from the boxes' widths
  std::int64_t first_frame = 0;
  std::int64_t last_frame = 0;
  double first_timestamp = 0.0;
  double last_timestamp = 0.0;
  std::int64_t keyframes_in_map = 0;            // keyframes since promotion
  std::map<std::uint64_t, ObjectPoint> points;  // by SLAM map point id
};

// An object as viewers and reports show it: live or removed, with its OCG state.
struct ObjectView {
  ObjectId id = 0;
  int class_id = 0;
  Cuboid cuboid;
  int state = 0;         // OCG state 1-4; 0 before the object's first keyframe
  bool removed = false;  // left the map (the change log's last cuboid)
};

// The object's point set: its map points with at least min_votes votes, within its largest
// extent of its centre once it has a cuboid, and within 3 robust sigmas of their median
// (the background caught in its boxes left out).
std::vector<Eigen::Vector3d> ObjectPointSet(const MapObject& object, int min_votes);
// The same points' ids (SLAM map point ids), in id order.
std::vector<std::uint64_t> ObjectPointIds(const MapObject& object, int min_votes);
// The object's appearance: the descriptors of its point set (points without one left
// out). An object keeps its texture when it is carried elsewhere, so the points of its new
// place match these far better than those of another object of its class.
std::vector<Descriptor> ObjectAppearance(const MapObject& object, int min_votes);

// OCG.mode "points": whether a frame still shows the object by its own map points. Of its
// point set (ObjectPointIds) the points that project inside the image from T_cw, at least
// Objects.presence_min_points and a share Objects.presence_min_share were tracked in the
// frame (tracked: its tracked map point ids, sorted) or, with frame, found by their
// descriptors near their projections (SearchPointsInFrame). A detector that misses an
// object does not change its texture; an object carried away takes its points with it,
// and what is left at its place (the table behind) was never most of its set. Tracking
// alone rarely sees them again: it follows its local map, and an object's points were made
// in the few frames it was detected in.
bool PresentByPoints(const MapObject& object, const std::vector<std::uint64_t>& tracked,
                     const SE3& T_cw, const PinholeCamera& camera, const ObjectsOptions& options,
                     const FrameFeatureSearch* frame = nullptr);

struct ObjectChange {
  // "removed" (by the OCG), "merged" (a duplicate, hygiene), "dropped" (too few
  // sightings, hygiene) or "restored" (a removed object found again at its place)
  std::string type;
  std::int64_t keyframe_id = 0;
  double timestamp = 0.0;
  ObjectId object_id = 0;
  ObjectId merged_into = 0;  // "merged" only
  int class_id = 0;
  Cuboid cuboid;  // the last estimate
  std::size_t sightings = 0;
  double doubt = 0.0;      // "removed" only
  double last_seen = 0.0;  // "removed" only: timestamp of the last sighting
  // "restored" only: the object that was found at its place (merged into it) and when it
  // had been removed
  ObjectId recreated_as = 0;
  double removed_at = 0.0;
  int session = 0;  // the session that made the change (StartSession)
  // "removed" only: why the OCG removed it (RemovalEvent::reason). Not kept in map files:
  // the revised change log they keep holds it.
  std::string reason;
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
  // pose_of_frame is asked for SightingFrames() alone.
  void FollowMap(
      const std::function<std::optional<SE3>(std::int64_t frame)>& pose_of_frame,
      const std::function<std::optional<Eigen::Vector3d>(std::uint64_t point)>& position_of_point,
      const std::function<const Descriptor*(std::uint64_t point)>& descriptor_of_point = {});

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
  // OCG.mode "points": each keyframe observation lists the objects not detected that the
  // last frame shows by their points (PresentByPoints).
  void SetPointPresence(bool point_presence) { point_presence_ = point_presence; }
  // The "points" evidence so far: keyframes given a frame to search, objects searched,
  // objects found present, and the thread CPU time it took.
  struct PointPresenceStats {
    std::int64_t keyframes = 0;
    std::int64_t keyframes_with_presence = 0;
    std::int64_t objects_searched = 0;
    std::int64_t objects_present = 0;
    double cpu_seconds = 0.0;
  };
  const PointPresenceStats& point_presence_stats() const { return point_presence_stats_; }

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
  // sighting made at frame, of the live objects and of those removed in this run.
  // Returns how many were given one.
  int SetSightingColours(std::int64_t frame, const cv::Mat& bgr,
                         const ColourSignatureOptions& options);
  // The mean colour (MeanColour) of the objects BoxAppearances() weighs, by id, each from
  // its sightings that have a colour; objects with fewer than min_signatures of them are
  // left out.
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

 private:
  friend struct MapFileAccess;
  // The objects a between-session pairing weighs (a later session only): visit(object,
  // removed) for each one removed in this run and last seen in an earlier session
  // (removed true) and each live one seen in this session alone (removed false).
  template <typename Visit>
  void ForEachBetweenSessionCandidate(Visit&& visit) const;
  // Re-estimates centre and cuboid from the sightings (yaw from the point set when it
  // tells one); false when they do not meet.
  bool Reestimate(MapObject& object, bool candidate) const;
  std::optional<double> PointSetYaw(const MapObject& object) const;
  // The candidate an unassociated, untruncated box continues after a detector gap (longer
  // than Objects.predicted_box_frames, within Objects.candidate_gap_seconds; the box fits
  // its track: FitOfBoxToTrack), the best fitting one; null when none.
  MapObject* CandidateAcrossGap(const ObjectDetection& detection, std::int64_t frame,
                                double timestamp, const SE3& T_cw);
  // Whether a box at point, seen from T_cw, is predicted sharply by the track's views
  // (Objects.candidate_gap_seconds): the view is within candidate_min_parallax_deg of one
  // of them (from nearly one place the depth does not matter: the box is where the last
  // one was), or within the track's own spread of views (which fixes the depth). From
  // farther round, the object of a track whose depth is free could be anywhere along a
  // line across the image, and a box of its class there is as likely another object.
  bool PredictsSharply(const std::vector<BoxView>& track, const Eigen::Vector3d& point,
                       const SE3& T_cw) const;
  // The map object whose projected cuboid a candidate's untruncated boxes fit (see
  // Objects.join_candidates), or null; the boxes that fit as partial views are marked
  // truncated.
  MapObject* HostOf(MapObject& candidate);
  // Candidates waiting for a box across a gap (not detected for more than
  // candidate_max_missed_frames) whose boxes fit a map object's projection join it: the
  // boxes a hard object got before it was mapped (issue 18: a vase found in runs seconds
  // apart, mapped from a later run, then dropped for too few sightings).
  void JoinWaitingCandidates();
  // A candidate about to be promoted that is a map object seen again (its boxes fit the
  // object's projection: Objects.join_candidates) joins it; returns the object's id.
  std::optional<ObjectId> JoinCandidate(MapObject& candidate, std::int64_t frame);
  // The sightings of stand_in that are partial views of object's projected cuboid (a part
  // of it, the rest hidden by something nearer) become truncated: their centres and extents
  // do not tell the object's. As a joining candidate's, so an object merged into another
  // does not pull its centre towards the visible part's.
  void MarkPartialViews(MapObject& stand_in, const MapObject& object) const;
  void Merge(ObjectId kept, ObjectId absorbed, std::int64_t keyframe_id, double timestamp,
             std::vector<ObjectChange>* merges);
  // Brings back the removed objects a map object now stands in for; returns their ids.
  std::vector<ObjectId> RestoreRemoved(std::int64_t keyframe_id, double timestamp,
                                       std::vector<ObjectChange>* merges);
  // OCG.mode "points": the objects not detected since the last keyframe that the frame at
  // T_cw shows by their points (PresentByPoints), into observation->present_by_points.
  void AddPresentByPoints(const SE3& T_cw, const FrameFeatureSearch* frame,
                          KeyframeObservation* observation);
  struct PointCue;
  // Whether one of box_points is a point on the object (voted for, within its largest
  // extent of its centre).
  bool HoldsOwnPoint(const MapObject& object,
                     const std::vector<const PointObservation*>& box_points) const;
  double AssociationScore(const MapObject& object, const ObjectDetection& detection,
                          std::int64_t frame, const SE3& T_cw,
                          const std::vector<const PointObservation*>& box_points,
                          const PointCue* object_points) const;

  ObjectsOptions options_;
  PinholeCamera camera_;
  Eigen::Matrix3d R_wg_;
  std::map<ObjectId, MapObject> objects_;
  std::map<ObjectId, MapObject> candidates_;                  // negative ids
  std::map<ObjectId, std::int64_t> observed_since_keyframe_;  // id -> last frame
  // The map point ids the last frame tracked, sorted ("points" evidence); empty without a
  // SLAM map.
  std::vector<std::uint64_t> last_tracked_points_;
  std::map<ObjectId, bool> geometry_changed_;
  std::vector<ObjectChange> changes_;
  bool restore_ = false;
  bool point_presence_ = false;
  PointPresenceStats point_presence_stats_;
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
// changes.json: {"changes": [{"type": "removed" | "merged" | "dropped" | "restored", ...}]}.
std::string ObjectChangesJson(const std::vector<ObjectChange>& changes);

}  // namespace ocg
