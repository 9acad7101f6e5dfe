#pragma once
// changes.json of a run: the object map's change log with moves linked (docs/sessions.md)
// and each entry's session and time. The app calls it when it writes a run's files.

#include <string>

#include "ocg/objects/map_diff.h"

namespace ocg {

struct ChangeLogContext {
  // The session the run is (0: a run from an empty map; later: continuing a loaded map).
  int session = 0;
  // Timestamp of the session's first frame, seconds: entries' "time" counts from it.
  double session_start = 0.0;
  MoveLinkOptions moves;
};

// changes.json as ObjectChangesJson writes it, revised against the live objects of
// objects.json (ObjectsJson's text). This session's removals become "moved" entries
// holding both ids and cuboids ("centroid" and "cuboid" stay the old place's) when:
//  - the object was last seen in an earlier session (last_seen before session_start, a
//    later session only) and a live object of its class was first seen in this session
//    ("first_session"), at any distance (LinkMoves without a reach, nearest first);
//  - or it was seen in this session and a live object of its class appeared near it after
//    its last sighting (LinkMoves with context.moves).
// Earlier sessions' removals stay "removed": their session paired them. In a later
// session, live objects first seen in it and not part of a move get an "added" entry.
// Every entry gets "session" (kept when the entry has one: a change an earlier session
// made) and "time" (seconds from session_start; null for earlier sessions' changes).
// Other entries pass unchanged.
// Throws ParseError, nlohmann::json::exception or std::invalid_argument on texts those
// functions did not write.
std::string ReviseChangeLog(const std::string& changes_json, const std::string& objects_json,
                            const ChangeLogContext& context);

}  // namespace ocg
