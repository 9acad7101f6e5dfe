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
// objects.json (ObjectsJson's text): a removed object with a live object of its class that
// appeared near it after its last sighting (LinkMoves) becomes one "moved" entry holding
// both ids and cuboids ("centroid" and "cuboid" stay the old place's); in a later session
// live objects whose first sighting is of it ("first_session") and not part of a move get
// an "added" entry; every entry
// gets "session" (kept when the entry has one: a change an earlier session made) and
// "time" (seconds from session_start; null for earlier sessions' changes). Other entries
// pass unchanged.
// Throws ParseError / nlohmann::json::exception on texts those functions did not write.
std::string ReviseChangeLog(const std::string& changes_json, const std::string& objects_json,
                            const ChangeLogContext& context);

}  // namespace ocg
