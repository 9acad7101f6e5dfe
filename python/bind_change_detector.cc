// ocg.ChangeDetector: the OCG change detector (SPEC 3) for any SLAM system that can say,
// once per keyframe, its pose, its camera and which of its objects it saw.

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <cmath>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

#include "bindings.h"
#include "ocg/core/camera.h"
#include "ocg/core/settings_file.h"
#include "ocg/ocg/change_detector.h"
#include "ocg/ocg/replay_format.h"
#include "ocg/ocg/state_machine.h"

namespace py = pybind11;

namespace ocg::python {
namespace {

// What process() returns: the whole graph after one keyframe.
struct KeyframeStates {
  std::int64_t keyframe = 0;
  KeyframeObservation observation;    // what was processed
  std::vector<ObjectStatus> objects;  // ascending id
  std::vector<RemovalEvent> removed;  // this keyframe's, ascending id
};

template <typename Field>
void BindOptionField(py::class_<OcgOptions>& options, const char* name) {
  const std::string key = name;
  options.def_property(
      name,
      [key](const OcgOptions& self) {
        Field out{};
        VisitOcgOptionFields(self, [&](const char* field, const auto& value) {
          if constexpr (std::is_same_v<std::decay_t<decltype(value)>, Field>) {
            if (key == field) out = value;
          }
        });
        return out;
      },
      [key](OcgOptions& self, const Field& given) {
        VisitOcgOptionFields(self, [&](const char* field, auto& value) {
          if constexpr (std::is_same_v<std::decay_t<decltype(value)>, Field>) {
            if (key == field) value = given;
          }
        });
      });
}

void SetOptions(OcgOptions& options, const py::kwargs& values) {
  for (const auto& [key, value] : values) {
    const std::string name = py::str(key);
    bool known = false;
    VisitOcgOptionFields(options,
                         [&](const char* field, auto&) { known = known || name == field; });
    if (!known) {
      std::string names;
      VisitOcgOptionFields(options, [&](const char* field, auto&) {
        names += (names.empty() ? "" : ", ") + std::string(field);
      });
      throw py::value_error("OcgOptions: unknown option '" + name + "' (known: " + names + ")");
    }
    py::cast(&options).attr(key) = value;
  }
  options.Check();
}

void BindCamera(py::module_& module) {
  py::class_<PinholeCamera>(module, "PinholeCamera",
                            "Pinhole camera with OpenCV's radial-tangential distortion. Focal "
                            "lengths and principal point in pixels, image size in pixels.")
      .def(py::init([](double fx, double fy, double cx, double cy, int width, int height, double k1,
                       double k2, double k3, double p1, double p2) {
             PinholeCamera camera;
             camera.fx = fx, camera.fy = fy, camera.cx = cx, camera.cy = cy;
             camera.width = width, camera.height = height;
             camera.k1 = k1, camera.k2 = k2, camera.k3 = k3, camera.p1 = p1, camera.p2 = p2;
             camera.Check();
             return camera;
           }),
           py::arg("fx"), py::arg("fy"), py::arg("cx"), py::arg("cy"), py::arg("width"),
           py::arg("height"), py::arg("k1") = 0.0, py::arg("k2") = 0.0, py::arg("k3") = 0.0,
           py::arg("p1") = 0.0, py::arg("p2") = 0.0,
           "Raises ValueError naming the field when the model is impossible (e.g. fx <= 0).")
      .def_readonly("fx", &PinholeCamera::fx)
      .def_readonly("fy", &PinholeCamera::fy)
      .def_readonly("cx", &PinholeCamera::cx)
      .def_readonly("cy", &PinholeCamera::cy)
      .def_readonly("width", &PinholeCamera::width)
      .def_readonly("height", &PinholeCamera::height)
      .def("__repr__", [](const PinholeCamera& c) {
        return "PinholeCamera(fx=" + std::to_string(c.fx) + ", fy=" + std::to_string(c.fy) +
               ", cx=" + std::to_string(c.cx) + ", cy=" + std::to_string(c.cy) +
               ", width=" + std::to_string(c.width) + ", height=" + std::to_string(c.height) + ")";
      });
}

void BindOptions(py::module_& module) {
  py::class_<OcgOptions> options(
      module, "OcgOptions",
      "Options of the OCG (settings section OCG.*, docs/settings.md): mode ('paper', "
      "'improved', 'off', 'visibility' or 'fallback'/'in_image'/'guard' joined with '+'), "
      "tau_observable, tau_doubt, increment_full/high/low, rate_high, ...\n\n"
      "OcgOptions(**values): defaults, then the given fields; raises ValueError naming an "
      "unknown field or an invalid value.");
  options.def(py::init([](const py::kwargs& values) {
    OcgOptions result;
    SetOptions(result, values);
    return result;
  }));
  OcgOptions prototype;
  VisitOcgOptionFields(prototype, [&](const char* name, auto& value) {
    BindOptionField<std::decay_t<decltype(value)>>(options, name);
  });
  options.def_static(
      "from_settings",
      [](const std::string& path) {
        OcgOptions result;
        ReadSettings(SettingsFile::Load(path), &result);
        result.Check();
        return result;
      },
      py::arg("path"),
      "The OCG.* keys of a settings file (ours or ORB-SLAM2's), defaults for the rest. Raises "
      "ocg.SettingsError naming file, line and key.");
  options.def("__repr__", [](const OcgOptions& self) {
    std::string text = "OcgOptions(";
    bool first = true;
    VisitOcgOptionFields(self, [&](const char* name, const auto& value) {
      text +=
          (first ? "" : ", ") + std::string(name) + "=" + std::string(py::repr(py::cast(value)));
      first = false;
    });
    return text + ")";
  });
}

void BindResults(py::module_& module) {
  py::class_<ObjectStatus>(module, "ObjectStatus", "One object of the graph after a keyframe.")
      .def_readonly("id", &ObjectStatus::id)
      .def_property_readonly(
          "state", [](const ObjectStatus& s) { return static_cast<int>(s.state); },
          "1 observed, 2 recently observed, 3 unknown, 4 suspicious (SPEC 3.3)")
      .def_property_readonly("state_name", [](const ObjectStatus& s) { return ToString(s.state); })
      .def_readonly("doubt", &ObjectStatus::doubt, "DoubtValue (Eq. 2)")
      .def_readonly("active_edge_rate", &ObjectStatus::active_edge_rate,
                    "ActiveEdgeRate at the last processed keyframe (Eq. 1), in [0, 1]")
      .def_readonly("judged_by_geometry", &ObjectStatus::judged_by_geometry)
      .def_readonly("class_id", &ObjectStatus::class_id, "COCO-80 id, -1 when never given")
      .def_readonly("observations", &ObjectStatus::observations)
      .def_readonly("first_keyframe", &ObjectStatus::first_keyframe)
      .def_readonly("last_observed_keyframe", &ObjectStatus::last_observed_keyframe)
      .def_property_readonly(
          "centroid",
          [](const ObjectStatus& s) -> std::optional<Eigen::Vector3d> {
            return s.geometry.centroid;
          },
          "last known centroid, world frame (3,), None when never given")
      .def("__repr__", [](const ObjectStatus& s) {
        return "ObjectStatus(id=" + std::to_string(s.id) +
               ", state=" + std::to_string(static_cast<int>(s.state)) +
               ", doubt=" + std::to_string(s.doubt) +
               ", active_edge_rate=" + std::to_string(s.active_edge_rate) + ")";
      });
  py::class_<RemovalEvent>(module, "RemovalEvent", "An object that reached state 5 (outlier).")
      .def_readonly("keyframe", &RemovalEvent::keyframe_id)
      .def_readonly("timestamp", &RemovalEvent::timestamp, "seconds")
      .def_readonly("object_id", &RemovalEvent::object_id)
      .def_readonly("class_id", &RemovalEvent::class_id)
      .def_readonly("centroid", &RemovalEvent::centroid, "last known, world frame, or None")
      .def_readonly("doubt", &RemovalEvent::doubt)
      .def_readonly("reason", &RemovalEvent::reason);
  py::class_<KeyframeStates>(module, "KeyframeStates",
                             "What ChangeDetector.process returns for one keyframe.")
      .def_readonly("keyframe", &KeyframeStates::keyframe)
      .def_property_readonly(
          "observation",
          [](const KeyframeStates& self) { return ObservationToPython(self.observation); },
          "the observation processed, as a dict of every field (ocg.observation_fields())")
      .def_readonly("objects", &KeyframeStates::objects,
                    "every object in the graph after the keyframe, ascending id")
      .def_readonly("removed", &KeyframeStates::removed,
                    "objects removed at this keyframe (state 5), ascending id")
      .def(
          "as_dict",
          [](const KeyframeStates& self) {
            py::dict result;
            for (const ObjectStatus& s : self.objects) {
              result[py::int_(s.id)] =
                  py::make_tuple(static_cast<int>(s.state), s.doubt, s.active_edge_rate);
            }
            return result;
          },
          "{object id: (state, doubt, active_edge_rate)}");
}

// process()'s arguments as one observation dict: one dict, or the first fields
// positionally (keyframe, T_cw, camera, observed, centroids) and any field by keyword.
py::dict ProcessArguments(const py::args& args, const py::kwargs& kwargs) {
  if (args.size() == 1 && kwargs.size() == 0 && py::isinstance<py::dict>(args[0])) {
    return args[0].cast<py::dict>();
  }
  static const char* const kPositional[] = {"keyframe", "T_cw", "camera", "observed", "centroids"};
  if (args.size() > std::size(kPositional)) {
    throw py::type_error("process() takes at most " + std::to_string(std::size(kPositional)) +
                         " positional arguments (keyframe, T_cw, camera, observed, centroids), " +
                         std::to_string(args.size()) + " given");
  }
  py::dict fields;
  for (std::size_t i = 0; i < args.size(); ++i) fields[kPositional[i]] = args[i];
  for (const auto& [key, value] : kwargs) {
    if (fields.contains(key)) {
      throw py::type_error("process() got multiple values for '" + std::string(py::str(key)) + "'");
    }
    fields[key] = value;
  }
  return fields;
}

}  // namespace

void BindChangeDetector(py::module_& module) {
  const std::string process_help =
      "process(observation) or process(keyframe, T_cw, camera, observed, centroids={}, "
      "**fields): updates the graph with one keyframe and returns every object's state.\n\n"
      "The observation is a dict, or arguments, of the replay format's fields (SPEC 3.1; "
      "ocg.observation_fields()):\n" +
      ObservationFieldsHelp() +
      "T_cw: a (4, 4) array or 16 numbers, row-major; camera: an ocg.PinholeCamera or a "
      "dict of its fields (fx, fy, cx, cy, width, height, optional k1, k2, k3, p1, p2); "
      "per-object fields: {object id: value}, ids as int or str.\n"
      "Returns KeyframeStates (objects: state 1-4, doubt, active_edge_rate; removed; "
      "observation, the dict processed).\n"
      "Raises ValueError naming the field that is missing, unknown or wrong (T_cw not a "
      "rigid motion, a centroid not finite, ...); nothing is applied then.";
  BindCamera(module);
  BindOptions(module);
  BindResults(module);
  py::class_<ObjectChangeDetector>(
      module, "ChangeDetector",
      "The Object Covisibility Graph change detector (SPEC 3, docs/ocg.md), fed once per "
      "keyframe by any SLAM system. Not thread-safe: call it from one thread.\n\n"
      "ChangeDetector(options=OcgOptions()); raises ValueError on invalid options.")
      .def(py::init([](const OcgOptions& options) { return ObjectChangeDetector(options); }),
           py::arg("options") = OcgOptions())
      .def(
          "process",
          [](ObjectChangeDetector& self, const py::args& args, const py::kwargs& kwargs) {
            const KeyframeObservation observation =
                ObservationFromPython(ProcessArguments(args, kwargs));
            KeyframeStates states;
            states.keyframe = observation.keyframe_id;
            states.observation = observation;
            states.removed = self.Process(observation).removed;
            states.objects = self.Snapshot();
            return states;
          },
          process_help.c_str())
      .def("status", &ObjectChangeDetector::Status, py::arg("id"),
           "ObjectStatus of one object, or None when it is not in the graph")
      .def("snapshot", &ObjectChangeDetector::Snapshot, "every object, ascending id")
      .def("forget", &ObjectChangeDetector::Forget, py::arg("id"),
           "drops an object the map merged away (no change-log entry); False when unknown")
      .def("to_json", &ObjectChangeDetector::ToJson, "the graph as ocg.json text")
      .def_static("from_json", &ObjectChangeDetector::FromJson, py::arg("text"),
                  "a detector from ocg.json text; raises ValueError naming what is wrong")
      .def_property_readonly("options", &ObjectChangeDetector::options)
      .def("__len__", &ObjectChangeDetector::ObjectCount);
}

}  // namespace ocg::python
