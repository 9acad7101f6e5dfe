#pragma once
// What changed in an object map: removals and appearances linked into moves (the change
// log, changes.json) and the diff of two saved object maps (ocg_diff, docs/sessions.md).
//
// Distances scale with the objects' sizes, never in metres: a monocular map has its own
// scale, and a cup and a laptop are moved over different distances.

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ocg/objects/box.h"
#include "ocg/ocg/observation.h"

namespace ocg {

// An object as change reports see it.
struct ObjectRecord {
  ObjectId id = 0;
  int class_id = 0;         // COCO-80
  Cuboid cuboid;            // in the map's world frame and units
  double first_seen = 0.0;  // timestamps of its first and last sighting, seconds
  double last_seen = 0.0;
  int first_session = 0;  // the session of its first sighting (map files; 0 otherwise)
  int observations = 0;   // sightings (objects.json "observations"; 0 when not known)
  int state = 0;          // its OCG state in its map (objects.json "state"; 0: not judged)
};

// When a session saw objects as their class (a detection of the object's class associated
// to it), timestamps in seconds, by id. A sighting of another class (a false positive at a
// place emptied by a move, absorbed into the object left there; a class flip) does not
// show the object there, so a move pairing orders a removal and an appearance by these.
// Each time is a supported one (SightingHistory::ClassSpan::SupportedFirst, SupportedLast:
// the second sighting's, the second last's), so that one stray box of the class at the
// new place before the move (another object's, called by its class) does not date the
// object that came there, nor one at the old place after it the object that left.
struct SeenAsClass {
  std::map<ObjectId, double> first;  // objects no earlier session saw
  std::map<ObjectId, double> last;
};

struct MoveLinkOptions {
  // ocg_diff (the change log's pairing has no reach): an object of the same class is the
  // removed one moved when their centres are at most search_factor x the larger extent (a
  // cup, 0.09 m: 0.9 m; a laptop, 0.33 m: 3.3 m)...
  double search_factor = 10.0;
  // ...and farther than same_place_factor x that extent: closer, it overlaps where the
  // removed one stood: the same object re-created (cuboid estimates err by about half an
  // extent; static_scene_check.py calls such a removal false with the same reach), not a
  // move. The generator moves objects at least their largest extent (docs/synthetic.md).
  double same_place_factor = 1.0;
  // Throws std::invalid_argument naming the field.
  void Check() const;
};

// A move: the object that left a place and the one that appeared at another.
struct MoveLink {
  ObjectRecord from;
  ObjectRecord to;
  double distance = 0.0;  // between the centres, map units
  bool recorded = false;  // DiffObjectMaps: the later run's changes.json reports it
};

// A move a run's changes.json reports (a "moved" entry not undone by a restore).
struct RecordedMove {
  ObjectId from = 0, to = 0;
  int session = 0;  // the session that found it
};

// The larger of the two objects' largest extents (map units), at least 1e-6.
double LargerExtent(const ObjectRecord& a, const ObjectRecord& b);

// The distance of the two objects' centres in units of LargerExtent(a, b): what the move
// and same-place factors compare with.
double RelativeDistance(const ObjectRecord& a, const ObjectRecord& b);

// Pairs removed objects with appeared ones of two object maps into moves: same class,
// centres within the distances of options. Two maps hold no times to order, so a
// same-class neighbour counts as well (within a session the change log pairs by sighting
// times and appearance instead: ReviseChangeLog, change_log.h). Nearest pairs (in units
// of LargerExtent) first, ties by ids; each object in at most one move.
// Throws std::invalid_argument when options fail Check().
std::vector<MoveLink> LinkMoves(const std::vector<ObjectRecord>& removed,
                                const std::vector<ObjectRecord>& appeared,
                                const MoveLinkOptions& options);

struct MapDiffOptions {
  // The same object at the same place: same class, centres within this many larger
  // extents (as MoveLinkOptions). Separate runs number their objects apart, so ids are
  // not needed.
  double same_place_factor = 1.0;
  MoveLinkOptions moves;
  void Check() const;
};

struct MapDiff {
  std::vector<MoveLink> unchanged;  // from = before, to = after (distance: how far apart)
  std::vector<MoveLink> moved;
  std::vector<ObjectRecord> removed;  // in before only
  std::vector<ObjectRecord> added;    // in after only
};

// The diff of two object maps in one world frame (a later session continuing a loaded
// map; two separate runs are not in one frame: CheckOneFrame, map_frames.h). The moves
// the later run recorded (MovesSince) come first, each whose objects are in before and
// after by id (recorded = true). Of the rest, objects at the same place are unchanged
// (pairs with equal ids first, then nearest first); of what is left, removals and
// additions of one class near each other are moves (LinkMoves); the others are removed
// or added.
MapDiff DiffObjectMaps(const std::vector<ObjectRecord>& before,
                       const std::vector<ObjectRecord>& after, const MapDiffOptions& options,
                       const std::vector<RecordedMove>& recorded = {});

// {"format": "ocg-map-diff", "version": 1, "counts", "distance_unit", "frame", "removed",
// "added", "moved" (with "recorded"), "unchanged"}: ids, classes, cuboids. distance_unit:
// DistanceUnit's; frame: why the maps are taken to be in one frame (CheckOneFrame's
// evidence).
std::string MapDiffJson(const MapDiff& diff, const std::string& distance_unit = "map units",
                        const std::string& frame = "");

// What a run folder's run.json and changes.json say of the map beside its objects.json.
struct RunRecord {
  std::string folder;
  int session = 0;                  // run.json "session.index" (0 without one)
  std::string map_loaded;           // "session.map_loaded": the map file it continued ("": none)
  std::string map_saved;            // "session.map_saved" ("": none)
  bool poses_given = false;         // "command": "objects" (ocg_slam objects, the poses' frame)
  std::vector<RecordedMove> moves;  // changes.json's standing "moved" entries
};

// A saved object map's live objects and its up direction (world frame).
struct SavedObjectMap {
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  std::vector<ObjectRecord> objects;
  std::optional<RunRecord> run;  // read from a run folder holding run.json
};

// Whether later continued the map file earlier saved (run.json's session sections: the
// same file, by path as given or as found on disk): one map, so one frame and one id
// numbering.
bool ContinuesMapOf(const RunRecord& later, const RunRecord& earlier);
// The moves after's run recorded since before's map was saved, when after continued it
// (ContinuesMapOf): its changes.json's moves found by later sessions than before's. Else
// none: another run's ids name other objects.
std::vector<RecordedMove> MovesSince(const SavedObjectMap& before, const SavedObjectMap& after);
// The unit of the maps' distances: "m" when both were mapped on given poses (ocg_slam
// objects: ground truth is in metres), else "map units" (a monocular SLAM map has its own
// scale; a bare objects.json says nothing).
std::string DistanceUnit(const SavedObjectMap& before, const SavedObjectMap& after);

// objects.json's text (name: the file, for errors). Throws ParseError naming it.
SavedObjectMap ParseObjectsJson(const std::string& text, const std::string& name);

// Reads the live objects of a saved object map. One reader per kind of file, so the
// binary map file can join without touching the diff.
class ObjectMapReader {
 public:
  virtual ~ObjectMapReader() = default;
  virtual std::string Name() const = 0;
  // Whether path is a file (or folder) of this reader's kind; reads at most its start.
  virtual bool Accepts(const std::string& path) const = 0;
  // Throws FileError / ParseError naming the file.
  virtual SavedObjectMap Read(const std::string& path) const = 0;
};

// objects.json ("format": "ocg-objects", as runs write it), or a run folder holding one
// (then with its RunRecord when the folder has run.json).
class ObjectsJsonReader : public ObjectMapReader {
 public:
  std::string Name() const override { return "objects.json"; }
  bool Accepts(const std::string& path) const override;
  SavedObjectMap Read(const std::string& path) const override;
};

// The readers this build has, in the order they are tried.
std::vector<std::unique_ptr<ObjectMapReader>> ObjectMapReaders();

// The live objects of path, read by the first reader that accepts it. Throws FileError
// naming the path and the kinds of file accepted when none does.
SavedObjectMap ReadObjectMap(const std::string& path,
                             const std::vector<std::unique_ptr<ObjectMapReader>>& readers);

}  // namespace ocg
