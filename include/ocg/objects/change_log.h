#pragma once
// changes.json of a run: the object map's change log with moves linked (docs/sessions.md)
// and each entry's session and time. The app calls it when it writes a run's files.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ocg/features/descriptor.h"
#include "ocg/objects/colour_signature.h"
#include "ocg/objects/map_diff.h"

namespace ocg {

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
AppearanceMatch MatchAppearance(const std::vector<Descriptor>& a, const std::vector<Descriptor>& b,
                                int max_distance);
// The same with from's descriptors compared (whatever the sizes): how much of from is
// found in to.
AppearanceMatch MatchFrom(const std::vector<Descriptor>& from, const std::vector<Descriptor>& to,
                          int max_distance);

struct AppearanceOptions {
  // Bits: two views of one texture patch (ORB-SLAM's tight matching threshold).
  int max_distance = 50;
  // Descriptors each object needs for its appearance to count in a pairing.
  int min_points = 5;
  // Weight of the colour's unlikeness (1 - ColourSimilarity, 0-1) beside the
  // descriptors' (1 - share matched, 0-1): colour decides between candidates whose
  // descriptors tell them apart by less than this share (flat objects, whose boxes carry
  // no texture ORB finds again), and yields where they differ more.
  double colour_weight = 0.1;
  // Sightings with a colour each object needs for its colour to count in a pairing.
  int min_colour_signatures = 3;
  // Throws std::invalid_argument naming the field.
  void Check() const;
};

struct ChangeLogContext {
  // The session the run is (0: a run from an empty map; later: continuing a loaded map).
  int session = 0;
  // Timestamp of the session's first frame, seconds: entries' "time" counts from it.
  double session_start = 0.0;
  MoveLinkOptions moves;
  // SLAM runs: ObjectMap::Appearances() (descriptors of each object's map points), by id;
  // empty in pose-given runs, where pairing goes by distance alone.
  std::map<ObjectId, std::vector<Descriptor>> appearance;
  // SLAM runs of a later session: ObjectMap::BoxAppearances(), by id. A pair both of whose
  // objects have one is weighed by it, else by appearance.
  std::map<ObjectId, std::vector<Descriptor>> box_appearance;
  // SLAM runs of a later session: ObjectMap::ColourAppearances(), by id. A pair both of
  // whose objects have one is weighed by it too (appearance_options.colour_weight).
  std::map<ObjectId, ColourHistogram> colour;
  AppearanceOptions appearance_options;
  // ObjectMap::SeenAsClassThisSession(): the in-session pairing orders a removal and an
  // appearance by when the two were seen as their class (objects left out: by
  // objects.json's first_seen and the removal's last_seen).
  SeenAsClass seen_as_class;
  // Map files: changes.json as the session that saved the loaded map revised it. Earlier
  // sessions' entries are taken from it (their moves, additions and reasons as that
  // session found them) instead of the object map's own entries. None: the object map's.
  std::optional<std::string> earlier_changes;
};

// changes.json as ObjectChangesJson writes it, revised against the live objects of
// objects.json (ObjectsJson's text). This session's removals become "moved" entries
// holding both ids and cuboids ("centroid" and "cuboid" stay the old place's) when:
//  - the object was last seen in an earlier session (last_seen before session_start, a
//    later session only) and a live object of its class was first seen in this session
//    ("first_session"), at any distance, all such pairs chosen together: one assignment
//    of least total cost, objects that look alike (context.box_appearance, MatchFrom, or
//    else context.appearance, MatchAppearance) before nearer ones (between-session
//    entries list their candidates as evidence), and, where both have one, whose colours
//    (context.colour) are alike;
//  - or it was seen in this session and a live object of its class appeared near it after
//    its last sighting (LinkMoves with context.moves), whether before or after the removal;
//    both times as context.seen_as_class gives them, where it does: a box of another
//    class absorbed into the removed object after its move does not make it seen later
//    than its new place was first seen.
// Earlier sessions' removals are not paired again: their session paired them (with
// context.earlier_changes, their entries are that session's, moves included; without, they
// stay "removed"). In a later
// session, live objects first seen in it and not part of a move get an "added" entry.
// Every entry gets "session" (kept when the entry has one: a change an earlier session
// made) and "time" (seconds from session_start; null for earlier sessions' changes).
// Other entries pass unchanged.
// Throws ParseError, nlohmann::json::exception or std::invalid_argument on texts those
// functions did not write.
std::string ReviseChangeLog(const std::string& changes_json, const std::string& objects_json,
                            const ChangeLogContext& context);

}  // namespace ocg
