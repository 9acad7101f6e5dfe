#pragma once
// The OCG change detector: the graph plus every object's state and DoubtValue, updated
// once per keyframe (SPEC 3). Not thread-safe; OcgManager owns one and serialises calls.
//
// Cost of Process(): O(sum of degrees of the observed objects + objects in states 1, 2
// and 4), independent of the map size. In "fallback" mode, neighbourless objects in
// state 3 are visited too (they can only be judged geometrically).

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "ocg/ocg/graph.h"
#include "ocg/ocg/judgement.h"
#include "ocg/ocg/observability.h"
#include "ocg/ocg/observation.h"
#include "ocg/ocg/options.h"

namespace ocg {

struct MapFileAccess;

struct ObjectStatus {
  ObjectId id = 0;
  ObjectState state = ObjectState::kObserved;
  double doubt = 0.0;
  double active_edge_rate = 0.0;  // at the last processed keyframe
  bool judged_by_geometry = false;
  int class_id = -1;  // -1 when never given
  ObjectGeometry geometry;
  std::uint32_t observations = 0;
  std::int64_t first_keyframe = 0;
  std::int64_t last_observed_keyframe = 0;
};

// An object that reached state 5 and left the map.
struct RemovalEvent {
  std::int64_t keyframe_id = 0;
  double timestamp = 0.0;
  ObjectId object_id = 0;
  int class_id = -1;
  std::optional<Eigen::Vector3d> centroid;  // last known
  double doubt = 0.0;
  std::string reason = "outlier";
};

struct KeyframeResult {
  std::int64_t keyframe_id = 0;
  std::vector<RemovalEvent> removed;  // ascending object id
};

class ObjectChangeDetector {
 public:
  explicit ObjectChangeDetector(OcgOptions options);

  // SPEC 3.5 order: graph update, then every affected object's rate and state on the
  // updated graph, then this keyframe's removals.
  KeyframeResult Process(const KeyframeObservation& observation);
  // Sessions (a map continued after a gap, docs/sessions.md). StartSession: a new session
  // begins; until an object is observed again, it counts as last seen in an earlier one.
  // EndSession: the camera leaves at the session's end, so every object leaves its
  // observable region; an object not observed in this session that became suspicious
  // (state 4) in it and is still, with its doubt above tau_doubt, becomes an outlier, as
  // on leaving (SPEC 3.4), and is removed (at the last keyframe). An object observed in this
  // session keeps its state (a static object the detector misses from one side gathers doubt
  // too) unless a move explains its doubt ("successor" mode): an object of its class that
  // entered the graph after its last observation, never seen with it, shares a neighbour
  // with it (it came up in the same region) and is not itself suspicious above tau_doubt.
  // Graph strategy only; in a run that started no session (session 0) only "successor"
  // removes. may_have_become(object, successor): whether the caller's evidence allows the
  // successor to be the object carried elsewhere (an object map that knows their colours
  // refuses two objects of different colours); none: every successor may be.
  using SuccessorCheck = std::function<bool(ObjectId object, ObjectId successor)>;
  void StartSession();
  KeyframeResult EndSession(const SuccessorCheck& may_have_become = {});
  // Removes an object that the object map dropped for its own reasons (a merge): no
  // change-log entry, and geometry given for it but not yet used is dropped too.
  // Returns false when unknown.
  bool Forget(ObjectId id);
  // "restore" mode: brings back an object this detector removed, in state 1 with no doubt,
  // its counts and view record kept, with the edges it had when removed to objects still in
  // the graph. Returns false (and does nothing) when the object is in the graph or was not
  // removed in "restore" mode. Process() calls it for observation.restored.
  bool Restore(ObjectId id);

  std::optional<ObjectStatus> Status(ObjectId id) const;
  // Geometry known for an object not in the graph, used when it is observed (again): given
  // before its first observation, or the last of a removed object (SPEC 3.1).
  std::optional<ObjectGeometryUpdate> PendingGeometry(ObjectId id) const;
  // Every object in the graph, ascending id.
  std::vector<ObjectStatus> Snapshot() const;
  const ObjectCovisibilityGraph& graph() const { return graph_; }
  const OcgOptions& options() const { return options_; }
  std::int64_t last_keyframe() const { return last_keyframe_; }
  std::size_t ObjectCount() const { return records_.size(); }

  // ocg.json: options, nodes with their state, edges. FromJson throws
  // std::invalid_argument naming what is wrong.
  std::string ToJson() const;
  static ObjectChangeDetector FromJson(const std::string& text);

 private:
  friend struct MapFileAccess;  // map files (src/app/object_map_file.cc)
  struct Record {
    StateAndDoubt state;
    double rate = 0.0;
    std::int64_t rate_keyframe = -1;
    bool judged_by_geometry = false;
    int class_id = -1;
    ObjectGeometry geometry;
    std::uint32_t observations = 0;
    std::int64_t first_keyframe = 0;
    std::int64_t last_observed_keyframe = 0;
    bool observed_in_session = true;    // since the last StartSession()
    bool suspected_in_session = false;  // entered state 4 since the last StartSession()
  };
  void ApplyUpdate(Record& record, const ObjectGeometryUpdate& update);
  void SetState(ObjectId id, Record& record, const StateAndDoubt& next);
  void UpdateIsolation(ObjectId id);
  // A removal's centroid, size and class wait in pending_ for the id's re-entry.
  void KeepGeometryForReentry(ObjectId id);
  // archive: keep the record and edges for Restore() ("restore" mode removals).
  void RemoveObject(ObjectId id, bool archive = false);
  // The graph as the judgement terms read it at one keyframe (GraphView, judgement_terms.h).
  class KeyframeView;
  RemovalEvent MakeRemoval(ObjectId id, std::int64_t keyframe, double timestamp) const;
  ObjectStatus MakeStatus(ObjectId id, const Record& record) const;

  OcgOptions options_;
  OcgModes modes_;
  ObjectCovisibilityGraph graph_;
  std::unordered_map<ObjectId, Record> records_;
  // Geometry of objects not in the graph (SPEC 3.1: a centroid may arrive before the
  // first observation; a removed object keeps its last one); applied when the id enters.
  std::unordered_map<ObjectId, ObjectGeometryUpdate> pending_;
  std::unordered_set<ObjectId> active_;    // states 1, 2 and 4
  std::unordered_set<ObjectId> isolated_;  // degree 0 (judged geometrically in "fallback")
  // "restore" mode: objects removed as outliers, as they were, until restored or forgotten.
  // Not in ocg.json: a restore happens within the run that removed the object.
  struct Removed {
    Record record;
    std::vector<CovisibilityEdge> edges;
  };
  std::unordered_map<ObjectId, Removed> removed_;
  std::int64_t last_keyframe_ = -1;
  double last_timestamp_ = 0.0;
  bool any_keyframe_ = false;
  // Scratch buffers reused across keyframes, so a keyframe allocates nothing.
  struct ObservedWeight {
    ObjectId id;
    std::uint64_t weight;      // sum of E(id, j) over observed j
    std::uint32_t neighbours;  // number of observed j
  };
  std::vector<CovisibilityEdge> touched_;
  std::vector<ObservedWeight> observed_weight_;
  std::vector<ObjectId> candidates_;
};

}  // namespace ocg
