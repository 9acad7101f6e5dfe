#include "ocg/objects/change_log.h"

#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "ocg/core/coco.h"
#include "ocg/io/change_entries.h"

namespace ocg {
namespace {

nlohmann::json CuboidJson(const Cuboid& cuboid) {
  const Eigen::Vector3d& c = cuboid.centre;
  const Eigen::Vector3d& s = cuboid.size;
  return {{"centre", {c.x(), c.y(), c.z()}}, {"size", {s.x(), s.y(), s.z()}}, {"yaw", cuboid.yaw}};
}

Cuboid CuboidOf(const nlohmann::json& json) {
  Cuboid cuboid;
  const auto centre = json.at("centre").get<std::vector<double>>();
  const auto size = json.at("size").get<std::vector<double>>();
  cuboid.centre = Eigen::Vector3d(centre.at(0), centre.at(1), centre.at(2));
  cuboid.size = Eigen::Vector3d(size.at(0), size.at(1), size.at(2));
  cuboid.yaw = json.at("yaw").get<double>();
  return cuboid;
}

}  // namespace

std::string ReviseChangeLog(const std::string& changes_json, const std::string& objects_json,
                            const ChangeLogContext& context) {
  nlohmann::json root = nlohmann::json::parse(changes_json);
  const SavedObjectMap live = ParseObjectsJson(objects_json, "objects.json");
  std::vector<ObjectRecord> removed;
  std::set<ObjectId> removed_now;  // by this session
  // A removal undone by a restore (the object found again at its place) moved nowhere.
  const std::vector<bool> standing = StandingRemovals(root.at("changes"));
  for (std::size_t i = 0; i < root.at("changes").size(); ++i) {
    const nlohmann::json& entry = root.at("changes")[i];
    if (entry.at("type") != "removed" || !standing[i] || entry.at("cuboid").is_null()) continue;
    ObjectRecord record;
    record.id = entry.at("object_id").get<ObjectId>();
    record.class_id = entry.at("class_id").get<int>();
    record.cuboid = CuboidOf(entry.at("cuboid"));
    record.last_seen = entry.value("last_seen", entry.at("timestamp").get<double>());
    if (entry.value("session", context.session) == context.session) {
      removed_now.insert(record.id);
    }
    removed.push_back(record);
  }
  std::map<ObjectId, MoveLink> moves_from;
  std::set<ObjectId> moved_to;
  const auto link = [&](const std::vector<ObjectRecord>& from, const std::vector<ObjectRecord>& to,
                        const MoveLinkOptions& options) {
    for (const MoveLink& move : LinkMoves(from, to, options, true)) {
      moves_from.emplace(move.from.id, move);
      moved_to.insert(move.to.id);
    }
  };
  if (context.session > 0) {
    // Between visits nothing bounds how far an object was carried: what this session
    // removed, last seen in an earlier one, pairs first with what this session found new,
    // at any distance (nearest first).
    std::vector<ObjectRecord> left, appeared;
    for (const ObjectRecord& record : removed) {
      if (removed_now.count(record.id) > 0 && record.last_seen < context.session_start) {
        left.push_back(record);
      }
    }
    for (const ObjectRecord& object : live.objects) {
      if (object.first_session == context.session) appeared.push_back(object);
    }
    MoveLinkOptions between = context.moves;
    between.search_factor = std::numeric_limits<double>::infinity();
    link(left, appeared, between);
  }
  std::vector<ObjectRecord> rest_removed, rest_live;
  for (const ObjectRecord& record : removed) {
    if (moves_from.count(record.id) == 0) rest_removed.push_back(record);
  }
  for (const ObjectRecord& object : live.objects) {
    if (moved_to.count(object.id) == 0) rest_live.push_back(object);
  }
  link(rest_removed, rest_live, context.moves);
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
      entry["reason"] = "removed here, same class appeared near after its last sighting";
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
             {"centroid",
              {object.cuboid.centre.x(), object.cuboid.centre.y(), object.cuboid.centre.z()}},
             {"cuboid", CuboidJson(object.cuboid)},
             {"reason", "first seen in this session"}});
    }
  }
  root["changes"] = list;
  return root.dump(1) + "\n";
}

}  // namespace ocg
