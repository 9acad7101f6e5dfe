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
#include "ocg/objects/object_change.h"

namespace ocg {

// How much two objects look alike (AppearanceMatch, object_change.h): of the smaller set,
// how many have a descriptor of the other set within max_distance bits.
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
  // Two objects whose colours are less alike than this (ColourSimilarity, 0-1) are not
  // one object carried: the pair is refused, unless descriptors vouch for it (a share of
  // at least colour_weight matched). An object's
  // signatures in its old and new places share 0.6-0.95 on the generated scenes, two
  // objects of one class of different colours 0-0.4; a removal left without a pair stays
  // one (a true removal does not take the new place of an object carried elsewhere).
  double min_colour_similarity = 0.1;
  // Throws std::invalid_argument naming the field.
  void Check() const;
};

// ColourSimilarity of the colours of objects a and b (by id, as ChangeLogContext::colour and
// ObjectMap::ColourAppearances hold them); none when either has none.
std::optional<double> ColourSimilarityOf(const std::map<ObjectId, ColourHistogram>& colours,
                                         ObjectId a, ObjectId b);

struct ChangeLogContext {
  // The session the run is (0: a run from an empty map; later: continuing a loaded map).
  int session = 0;
  // Timestamp of the session's first frame, seconds: entries' "time" counts from it.
  double session_start = 0.0;
  // Its same_place_factor: a removal and a same-class object nearer than this are the
  // same object re-created, no move (search_factor is not used: a move has no reach).
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
  // Map files: the change log as the session that saved the loaded map revised it. Earlier
  // sessions' entries are taken from it (their moves, additions and reasons as that
  // session found them) instead of the object map's own entries. None: the object map's.
  std::optional<std::vector<ChangeEntry>> earlier_changes;
};

// The object map's change log (changes, in order) revised against its live objects (live:
// LiveObjectRecords, object_map.h): the entries of changes.json (ChangeLogJson writes them).
// This session's removals become "moved" entries holding both ids and cuboids (the entry's
// cuboid stays the old place's) when a live object of the removed one's class was first
// seen after the removed one was last seen, at any distance but not at its place
// (context.moves.same_place_factor), all such pairs chosen together: one assignment of as
// many pairs as the times allow at least total cost, objects that look alike
// (context.box_appearance, MatchFrom, or else context.appearance, MatchAppearance) before
// nearer ones, and, where both have one, whose colours (context.colour) are alike; a pair
// whose colours are less alike than appearance_options.min_colour_similarity is none,
// unless descriptors vouch for it.
// A removal whose place holds a live object of its class (their cuboids can overlap:
// centres nearer than the mean of their largest extents) moved nowhere: a duplicate
// removed beside the object it doubled, an object re-created where it stands; a neighbour
// of its class beside it does not hold its place.
//  - A removed object last seen in an earlier session (last_seen before session_start, a
//    later session only) pairs first, with the objects first seen in this session
//    (first_session); its entry lists every candidate as evidence.
//  - One seen in this session pairs with the live objects left, whether they appeared
//    before or after the removal; both times as context.seen_as_class gives them, where
//    it does: a box of another class absorbed into the removed object after its move does
//    not make it seen later than its new place was first seen.
// Earlier sessions' removals are not paired again: their session paired them (with
// context.earlier_changes, their entries are that session's, moves included; without, they
// stay "removed"). In a later session, live objects first seen in it and not part of a move
// get an "added" entry. Every entry gets a time (seconds from session_start; none for
// earlier sessions' changes). Other entries pass unchanged (EntryOf).
// Throws std::invalid_argument when context.appearance_options fail their Check().
std::vector<ChangeEntry> ReviseChangeLog(const std::vector<ObjectChange>& changes,
                                         const std::vector<ObjectRecord>& live,
                                         const ChangeLogContext& context);

}  // namespace ocg
