// The OCG's keyframe input as a Python dict, read and written from its one field list
// (VisitObservationFields, VisitObjectUpdateFields, VisitCameraFields in
// ocg/ocg/observation.h): the dict's keys are the replay format's (SPEC 3.1), so a field
// added there is accepted here with no change to this file.

#include <pybind11/stl.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "bindings.h"
#include "ocg/ocg/replay_format.h"

namespace py = pybind11;

namespace ocg::python {
namespace {

using Numbers = py::array_t<double, py::array::c_style | py::array::forcecast>;

[[noreturn]] void Wrong(const std::string& what, const std::string& expected, py::handle value) {
  throw py::value_error(what + " must be " + expected + ", got " + std::string(py::repr(value)));
}

// Python's values into the observation's types; `what` names the field in errors. A field
// of a new type needs its Decode and Encode here.

template <typename Int>
Int IntegerFrom(py::handle value, const std::string& what) {
  const std::string expected = "an integer in [" +
                               std::to_string(std::numeric_limits<Int>::lowest()) + ", " +
                               std::to_string(std::numeric_limits<Int>::max()) + "]";
  if (py::isinstance<py::bool_>(value)) Wrong(what, expected, value);
  try {
    return value.cast<Int>();
  } catch (const py::cast_error&) {
    Wrong(what, expected, value);
  }
}

void Decode(py::handle value, const ObservationField&, const std::string& what,
            std::int64_t* number) {
  *number = IntegerFrom<std::int64_t>(value, what);
}
void Decode(py::handle value, const ObservationField&, const std::string& what, int* number) {
  *number = IntegerFrom<int>(value, what);
}

void Decode(py::handle value, const ObservationField& field, const std::string& what,
            double* number) {
  if (py::isinstance<py::bool_>(value) || py::isinstance<py::str>(value)) {
    Wrong(what, "a number", value);
  }
  try {
    *number = value.cast<double>();
  } catch (const py::cast_error&) {
    Wrong(what, "a number", value);
  }
  if (!std::isfinite(*number)) throw py::value_error(what + " is not finite");
  if (field.non_negative && *number < 0) Wrong(what, "non-negative", value);
}

Numbers NumbersFrom(py::handle value, const std::string& what, const std::string& expected) {
  if (py::isinstance<py::str>(value)) Wrong(what, expected, value);
  Numbers numbers = Numbers::ensure(value);
  if (!numbers) Wrong(what, expected, value);
  return numbers;
}

void Decode(py::handle value, const ObservationField&, const std::string& what, SE3* pose) {
  const std::string expected = "a (4, 4) matrix or 16 numbers, row-major";
  const Numbers numbers = NumbersFrom(value, what, expected);
  const bool square = numbers.ndim() == 2 && numbers.shape(0) == 4 && numbers.shape(1) == 4;
  if (!square && !(numbers.ndim() == 1 && numbers.shape(0) == 16)) Wrong(what, expected, value);
  Eigen::Matrix4d matrix;
  for (int i = 0; i < 16; ++i) matrix(i / 4, i % 4) = numbers.data()[i];
  try {
    *pose = RigidMotionFromMatrix(matrix);
  } catch (const std::invalid_argument& error) {
    throw py::value_error(what + " " + error.what());
  }
}

void Decode(py::handle value, const ObservationField& field, const std::string& what,
            std::optional<Eigen::Vector3d>* vector) {
  const std::string expected = "3 numbers";
  const Numbers numbers = NumbersFrom(value, what, expected);
  if (numbers.ndim() != 1 || numbers.shape(0) != 3) Wrong(what, expected, value);
  vector->emplace(numbers.data()[0], numbers.data()[1], numbers.data()[2]);
  if (!(*vector)->allFinite()) throw py::value_error(what + " is not finite");
  if (field.non_negative && ((*vector)->array() < 0).any()) Wrong(what, "non-negative", value);
}

void Decode(py::handle value, const ObservationField& field, const std::string& what,
            std::optional<int>* number) {
  Decode(value, field, what, &number->emplace());
}

bool IsIterableNotText(py::handle value) {
  return py::isinstance<py::iterable>(value) && !py::isinstance<py::str>(value) &&
         !py::isinstance<py::bytes>(value) && !py::isinstance<py::dict>(value);
}

void Decode(py::handle value, const ObservationField&, const std::string& what,
            std::vector<ObjectId>* ids) {
  if (!IsIterableNotText(value)) Wrong(what, "a sequence of object ids", value);
  ids->clear();
  for (py::handle id : py::reinterpret_borrow<py::iterable>(value)) {
    ids->push_back(IntegerFrom<ObjectId>(id, what + "[" + std::to_string(ids->size()) + "]"));
  }
}

// Throws naming the first key of values that visit_fields does not list.
template <typename VisitFields>
void CheckKeysKnown(const py::dict& values, const std::string& where, VisitFields&& visit_fields) {
  for (const auto& [key, value] : values) {
    const std::string name = py::str(key);
    if (const auto known = KnownNamesIfUnlisted(name, visit_fields)) {
      throw py::value_error(where + "unknown field '" + name + "' (known: " + *known + ")");
    }
  }
}

void Decode(py::handle value, const ObservationField&, const std::string& what,
            PinholeCamera* camera) {
  if (py::isinstance<PinholeCamera>(value)) {
    *camera = value.cast<PinholeCamera>();
  } else if (py::isinstance<py::dict>(value)) {
    const auto fields = py::reinterpret_borrow<py::dict>(value);
    CheckKeysKnown(fields, what + ": ",
                   [camera](auto&& visit) { VisitCameraFields(visit, *camera); });
    VisitCameraFields(
        [&](const ObservationField& field, auto& member) {
          if (!fields.contains(field.name)) {
            if (field.optional()) return;
            throw py::value_error(what + ": missing field '" + field.name + "'");
          }
          Decode(fields[field.name], field, what + "." + field.name, &member);
        },
        *camera);
  } else {
    Wrong(what, "an ocg.PinholeCamera or a dict of its fields", value);
  }
  try {
    camera->Check();
  } catch (const std::invalid_argument& error) {
    throw py::value_error(what + ": " + error.what());
  }
}

// An object id as a dict key: an int, or its digits as a str (a dict from json.loads).
ObjectId ObjectKey(py::handle key, const std::string& what) {
  if (py::isinstance<py::str>(key)) {
    const std::string text = py::str(key);
    try {
      size_t used = 0;
      const long long id = std::stoll(text, &used);
      if (used == text.size()) return id;
    } catch (const std::exception&) {
    }
    Wrong(what + " key", "an object id", key);
  }
  return IntegerFrom<ObjectId>(key, what + " key");
}

py::object Encode(std::int64_t number) { return py::int_(number); }
py::object Encode(int number) { return py::int_(number); }
py::object Encode(double number) { return py::float_(number); }
py::object Encode(const SE3& pose) {
  const Eigen::Matrix4d matrix = pose.Matrix();
  py::list rows;
  for (int r = 0; r < 4; ++r) {
    py::list row;
    for (int c = 0; c < 4; ++c) row.append(matrix(r, c));
    rows.append(row);
  }
  return std::move(rows);
}
py::object Encode(const Eigen::Vector3d& vector) {
  py::list list;
  for (int i = 0; i < 3; ++i) list.append(vector[i]);
  return std::move(list);
}
py::object Encode(const std::vector<ObjectId>& ids) { return py::cast(ids); }
py::object Encode(const PinholeCamera& camera) {
  py::dict fields;
  VisitCameraFields([&](const ObservationField& field,
                        const auto& member) { fields[field.name] = Encode(member); },
                    camera);
  return std::move(fields);
}

}  // namespace

KeyframeObservation ObservationFromPython(py::handle value) {
  if (!py::isinstance<py::dict>(value)) Wrong("an observation", "a dict", value);
  const auto fields = py::reinterpret_borrow<py::dict>(value);
  KeyframeObservation observation;
  ObjectGeometryUpdate prototype;
  CheckKeysKnown(fields, "observation: ", [&](auto&& visit) {
    VisitObservationFields(visit, observation);
    VisitObjectUpdateFields(visit, prototype);
  });
  VisitObservationFields(
      [&](const ObservationField& field, auto& member) {
        if (!fields.contains(field.name)) {
          if (field.optional()) return;
          throw py::value_error(std::string("observation: missing field '") + field.name + "'");
        }
        Decode(fields[field.name], field, field.name, &member);
      },
      observation);
  VisitObjectUpdateFields(
      [&](const ObservationField& field, const auto&) {
        if (!fields.contains(field.name)) return;
        const py::object entries = fields[field.name];
        if (!py::isinstance<py::dict>(entries)) {
          Wrong(field.name, std::string("a dict {object id: ") + field.entry + "}", entries);
        }
        for (const auto& [key, entry] : py::reinterpret_borrow<py::dict>(entries)) {
          const ObjectId id = ObjectKey(key, field.name);
          // This field's member of the object's update.
          VisitObjectUpdateFields(
              [&, &entry = entry](const ObservationField& other, auto& member) {
                if (std::strcmp(other.name, field.name) != 0) return;
                const std::string what = std::string(field.name) + "[" + std::to_string(id) + "]";
                Decode(entry, field, what, &member);
              },
              observation.updates[id]);
        }
      },
      prototype);
  return observation;
}

py::dict ObservationToPython(const KeyframeObservation& observation) {
  py::dict fields;
  VisitObservationFields([&](const ObservationField& field,
                             const auto& member) { fields[field.name] = Encode(member); },
                         observation);
  const ObjectGeometryUpdate prototype;
  VisitObjectUpdateFields(
      [&](const ObservationField& field, const auto&) { fields[field.name] = py::dict(); },
      prototype);
  for (const auto& [id, update] : observation.updates) {
    VisitObjectUpdateFields(
        [&, &id = id](const ObservationField& field, const auto& member) {
          if (member) fields[field.name].cast<py::dict>()[py::int_(id)] = Encode(*member);
        },
        update);
  }
  return fields;
}

void BindObservation(py::module_& module) {
  module.def(
      "observation_fields",
      [] {
        py::list list;
        const auto add = [&](const ObservationField& field, const char* type, bool per_object) {
          py::dict entry;
          entry["name"] = field.name;
          entry["type"] = type;
          entry["unit"] = field.unit;
          entry["optional"] = field.optional();
          entry["per_object"] = per_object;
          entry["meaning"] = field.meaning;
          list.append(entry);
        };
        KeyframeObservation observation;
        VisitObservationFields(
            [&](const ObservationField& field, const auto& member) {
              add(field, ObservationFieldType(member), false);
            },
            observation);
        ObjectGeometryUpdate update;
        VisitObjectUpdateFields(
            [&](const ObservationField& field, const auto& member) {
              add(field, ObservationFieldType(member), true);
            },
            update);
        return list;
      },
      "The fields of the OCG's keyframe input, as ChangeDetector.process and the replay "
      "format (ocg_replay, SPEC 3.1) name them: a list of dicts {name, type, unit, "
      "optional, per_object, meaning}.");
  module.def(
      "observation_to_json",
      [](py::handle observation) { return ObservationToJson(ObservationFromPython(observation)); },
      py::arg("observation"),
      "One line of the replay format (ocg_replay's input) for an observation dict; raises "
      "ValueError naming a missing, unknown or wrong field.");
  module.def(
      "observation_from_json",
      [](const std::string& line) { return ObservationToPython(ParseObservationJson(line)); },
      py::arg("line"),
      "The observation dict of one line of the replay format (every field, empty ones "
      "included; T_cw as 4 rows of 4, vectors as lists); raises ocg.ReplayFormatError naming "
      "the field.");
}

}  // namespace ocg::python
