#pragma once
// The SLAM map: keyframes, map points, the covisibility graph and the spanning tree.
//
// Threading: one lock, Map::mutex(), guards every KeyFrame, MapPoint and the Map itself.
// Tracking (the caller's thread) and LocalMapping (its own thread, or the caller's in
// sequential mode) hold it for each step that reads or changes the map; nothing reads
// map data without it. Containers are ordered by id, so iteration order, and with it the
// results, do not depend on addresses.

#include <Eigen/Core>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

#include "ocg/core/lie.h"
#include "ocg/features/orb_extractor.h"
#include "ocg/features/vocabulary.h"
#include "ocg/slam/map_journal.h"

namespace ocg {

using KeyFrameId = std::uint64_t;
using MapPointId = std::uint64_t;
struct KeyFrame;
struct MapPoint;
using KeyFramePtr = std::shared_ptr<KeyFrame>;
using MapPointPtr = std::shared_ptr<MapPoint>;

struct MapPoint {
  MapPointId id = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // world
  // The observation descriptor with the least median distance to the others.
  Descriptor descriptor{};
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // mean viewing direction (unit)
  // Scale invariance: distances from a camera at which the point can be detected.
  double min_distance = 0.0;
  double max_distance = 0.0;
  std::map<KeyFrameId, int> observations;  // keyframe -> feature index
  KeyFrameId reference = 0;                // keyframe whose observation sets the scale
  KeyFrameId first_keyframe = 0;
  std::uint64_t first_frame = 0;
  int visible = 1;  // frames in whose frustum it was
  int found = 1;    // frames that matched it
  bool bad = false;
  int map = 0;  // the atlas map it belongs to (Map's map indices), its keyframes' map
  // Tracking's scratch mark (ORB-SLAM2's mnTrackReferenceForFrame): the last frame whose
  // local map search already had this point, so that a point seen by several local
  // keyframes is projected once without a set of ids per frame. Not saved with the map.
  std::uint64_t searched_by_frame = kNoFrame;
  // Where the map journal's reader last read it (ChangesSince): an adjustment that moves
  // it less than MapJournal::point_tolerance() from there leaves it out of the journal.
  // Not saved with the map.
  Eigen::Vector3d read_position =
      Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());

  static constexpr std::uint64_t kNoFrame = std::numeric_limits<std::uint64_t>::max();

  double FoundRatio() const { return static_cast<double>(found) / visible; }
};

// A pose measured relative to a keyframe, and in which state of the map it was measured:
// tracking places each frame and each new keyframe so, on another thread than the loop
// closing that may move the map meanwhile (PoseFromAnchor).
struct Anchor {
  KeyFramePtr keyframe;  // may still wait for local mapping (not in the map yet)
  SE3 T_c_keyframe;
  int map = 0;                    // keyframe->map when measured: a merge since changes units
  std::uint64_t corrections = 0;  // Map::corrections() when measured
};

struct KeyFrame {
  KeyFrameId id = 0;
  std::uint64_t frame_id = 0;
  double timestamp = 0.0;
  std::string timestamp_text;
  SE3 T_cw;
  ExtractedFeatures features;
  BowVector bow;
  FeatureVector feature_vector;
  std::vector<MapPointPtr> points;  // per feature; null when none
  // Covisibility: keyframes sharing at least kCovisibilityThreshold points (or the best
  // one when none does), with the number shared.
  std::map<KeyFrameId, int> covisible;
  std::vector<KeyFrameId> ordered_covisible;  // by weight, then id
  KeyFrameId parent = 0;                      // spanning tree (0 for the first keyframe)
  bool has_parent = false;
  std::set<KeyFrameId> children;
  std::set<KeyFrameId> loop_edges;  // keyframes a closed loop linked it to (never culled)
  bool bad = false;
  int map = 0;  // the atlas map it belongs to (Map's map indices)
  // Culled keyframes: the pose relative to the parent at culling time, so that frames
  // that referred to it can follow the parent's later corrections.
  SE3 T_c_parent;
  // A keyframe made by tracking, until local mapping links it into the map: where the
  // frame it was made of stood then. A loop correction, merge or global adjustment that
  // moves the map before the link does not see it (it is not in the map yet); linking
  // places it again from this anchor (LocalMapping), so it follows them.
  std::optional<Anchor> anchor;

  Eigen::Vector3d Centre() const { return T_cw.Inverse().translation(); }
  int TrackedPoints(int min_observations) const;
  // Per feature: whether it holds a map point that is not bad (the features BoW matching
  // may use).
  std::vector<bool> GoodPointMask() const;
};

// Where a map point falls in a camera, if it can be seen there: in front, inside the
// (undistorted) image bounds and, with check_scale, within the point's scale-invariance
// distances (x0.8 .. x1.2) and at most 60 degrees from its mean viewing direction.
struct PointProjection {
  Eigen::Vector2d pixel;
  double distance = 0.0;  // from the camera centre
  double view_cos = 0.0;  // cosine to the mean viewing direction (check_scale only)
};
std::optional<PointProjection> ProjectPoint(const PinholeCamera& camera, const ImageBounds& bounds,
                                            const SE3& T_cw, const MapPoint& point,
                                            bool check_scale);

class Map;

// Where a pose measured relative to an anchor stands now: the anchor's keyframe as the map
// now holds it (a keyframe not yet linked through its own anchor, a culled one through
// its parent), the relative translation in the units of that keyframe's map now (times
// the scale of every merge of the anchor's map since). None when the keyframe is gone.
struct AnchoredPose {
  SE3 T_cw;
  int map = 0;  // the map the pose is in now
};
// live_keyframe (optional): as PoseFromReference's anchor.
std::optional<AnchoredPose> PoseFromAnchor(const Map& map, const Anchor& anchor,
                                           KeyFrameId* live_keyframe = nullptr);

// The pose now of a frame placed relative to a keyframe (T_c_reference), following a
// culled keyframe to its parent with the relative pose kept at culling (ORB-SLAM2's way),
// so the frame takes every correction that came later. None when the keyframe is gone.
// anchor (optional): the live keyframe the pose was taken from, the end of that chain; the
// pose changes only when the anchor's pose or life changes (both in the map's journal).
std::optional<SE3> PoseFromReference(const Map& map, KeyFrameId reference, const SE3& T_c_reference,
                                     KeyFrameId* anchor = nullptr);

// The atlas (ORB-SLAM3's idea): the keyframes and points of every map the run made, each
// tagged with its map's index (KeyFrame::map, MapPoint::map). Maps share nothing but the
// keyframe database and the id counters: no point is seen by keyframes of two maps, so
// covisibility, local mapping and tracking's local map stay inside one map. Tracking
// works in the current map; relocalization may find a keyframe of any map, which then
// becomes current; a merge moves one map into another's frame and retags it.
class Map {
 public:
  static constexpr int kCovisibilityThreshold = 15;

  // The map new keyframes and points go to (tracking's), and how many maps were started
  // (indices 0 .. map_count() - 1; merged ones keep their index but hold nothing).
  int current_map() const { return current_map_; }
  void SetCurrentMap(int map) {
    if (map != current_map_) journal_.Everything();
    current_map_ = map;
  }
  int map_count() const { return map_count_; }
  // Starts an empty map, which becomes current; returns its index.
  int StartNewMap() {
    current_map_ = map_count_++;
    journal_.Everything();
    return current_map_;
  }
  // The keyframes of one map, culled ones included / not.
  std::size_t KeyFrameCount(int map) const;
  std::size_t LiveKeyFrameCount(int map) const;
  // The first keyframe of a map (never culled, the gauge of its adjustments); none for an
  // empty map.
  std::optional<KeyFrameId> FirstKeyFrame(int map) const;
  // Removes a map's keyframes and points (a reset of a young map); returns the keyframe
  // ids removed, for the keyframe database.
  std::vector<KeyFrameId> EraseMap(int map);
  // A merge: every keyframe and point of map from moves by the similarity S_into_from
  // (from's world to into's world: poses T_cw become T_cw * S_into_from^-1 with the scale
  // divided out, points S_into_from * X) and is retagged into; the current map follows.
  void MoveMap(int from, int into, const Sim3& S_into_from);
  // Merges so far, and the last one's scale (S_into_from's): motion measured before it
  // is in the old units.
  int merges() const { return merges_; }
  double last_merge_scale() const { return last_merge_scale_; }
  // Distances measured in map `from` times this are in map `to`'s units: the product of the
  // scales of the merges that took from into to (1 when from is to or never went into it).
  double ScaleInto(int from, int to) const;

  std::mutex& mutex() const { return mutex_; }
  // Changing the map over several steps (local mapping's work on a keyframe, a loop
  // correction, the merge of a global adjustment, an initialization) takes
  // mapping_mutex() first and then mutex() for each change. Tracking only reads the map
  // (and counts its points' sightings), so a thread that holds mapping_mutex() may read
  // the map without mutex(): nobody else changes it meanwhile. Lock order: mapping_mutex()
  // before mutex(); a thread holding mutex() never waits for mapping_mutex().
  std::mutex& mapping_mutex() const { return mapping_mutex_; }
  // Tracking must keep up with the camera; local mapping's steps on a keyframe take
  // several times a frame's tracking, and the mutex is not fair (the thread releasing it
  // can take it back before a waiter wakes). So tracking takes the lock saying that it
  // waits, and local mapping, between its steps, lets a waiting tracker in first.
  std::unique_lock<std::mutex> LockForTracking() const;
  bool TrackerWaiting() const { return trackers_waiting_.load() > 0; }
  // Called holding lock (on mutex()): while a tracker waits, releases the lock until the
  // tracker has it (at most max_wait: it may wait behind another thread), then takes it
  // again, after the tracker's step. Returns whether a tracker was let in.
  bool LetWaitingTrackerIn(std::unique_lock<std::mutex>& lock,
                           std::chrono::microseconds max_wait = std::chrono::milliseconds(5)) const;

  KeyFrameId NextKeyFrameId() { return next_keyframe_id_++; }
  MapPointId NextMapPointId() { return next_point_id_++; }
  // Map files (map_file.h): the id counters, so that a loaded map's new keyframes and
  // points never take the id of a saved one.
  KeyFrameId next_keyframe_id() const { return next_keyframe_id_; }
  MapPointId next_map_point_id() const { return next_point_id_; }
  void RestoreIdCounters(KeyFrameId next_keyframe, MapPointId next_point) {
    next_keyframe_id_ = next_keyframe;
    next_point_id_ = next_point;
  }
  // keyframe->map must be set: the map's first keyframe is kept up to date here.
  void Add(const KeyFramePtr& keyframe);
  void Add(const MapPointPtr& point) {
    points_[point->id] = point;
    point_index_[point->id] = point.get();
    journal_.Point(point->id);
  }
  KeyFramePtr GetKeyFrame(KeyFrameId id) const;
  // The point with this id, null when the map does not hold it: a hash lookup, the same
  // cost however large the map (the map journal's reader looks up a keyframe's changed
  // points, a thousand ids spread over the local window, at every keyframe).
  MapPoint* FindPoint(MapPointId id) const {
    const auto found = point_index_.find(id);
    return found == point_index_.end() ? nullptr : found->second;
  }
  // Every keyframe ever added, the culled ones (bad) included: frames placed relative to
  // a culled keyframe still follow it to its parent.
  const std::map<KeyFrameId, KeyFramePtr>& keyframes() const { return keyframes_; }
  // The keyframes not culled, of every map.
  std::size_t LiveKeyFrameCount() const;
  const std::map<MapPointId, MapPointPtr>& points() const { return points_; }
  // Forgets every map and the id counters.
  void Clear();

  // Observations and geometry.
  void AddObservation(const KeyFramePtr& keyframe, int feature, const MapPointPtr& point);
  void EraseObservation(const KeyFramePtr& keyframe, const MapPointPtr& point);
  // Marks the point bad and removes it from the map and every keyframe.
  void ErasePoint(const MapPointPtr& point);
  // Keeps the point with more observations; the other's observations move to it.
  void ReplacePoint(const MapPointPtr& old_point, const MapPointPtr& new_point);
  void UpdatePointGeometry(const MapPointPtr& point, const ScalePyramid& pyramid) const;
  void UpdatePointDescriptor(const MapPointPtr& point) const;
  // Recounts the points the keyframe shares with others; updates both sides' edges and
  // gives a new keyframe its spanning-tree parent.
  void UpdateConnections(const KeyFramePtr& keyframe);
  std::vector<KeyFramePtr> BestCovisible(const KeyFramePtr& keyframe, std::size_t count) const;
  // Marks the keyframe bad, removes its observations and edges, hands its children to
  // its parent, and releases its features, BoW vectors and point slots (a culled keyframe
  // keeps only what PoseFromReference needs).
  void EraseKeyFrame(const KeyFramePtr& keyframe);
  // Loop corrections and global bundle adjustments move the whole map; a tracker whose
  // last frame was placed before the count changed re-anchors it on its keyframe.
  std::uint64_t corrections() const { return corrections_; }
  void CountCorrection() {
    ++corrections_;
    journal_.Everything();
  }
  // What changed (map_journal.h). Whoever changes a point's position or descriptor or a
  // keyframe's pose outside Map's methods notes it here (the adjustments' write-back).
  MapJournal& journal() const { return journal_; }
  // An adjustment moved the point: noted unless it is within the journal's point
  // tolerance of where the reader last read it.
  void NotePointMoved(const MapPoint& point) const {
    if (!((point.position - point.read_position).norm() <= journal_.point_tolerance()))
      journal_.Point(point.id);
  }

 private:
  mutable std::mutex mutex_;
  mutable std::mutex mapping_mutex_;
  mutable std::atomic<int> trackers_waiting_{0};
  KeyFrameId next_keyframe_id_ = 0;
  MapPointId next_point_id_ = 0;
  std::uint64_t corrections_ = 0;
  int current_map_ = 0;
  int map_count_ = 1;
  int merges_ = 0;
  double last_merge_scale_ = 1.0;
  std::map<int, std::pair<int, double>> merged_into_;  // merged map -> (into, scale)
  std::map<int, KeyFrameId> first_keyframes_;          // per map
  std::map<KeyFrameId, KeyFramePtr> keyframes_;
  std::map<MapPointId, MapPointPtr> points_;
  // points_ by hash (FindPoint): the same points, held by points_ (an entry leaves both).
  std::unordered_map<MapPointId, MapPoint*> point_index_;
  mutable MapJournal journal_;
};

}  // namespace ocg
