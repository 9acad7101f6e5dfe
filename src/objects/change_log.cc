#include "ocg/objects/change_log.h"

#include <iomanip>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>

#include "ocg/core/coco.h"
#include "ocg/io/change_entries.h"
#include "ocg/objects/cuboid_json.h"

namespace ocg {
namespace {

// Two decimals, as a reader wants a distance in a sentence.
std::string Rounded(double value) {
  std::ostringstream text;
  text << std::fixed << std::setprecision(2) << value;
  return text.str();
}

}  // namespace

std::string ReviseChangeLog(const std::string& changes_json, const std::string& objects_json,
                            const ChangeLogContext& context) {
  nlohmann::json root = nlohmann::json::parse(changes_json);
  const SavedObjectMap live = ParseObjectsJson(objects_json, "objects.json");
  // Each removal is paired once, by the session that made it: an earlier session's
  // removals were paired when that session wrote its changes.json, and pairing them again
  // against a later map linked them to what the later session found (they stay removals
  // here). This session's removals of objects it saw pair by the in-session rule; those of
  // objects last seen in an earlier session by the between-session rule.
  std::vector<ObjectRecord> seen_now, seen_before;
  // A removal undone by a restore (the object found again at its place) moved nowhere.
  const std::vector<bool> standing = StandingRemovals(root.at("changes"));
  for (std::size_t i = 0; i < root.at("changes").size(); ++i) {
    const nlohmann::json& entry = root.at("changes")[i];
    if (entry.at("type") != "removed" || !standing[i] || entry.at("cuboid").is_null()) continue;
    if (entry.value("session", context.session) != context.session) continue;
    ObjectRecord record;
    record.id = entry.at("object_id").get<ObjectId>();
    record.class_id = entry.at("class_id").get<int>();
    record.cuboid = CuboidFromJson(entry.at("cuboid"));
    record.last_seen = entry.value("last_seen", entry.at("timestamp").get<double>());
    const bool earlier = context.session > 0 && record.last_seen < context.session_start;
    (earlier ? seen_before : seen_now).push_back(record);
  }
  std::map<ObjectId, MoveLink> moves_from;
  std::set<ObjectId> moved_to;
  std::set<ObjectId> between_sessions;  // moves_from's keys linked by the between-session rule
  const auto link = [&](const std::vector<ObjectRecord>& from, const std::vector<ObjectRecord>& to,
                        const MoveLinkOptions& options) {
    std::vector<ObjectId> linked;
    for (const MoveLink& move : LinkMoves(from, to, options, true)) {
      moves_from.emplace(move.from.id, move);
      moved_to.insert(move.to.id);
      linked.push_back(move.from.id);
    }
    return linked;
  };
  {
    // Between visits nothing bounds how far an object was carried: what this session
    // removed, last seen in an earlier one, pairs with what this session found new, at
    // any distance (nearest first).
    std::vector<ObjectRecord> appeared;
    for (const ObjectRecord& object : live.objects) {
      if (object.first_session == context.session) appeared.push_back(object);
    }
    MoveLinkOptions between = context.moves;
    between.search_factor = std::numeric_limits<double>::infinity();
    for (ObjectId id : link(seen_before, appeared, between)) between_sessions.insert(id);
  }
  std::vector<ObjectRecord> rest_live;
  for (const ObjectRecord& object : live.objects) {
    if (moved_to.count(object.id) == 0) rest_live.push_back(object);
  }
  link(seen_now, rest_live, context.moves);
  nlohmann::json list = nlohmann::json::array();
  // Entries kept from a loaded map carry their own session; their clock was another
  // session's, so they get no time.
  const auto stamp = [&](nlohmann::json entry) {
    if (!entry.contains("session")) entry["session"] = context.session;
    entry["time"] =
        entry.at("session").get<int>() == context.session
            ? nlohmann::json(entry.at("timestamp").get<double>() - context.session_start)
            : nlohmann::json(nullptr);
    list.push_back(std::move(entry));
  };
  for (nlohmann::json entry : root.at("changes")) {
    const auto move = entry.at("type") == "removed"
                          ? moves_from.find(entry.at("object_id").get<ObjectId>())
                          : moves_from.end();
    if (move != moves_from.end()) {
      const ObjectRecord& to = move->second.to;
      entry["type"] = "moved";
      entry["reason"] = between_sessions.count(move->first) > 0
                            ? "removed from its place, last seen before session " +
                                  std::to_string(context.session) +
                                  "; same class first seen in session " +
                                  std::to_string(context.session) + ", " +
                                  Rounded(move->second.distance) + " away (map units)"
                            : "removed here, same class appeared near after its last sighting";
      entry["to"] = {
          {"object_id", to.id}, {"cuboid", CuboidJson(to.cuboid)}, {"first_seen", to.first_seen}};
      entry["distance"] = move->second.distance;
    }
    stamp(std::move(entry));
  }
  if (context.session > 0) {
    for (const ObjectRecord& object : live.objects) {
      if (object.first_session != context.session || moved_to.count(object.id) > 0) continue;
      stamp({{"type", "added"},
             {"timestamp", object.first_seen},
             {"object_id", object.id},
             {"class_id", object.class_id},
             {"class", CocoClassName(object.class_id)},
             {"centroid", VectorJson(object.cuboid.centre)},
             {"cuboid", CuboidJson(object.cuboid)},
             {"reason", "first seen in this session"}});
    }
  }
  root["changes"] = list;
  return root.dump(1) + "\n";
}

}  // namespace ocg
