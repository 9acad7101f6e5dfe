#pragma once
// The change log as structs: the object map's own changes (ObjectChange, made as they
// happen) and the entries of changes.json (ChangeEntry: ReviseChangeLog's result, moves
// linked, additions, sessions and times; docs/objects.md, "Outputs"). The log is worked on
// as these structs and written as JSON once, at the edge (ChangeLogJson); map files keep
// the revised log as that text and read it back with ParseChangeLog.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ocg/features/descriptor.h"
#include "ocg/objects/box.h"
#include "ocg/ocg/observation.h"

namespace ocg {

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

// How much two objects look alike by the ORB descriptors of their map points: of the
// smaller set, how many have a descriptor of the other set within max_distance bits.
struct AppearanceMatch {
  int compared = 0;
  int matched = 0;
  // Median over the smaller set of the distance to its nearest descriptor in the other,
  // bits (256 when compared is 0): how far apart the two looks are when few match.
  int median_distance = kDescriptorBits;
  double Share() const { return compared > 0 ? static_cast<double>(matched) / compared : 0.0; }
};

// A between-session pairing's evidence of how alike a removed object and a candidate
// look (changes.json "appearance"); at least one of the two is set.
struct PairingLook {
  std::optional<AppearanceMatch> match;
  bool from_boxes = false;  // match: of the box appearances, else of the map points'
  std::optional<double> colour_similarity;  // ColourSimilarity, 0-1
};

// An object a between-session removal could have become (changes.json "candidates").
struct PairingCandidate {
  ObjectId object_id = 0;
  double distance = 0.0;  // between the centres, map units
  int observations = 0;   // its sightings
  std::optional<PairingLook> appearance;
};

// Where a moved object went (changes.json "to").
struct MoveDestination {
  ObjectId object_id = 0;
  Cuboid cuboid;
  double first_seen = 0.0;  // seconds
};

// One entry of changes.json. Fields a type does not have are unset.
struct ChangeEntry {
  // ObjectChange's types, "moved" (a removal linked to where the object went) or "added"
  // (first seen in a later session)
  std::string type;
  int session = 0;
  std::optional<std::int64_t> keyframe;  // every type but "added"
  double timestamp = 0.0;
  ObjectId object_id = 0;
  int class_id = 0;
  Cuboid cuboid;                            // a move's old place
  std::optional<std::size_t> observations;  // every type but "added"
  std::string reason;
  std::optional<double> doubt;      // "removed", "moved"
  std::optional<double> last_seen;  // "removed", "moved"
  std::optional<ObjectId> merged_into;
  std::optional<ObjectId> recreated_as;  // "restored"
  std::optional<double> removed_at;      // "restored"
  std::optional<MoveDestination> to;     // "moved"
  std::optional<double> distance;        // "moved": between the places, map units
  std::optional<PairingLook> appearance;
  std::optional<std::vector<PairingCandidate>> candidates;
  // Seconds from the session's start; none for an earlier session's change (its clock
  // was another session's).
  std::optional<double> time;
};

// The entry of an object map's change as it stands before any revision.
ChangeEntry EntryOf(const ObjectChange& change);
std::vector<ChangeEntry> EntriesOf(const std::vector<ObjectChange>& changes);

// Whether each change is a removal ("removed" or "moved") not undone by a later "restored"
// entry of the same object (StandingRemovals of change_entries.h).
std::vector<bool> StandingRemovals(const std::vector<ChangeEntry>& entries);

// changes.json: {"changes": [...]}, keys in JSON's order, one space of indent, a final line
// break. with_time false: without "time" (as map files keep the log); else every entry
// has one (null when unset).
std::string ChangeLogJson(const std::vector<ChangeEntry>& entries, bool with_time = true);
// The entries of a changes.json text (ChangeLogJson's). Throws ParseError naming name and
// the key on a text that is not one (an unknown key too: it would be lost).
std::vector<ChangeEntry> ParseChangeLog(const std::string& text, const std::string& name);

}  // namespace ocg
