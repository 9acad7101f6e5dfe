// objects.json (SPEC 5) and the live objects as the change log reads them: the object
// map's edge to its outputs (declared in object_map.h).

#include <algorithm>
#include <map>
#include <nlohmann/json.hpp>
#include <utility>

#include "ocg/core/coco.h"
#include "ocg/objects/cuboid_json.h"
#include "ocg/objects/object_map.h"

namespace ocg {

namespace {

// Sessions (map files): the first and the last that saw the object (0 and 0 without
// sightings).
std::pair<int, int> SessionsOf(const MapObject& object) { return object.sightings.SessionRange(); }

}  // namespace

std::vector<ObjectRecord> LiveObjectRecords(const ObjectMap& map) {
  std::vector<ObjectRecord> records;
  for (const auto& [id, object] : map.objects()) {
    ObjectRecord record;
    record.id = id;
    record.class_id = object.class_id;
    record.cuboid = object.cuboid;
    record.first_seen = object.first_timestamp;
    record.last_seen = object.last_timestamp;
    record.first_session = SessionsOf(object).first;
    record.observations = static_cast<int>(object.sightings.total());
    records.push_back(record);
  }
  return records;
}

std::string ObjectsJson(const ObjectMap& map, const std::vector<ObjectStatus>& states) {
  std::map<ObjectId, const ObjectStatus*> by_id;
  for (const ObjectStatus& status : states) by_id[status.id] = &status;
  nlohmann::json objects = nlohmann::json::array();
  for (const auto& [id, object] : map.objects()) {
    const auto [first_session, last_session] = SessionsOf(object);
    nlohmann::json entry = {
        {"id", id},
        {"class_id", object.class_id},
        {"class", CocoClassName(object.class_id)},
        {"cuboid", CuboidJson(object.cuboid)},
        {"yaw_from", object.yaw_from_points ? "map points" : "boxes"},
        {"observations", object.sightings.total()},
        {"map_points", ObjectPointSet(object, map.options().min_point_votes).size()},
        {"first_seen", object.first_timestamp},
        {"last_seen", object.last_timestamp},
        {"first_session", first_session},
        {"last_session", last_session},
        {"state", nullptr},
        {"doubt", nullptr}};
    const auto status = by_id.find(id);
    if (status != by_id.end()) {
      entry["state"] = static_cast<int>(status->second->state);
      entry["doubt"] = status->second->doubt;
    }
    objects.push_back(entry);
  }
  const Eigen::Vector3d up = map.gravity_frame().col(2);
  return nlohmann::json({{"format", "ocg-objects"},
                         {"version", 1},
                         {"up", VectorJson(up)},
                         {"objects", objects}})
             .dump(1) +
         "\n";
}

}  // namespace ocg
