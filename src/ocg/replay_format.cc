#include "ocg/ocg/replay_format.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "ocg/core/coco.h"
#include "ocg/core/whole_number.h"

namespace ocg {
namespace {

using nlohmann::json;

// The JSON form of each type a field of the observation has (VisitObservationFields);
// `what` names the field in errors. A field of a new type needs its Decode and Encode here.

// A whole number of type Int.
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

double NumberField(const json& value, const std::string& what) {
  if (!value.is_number()) {
    throw ReplayFormatError("wrong type: " + what + " must be a number, got " + value.dump());
  }
  return value.get<double>();
}

void Decode(const json& value, const ObservationField&, const std::string& what,
            std::int64_t* number) {
  *number = WholeNumberField<std::int64_t>(value, what);
}
void Decode(const json& value, const ObservationField&, const std::string& what, int* number) {
  *number = WholeNumberField<int>(value, what);
}
void Decode(const json& value, const ObservationField&, const std::string& what, double* number) {
  *number = NumberField(value, what);
}

void Decode(const json& value, const ObservationField&, const std::string& what, SE3* pose) {
  if (!value.is_array() || value.size() != 16) {
    throw ReplayFormatError(what + " must be 16 numbers, a row-major 4x4 matrix");
  }
  Eigen::Matrix4d matrix;
  for (int i = 0; i < 16; ++i) matrix(i / 4, i % 4) = NumberField(value[i], what + " entry");
  try {
    *pose = RigidMotionFromMatrix(matrix);
  } catch (const std::invalid_argument& error) {
    throw ReplayFormatError(what + " " + error.what());
  }
}

void Decode(const json& value, const ObservationField&, const std::string& what,
            std::vector<ObjectId>* ids) {
  if (!value.is_array()) throw ReplayFormatError(what + " must be a list of object ids");
  ids->clear();
  ids->reserve(value.size());
  for (const json& id : value) ids->push_back(WholeNumberField<ObjectId>(id, what + " entry"));
}

void Decode(const json& value, const ObservationField& field, const std::string& what,
            std::optional<Eigen::Vector3d>* vector) {
  if (!value.is_array() || value.size() != 3 ||
      !std::all_of(value.begin(), value.end(), [](const json& x) { return x.is_number(); })) {
    throw ReplayFormatError(what + " must be a list of 3 numbers");
  }
  vector->emplace(value[0].get<double>(), value[1].get<double>(), value[2].get<double>());
  if (field.non_negative && ((*vector)->array() < 0).any()) {
    throw ReplayFormatError(what + " must be non-negative, got " + value.dump());
  }
}

void Decode(const json& value, const ObservationField& field, const std::string& what,
            std::optional<int>* number) {
  Decode(value, field, what, &number->emplace());
}

// Throws when object holds a key that is not one of the fields visit_fields lists.
template <typename VisitFields>
void CheckKeysKnown(const json& object, const std::string& where, VisitFields&& visit_fields) {
  for (const auto& [key, value] : object.items()) {
    if (const auto known = KnownNamesIfUnlisted(key, visit_fields)) {
      throw ReplayFormatError("unknown field \"" + key + "\"" + where + " (known: " + *known + ")");
    }
  }
}

void Decode(const json& value, const ObservationField&, const std::string& what,
            PinholeCamera* camera) {
  if (!value.is_object()) throw ReplayFormatError(what + " must be an object");
  CheckKeysKnown(value, " in " + what,
                 [camera](auto&& visit) { VisitCameraFields(visit, *camera); });
  VisitCameraFields(
      [&](const ObservationField& field, auto& member) {
        const auto it = value.find(field.name);
        if (it == value.end()) {
          if (field.optional()) return;
          throw ReplayFormatError(std::string("missing field \"") + field.name + "\" in " + what);
        }
        Decode(*it, field, what + " " + field.name, &member);
      },
      *camera);
  try {
    camera->Check();
  } catch (const std::invalid_argument& error) {
    throw ReplayFormatError(what + ": " + error.what());
  }
}

json Encode(std::int64_t number) { return number; }
json Encode(double number) { return number; }
json Encode(const SE3& pose) {
  json matrix_json = json::array();
  const Eigen::Matrix4d matrix = pose.Matrix();
  for (int i = 0; i < 16; ++i) matrix_json.push_back(matrix(i / 4, i % 4));
  return matrix_json;
}
json Encode(const std::vector<ObjectId>& ids) { return ids; }
json Encode(const Eigen::Vector3d& vector) { return {vector.x(), vector.y(), vector.z()}; }
json Encode(int number) { return number; }
json Encode(const PinholeCamera& camera) {
  json camera_json = json::object();
  VisitCameraFields(
      [&](const ObservationField& field, const auto& member) {
        // The distortion coefficients go together: all when the camera has distortion.
        if (field.written_when_empty() || camera.HasDistortion())
          camera_json[field.name] = Encode(member);
      },
      camera);
  return camera_json;
}

bool IsEmpty(const std::vector<ObjectId>& ids) { return ids.empty(); }
template <typename Value>
bool IsEmpty(const Value&) {
  return false;
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

std::string FieldHelp(const ObservationField& field, const char* type) {
  std::string text = std::string(field.name) + ": " + type;
  if (field.unit[0] != '\0') text += ", " + std::string(field.unit);
  if (field.non_negative) text += ", not negative";
  text += std::string(field.optional() ? " (optional)" : "") + "; " + field.meaning + ".\n";
  return text;
}

std::string Quoted(const char* name) { return std::string("\"") + name + "\""; }

}  // namespace

SE3 RigidMotionFromMatrix(const Eigen::Matrix4d& matrix) {
  if (!matrix.allFinite()) throw std::invalid_argument("has NaN or infinite entries");
  if ((matrix.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-9) {
    throw std::invalid_argument("last row must be [0, 0, 0, 1]");
  }
  const Eigen::Matrix3d rotation = matrix.topLeftCorner<3, 3>();
  if ((rotation * rotation.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-3 ||
      rotation.determinant() < 0) {
    throw std::invalid_argument("rotation block is not a rotation");
  }
  return SE3::FromMatrix(matrix);
}

std::string ObservationFieldsHelp() {
  std::string text;
  const auto add = [&text](const ObservationField& field, const auto& member) {
    text += FieldHelp(field, ObservationFieldType(member));
  };
  const KeyframeObservation observation;
  VisitObservationFields(add, observation);
  const ObjectGeometryUpdate update;
  VisitObjectUpdateFields(add, update);
  return text;
}

std::string ObservationFieldsMarkdown() {
  std::string text =
      "<!-- settings-table observation -->\n"
      "| field | form | unit | when absent | meaning |\n"
      "|---|---|---|---|---|\n";
  const auto add = [&text](const ObservationField& field, const auto& member) {
    const char* absent = !field.optional()            ? "an error"
                         : field.written_when_empty() ? "empty or 0; always written"
                                                      : "empty; written when not";
    text += std::string("| `") + field.name + "` | " + ObservationFieldType(member) + " | " +
            (*field.unit != '\0' ? field.unit : "") + " | " + absent + " | " + field.meaning +
            " |\n";
  };
  const KeyframeObservation observation;
  VisitObservationFields(add, observation);
  const ObjectGeometryUpdate update;
  VisitObjectUpdateFields(add, update);
  return text + "<!-- end settings-table -->\n";
}

KeyframeObservation ParseObservationJson(const std::string& line) {
  json root;
  try {
    root = json::parse(line);
  } catch (const json::exception& error) {  // parse_error; out_of_range for 1e999
    throw ReplayFormatError(std::string("not valid JSON: ") + error.what());
  }
  if (!root.is_object()) throw ReplayFormatError("expected a JSON object");
  KeyframeObservation observation;
  ObjectGeometryUpdate prototype;
  CheckKeysKnown(root, "", [&](auto&& visit) {
    VisitObservationFields(visit, observation);
    VisitObjectUpdateFields(visit, prototype);
  });
  VisitObservationFields(
      [&](const ObservationField& field, auto& member) {
        const auto it = root.find(field.name);
        if (it == root.end()) {
          if (field.optional()) return;
          throw ReplayFormatError("missing field " + Quoted(field.name));
        }
        Decode(*it, field, Quoted(field.name), &member);
      },
      observation);
  VisitObjectUpdateFields(
      [&](const ObservationField& field, const auto&) {
        const auto entries = root.find(field.name);
        if (entries == root.end()) return;
        if (!entries->is_object()) {
          throw ReplayFormatError(Quoted(field.name) +
                                  " must be an object {object id: " + field.entry + "}");
        }
        for (const auto& [key, value] : entries->items()) {
          // This field's member of the object's update.
          VisitObjectUpdateFields(
              [&, &key = key, &value = value](const ObservationField& other, auto& member) {
                if (std::strcmp(other.name, field.name) == 0)
                  Decode(value, field, std::string(field.entry) + " of object " + key, &member);
              },
              observation.updates[ParseObjectKey(key, field.name)]);
        }
      },
      prototype);
  return observation;
}

std::string ObservationToJson(const KeyframeObservation& observation) {
  json root = json::object();
  VisitObservationFields(
      [&](const ObservationField& field, const auto& member) {
        if (field.written_when_empty() || !IsEmpty(member)) root[field.name] = Encode(member);
      },
      observation);
  // Per-object values, one {id: value} map per field.
  json per_object = json::object();
  for (const auto& [id, update] : observation.updates) {
    VisitObjectUpdateFields(
        [&, &id = id](const ObservationField& field, const auto& member) {
          if (member) per_object[field.name][std::to_string(id)] = Encode(*member);
        },
        update);
  }
  const ObjectGeometryUpdate prototype;
  VisitObjectUpdateFields(
      [&](const ObservationField& field, const auto&) {
        if (per_object.contains(field.name)) {
          root[field.name] = per_object[field.name];
        } else if (field.written_when_empty()) {
          root[field.name] = json::object();
        }
      },
      prototype);
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
