#include "ocg/objects/object_change.h"

#include <nlohmann/json.hpp>
#include <set>
#include <utility>

#include "ocg/core/coco.h"
#include "ocg/io/change_entries.h"
#include "ocg/io/text_lines.h"
#include "ocg/objects/cuboid_json.h"

namespace ocg {
namespace {

nlohmann::json LookJson(const PairingLook& look) {
  nlohmann::json json = nlohmann::json::object();
  if (look.match) {
    json["matched"] = look.match->matched;
    json["compared"] = look.match->compared;
    json["median_distance"] = look.match->median_distance;
    json["from"] = look.from_boxes ? "boxes" : "map points";
  }
  if (look.colour_similarity) json["colour_similarity"] = *look.colour_similarity;
  return json;
}

PairingLook LookFromJson(const nlohmann::json& json) {
  PairingLook look;
  if (json.contains("matched")) {
    AppearanceMatch match;
    match.matched = json.at("matched").get<int>();
    match.compared = json.at("compared").get<int>();
    match.median_distance = json.at("median_distance").get<int>();
    look.match = match;
    look.from_boxes = json.at("from").get<std::string>() == "boxes";
  }
  if (json.contains("colour_similarity"))
    look.colour_similarity = json.at("colour_similarity").get<double>();
  return look;
}

nlohmann::json EntryJson(const ChangeEntry& entry, bool with_time) {
  nlohmann::json json = {{"type", entry.type},
                         {"session", entry.session},
                         {"timestamp", entry.timestamp},
                         {"object_id", entry.object_id},
                         {"class_id", entry.class_id},
                         {"class", CocoClassName(entry.class_id)},
                         {"centroid", VectorJson(entry.cuboid.centre)},
                         {"cuboid", CuboidJson(entry.cuboid)},
                         {"reason", entry.reason}};
  if (entry.keyframe) json["keyframe"] = *entry.keyframe;
  if (entry.observations) json["observations"] = *entry.observations;
  if (entry.doubt) json["doubt"] = *entry.doubt;
  if (entry.last_seen) json["last_seen"] = *entry.last_seen;
  if (entry.merged_into) json["merged_into"] = *entry.merged_into;
  if (entry.recreated_as) json["recreated_as"] = *entry.recreated_as;
  if (entry.removed_at) json["removed_at"] = *entry.removed_at;
  if (entry.to) {
    json["to"] = {{"object_id", entry.to->object_id},
                  {"cuboid", CuboidJson(entry.to->cuboid)},
                  {"first_seen", entry.to->first_seen}};
  }
  if (entry.distance) json["distance"] = *entry.distance;
  if (entry.appearance) json["appearance"] = LookJson(*entry.appearance);
  if (entry.candidates) {
    json["candidates"] = nlohmann::json::array();
    for (const PairingCandidate& candidate : *entry.candidates) {
      nlohmann::json item = {{"object_id", candidate.object_id},
                             {"distance", candidate.distance},
                             {"observations", candidate.observations}};
      if (candidate.appearance) item["appearance"] = LookJson(*candidate.appearance);
      json["candidates"].push_back(std::move(item));
    }
  }
  if (with_time) json["time"] = entry.time ? nlohmann::json(*entry.time) : nlohmann::json();
  return json;
}

ChangeEntry EntryFromJson(const nlohmann::json& json) {
  // Keys EntryJson writes that the fields below do not hold: the class name and the
  // centroid follow from the class and the cuboid.
  static const std::set<std::string> known = {
      "type",       "session",     "timestamp",    "object_id",  "class_id",     "class",
      "centroid",   "cuboid",      "reason",       "keyframe",   "observations", "doubt",
      "last_seen",  "merged_into", "recreated_as", "removed_at", "to",           "distance",
      "appearance", "candidates",  "time"};
  for (const auto& [key, value] : json.items()) {
    if (known.count(key) == 0) throw std::invalid_argument("unknown key \"" + key + "\"");
  }
  ChangeEntry entry;
  entry.type = json.at("type").get<std::string>();
  entry.session = json.at("session").get<int>();
  entry.timestamp = json.at("timestamp").get<double>();
  entry.object_id = json.at("object_id").get<ObjectId>();
  entry.class_id = json.at("class_id").get<int>();
  entry.cuboid = CuboidFromJson(json.at("cuboid"));
  entry.reason = json.at("reason").get<std::string>();
  const auto optional = [&json](const char* key, auto* field) {
    using Value = typename std::remove_reference_t<decltype(*field)>::value_type;
    if (json.contains(key)) *field = json.at(key).get<Value>();
  };
  optional("keyframe", &entry.keyframe);
  optional("observations", &entry.observations);
  optional("doubt", &entry.doubt);
  optional("last_seen", &entry.last_seen);
  optional("merged_into", &entry.merged_into);
  optional("recreated_as", &entry.recreated_as);
  optional("removed_at", &entry.removed_at);
  optional("distance", &entry.distance);
  if (json.contains("to")) {
    const nlohmann::json& to = json.at("to");
    entry.to = MoveDestination{to.at("object_id").get<ObjectId>(), CuboidFromJson(to.at("cuboid")),
                               to.at("first_seen").get<double>()};
  }
  if (json.contains("appearance")) entry.appearance = LookFromJson(json.at("appearance"));
  if (json.contains("candidates")) {
    entry.candidates.emplace();
    for (const nlohmann::json& item : json.at("candidates")) {
      PairingCandidate candidate;
      candidate.object_id = item.at("object_id").get<ObjectId>();
      candidate.distance = item.at("distance").get<double>();
      candidate.observations = item.at("observations").get<int>();
      if (item.contains("appearance")) candidate.appearance = LookFromJson(item.at("appearance"));
      entry.candidates->push_back(candidate);
    }
  }
  if (json.contains("time") && !json.at("time").is_null())
    entry.time = json.at("time").get<double>();
  return entry;
}

}  // namespace

ChangeEntry EntryOf(const ObjectChange& change) {
  ChangeEntry entry;
  entry.type = change.type;
  entry.session = change.session;
  entry.keyframe = change.keyframe_id;
  entry.timestamp = change.timestamp;
  entry.object_id = change.object_id;
  entry.class_id = change.class_id;
  entry.cuboid = change.cuboid;
  entry.observations = change.sightings;
  if (change.type == "removed") {
    entry.doubt = change.doubt;
    entry.last_seen = change.last_seen;
    entry.reason = change.reason.empty() ? "outlier" : change.reason;
  } else if (change.type == "merged") {
    entry.merged_into = change.merged_into;
    entry.reason = "duplicate";
  } else if (change.type == "restored") {
    entry.recreated_as = change.recreated_as;
    entry.removed_at = change.removed_at;
    entry.reason = "detected again at its place";
  } else {
    entry.reason = "too few sightings";
  }
  return entry;
}

std::vector<ChangeEntry> EntriesOf(const std::vector<ObjectChange>& changes) {
  std::vector<ChangeEntry> entries;
  entries.reserve(changes.size());
  for (const ObjectChange& change : changes) entries.push_back(EntryOf(change));
  return entries;
}

std::vector<bool> StandingRemovals(const std::vector<ChangeEntry>& entries) {
  return StandingRemovalsBy(entries.size(), [&entries](std::size_t i) {
    return std::make_pair(entries[i].type, entries[i].object_id);
  });
}

std::string ChangeLogJson(const std::vector<ChangeEntry>& entries, bool with_time) {
  nlohmann::json list = nlohmann::json::array();
  for (const ChangeEntry& entry : entries) list.push_back(EntryJson(entry, with_time));
  return nlohmann::json({{"changes", list}}).dump(1) + "\n";
}

std::vector<ChangeEntry> ParseChangeLog(const std::string& text, const std::string& name) {
  std::vector<ChangeEntry> entries;
  try {
    const nlohmann::json root = nlohmann::json::parse(text);
    for (const nlohmann::json& entry : root.at("changes")) entries.push_back(EntryFromJson(entry));
  } catch (const std::exception& error) {
    throw ParseError(name + ": entry " + std::to_string(entries.size()) + ": " + error.what());
  }
  return entries;
}

}  // namespace ocg
