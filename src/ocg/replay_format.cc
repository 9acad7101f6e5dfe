#include "ocg/ocg/replay_format.h"

#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "ocg/core/coco.h"
#include "ocg/core/whole_number.h"

namespace ocg {
namespace {

using nlohmann::json;

const json& Field(const json& object, const char* name) {
  const auto it = object.find(name);
  if (it == object.end()) throw ReplayFormatError(std::string("missing field \"") + name + "\"");
  return *it;
}

Eigen::Vector3d Vector3FromJson(const json& value, const std::string& what) {
  if (!value.is_array() || value.size() != 3) {
    throw ReplayFormatError(what + " must be a list of 3 numbers");
  }
  Eigen::Vector3d vector;
  for (int i = 0; i < 3; ++i) {
    if (!value[i].is_number()) throw ReplayFormatError(what + " must be a list of 3 numbers");
    vector[i] = value[i].get<double>();
  }
  return vector;
}

// A whole number of type Int; what names the field in the error.
template <typename Int>
Int WholeNumberField(const json& value, const std::string& what) {
  const std::optional<Int> number = JsonWholeNumberAs<Int>(value);
  if (!number) {
    throw ReplayFormatError("wrong type: " + what + " must be a whole number in [" +
                            std::to_string(std::numeric_limits<Int>::lowest()) + ", " +
                            std::to_string(std::numeric_limits<Int>::max()) + "], got " +
                            value.dump());
  }
  return *number;
}

std::vector<ObjectId> ObjectIdList(const json& value, const std::string& what) {
  if (!value.is_array()) throw ReplayFormatError(what + " must be a list of object ids");
  std::vector<ObjectId> ids;
  ids.reserve(value.size());
  for (const json& id : value) ids.push_back(WholeNumberField<ObjectId>(id, what + " entry"));
  return ids;
}

ObjectId ParseObjectKey(const std::string& key, const char* field) {
  try {
    size_t used = 0;
    const long long id = std::stoll(key, &used);
    if (used == key.size()) return id;
  } catch (const std::exception&) {
  }
  throw ReplayFormatError(std::string("\"") + field + "\" key '" + key + "' is not an object id");
}

}  // namespace

KeyframeObservation ParseObservationJson(const std::string& line) {
  json root;
  try {
    root = json::parse(line);
  } catch (const json::exception& error) {  // parse_error; out_of_range for 1e999
    throw ReplayFormatError(std::string("not valid JSON: ") + error.what());
  }
  if (!root.is_object()) throw ReplayFormatError("expected a JSON object");
  try {
    KeyframeObservation observation;
    observation.keyframe_id =
        WholeNumberField<std::int64_t>(Field(root, "keyframe"), "\"keyframe\"");
    observation.timestamp = root.value("timestamp", 0.0);
    const json& pose = Field(root, "T_cw");
    if (!pose.is_array() || pose.size() != 16) {
      throw ReplayFormatError("\"T_cw\" must be 16 numbers, a row-major 4x4 matrix");
    }
    Eigen::Matrix4d matrix;
    for (int i = 0; i < 16; ++i) matrix(i / 4, i % 4) = pose[i].get<double>();
    const Eigen::Matrix3d rotation = matrix.topLeftCorner<3, 3>();
    if ((rotation * rotation.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-3 ||
        rotation.determinant() < 0) {
      throw ReplayFormatError("\"T_cw\" rotation block is not a rotation");
    }
    observation.T_cw = SE3::FromMatrix(matrix);
    const json& camera = Field(root, "camera");
    observation.camera.fx = Field(camera, "fx").get<double>();
    observation.camera.fy = Field(camera, "fy").get<double>();
    observation.camera.cx = Field(camera, "cx").get<double>();
    observation.camera.cy = Field(camera, "cy").get<double>();
    observation.camera.width = WholeNumberField<int>(Field(camera, "width"), "\"camera\" width");
    observation.camera.height = WholeNumberField<int>(Field(camera, "height"), "\"camera\" height");
    PinholeCamera& model = observation.camera;
    const std::pair<const char*, double*> distortion[] = {{"k1", &model.k1},
                                                          {"k2", &model.k2},
                                                          {"k3", &model.k3},
                                                          {"p1", &model.p1},
                                                          {"p2", &model.p2}};
    for (const auto& [name, coefficient] : distortion) {
      if (camera.contains(name)) *coefficient = camera.at(name).get<double>();
    }
    try {
      observation.camera.Check();
    } catch (const std::invalid_argument& error) {
      throw ReplayFormatError(std::string("\"camera\": ") + error.what());
    }
    observation.observed = ObjectIdList(Field(root, "observed"), "\"observed\"");
    if (root.contains("centroids")) {
      for (const auto& [key, value] : root.at("centroids").items()) {
        observation.updates[ParseObjectKey(key, "centroids")].centroid =
            Vector3FromJson(value, "centroid of object " + key);
      }
    }
    if (root.contains("sizes")) {
      for (const auto& [key, value] : root.at("sizes").items()) {
        observation.updates[ParseObjectKey(key, "sizes")].size =
            Vector3FromJson(value, "size of object " + key);
      }
    }
    if (root.contains("classes")) {
      for (const auto& [key, value] : root.at("classes").items()) {
        observation.updates[ParseObjectKey(key, "classes")].class_id =
            WholeNumberField<int>(value, "class of object " + key);
      }
    }
    if (root.contains("forgotten")) {
      observation.forgotten = ObjectIdList(root.at("forgotten"), "\"forgotten\"");
    }
    if (root.contains("present_by_points")) {
      observation.present_by_points =
          ObjectIdList(root.at("present_by_points"), "\"present_by_points\"");
    }
    if (root.contains("restored")) {
      observation.restored = ObjectIdList(root.at("restored"), "\"restored\"");
    }
    return observation;
  } catch (const json::exception& error) {
    throw ReplayFormatError(std::string("wrong type: ") + error.what());
  }
}

std::string ObservationToJson(const KeyframeObservation& observation) {
  json pose = json::array();
  const Eigen::Matrix4d matrix = observation.T_cw.Matrix();
  for (int i = 0; i < 16; ++i) pose.push_back(matrix(i / 4, i % 4));
  const PinholeCamera& camera = observation.camera;
  json camera_json = {{"fx", camera.fx}, {"fy", camera.fy},       {"cx", camera.cx},
                      {"cy", camera.cy}, {"width", camera.width}, {"height", camera.height}};
  if (camera.HasDistortion()) {
    camera_json.update({{"k1", camera.k1},
                        {"k2", camera.k2},
                        {"k3", camera.k3},
                        {"p1", camera.p1},
                        {"p2", camera.p2}});
  }
  json root = {{"keyframe", observation.keyframe_id},
               {"timestamp", observation.timestamp},
               {"T_cw", pose},
               {"camera", camera_json},
               {"observed", observation.observed}};
  json centroids = json::object(), sizes = json::object(), classes = json::object();
  for (const auto& [id, update] : observation.updates) {
    const std::string key = std::to_string(id);
    if (update.centroid) {
      centroids[key] = {update.centroid->x(), update.centroid->y(), update.centroid->z()};
    }
    if (update.size) sizes[key] = {update.size->x(), update.size->y(), update.size->z()};
    if (update.class_id) classes[key] = *update.class_id;
  }
  root["centroids"] = centroids;
  if (!sizes.empty()) root["sizes"] = sizes;
  if (!classes.empty()) root["classes"] = classes;
  if (!observation.forgotten.empty()) root["forgotten"] = observation.forgotten;
  if (!observation.restored.empty()) root["restored"] = observation.restored;
  if (!observation.present_by_points.empty())
    root["present_by_points"] = observation.present_by_points;
  return root.dump();
}

std::string StatesLineJson(std::int64_t keyframe_id, const std::vector<ObjectStatus>& objects,
                           const std::vector<RemovalEvent>& removed) {
  json list = json::array();
  for (const ObjectStatus& status : objects) {
    list.push_back({{"id", status.id},
                    {"state", static_cast<int>(status.state)},
                    {"doubt", status.doubt},
                    {"active_edge_rate", status.active_edge_rate}});
  }
  json removed_ids = json::array();
  for (const RemovalEvent& event : removed) removed_ids.push_back(event.object_id);
  return json({{"keyframe", keyframe_id}, {"objects", list}, {"removed", removed_ids}}).dump();
}

std::string ChangeLogJson(const std::vector<RemovalEvent>& removals) {
  json changes = json::array();
  for (const RemovalEvent& event : removals) {
    json centroid = nullptr;
    if (event.centroid) centroid = {event.centroid->x(), event.centroid->y(), event.centroid->z()};
    changes.push_back({{"type", "removed"},
                       {"keyframe", event.keyframe_id},
                       {"timestamp", event.timestamp},
                       {"object_id", event.object_id},
                       {"class_id", event.class_id},
                       {"class", CocoClassName(event.class_id)},
                       {"centroid", centroid},
                       {"doubt", event.doubt},
                       {"reason", event.reason}});
  }
  return json({{"changes", changes}}).dump(1) + "\n";
}

}  // namespace ocg
