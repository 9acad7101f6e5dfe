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
#include "ocg/ocg/state_machine.h"

namespace py = pybind11;

namespace ocg::python {
namespace {

// What process() returns: the whole graph after one keyframe.
struct KeyframeStates {
  std::int64_t keyframe = 0;
  std::vector<ObjectStatus> objects;  // ascending id
  std::vector<RemovalEvent> removed;  // this keyframe's, ascending id
};

// Python's T_cw as an SE3, refusing what is not a rigid motion instead of silently
// re-orthonormalising a wrong matrix (the replay format's rule).
SE3 RigidPose(const Eigen::Matrix4d& matrix, const char* name) {
  if (!matrix.allFinite())
    throw py::value_error(std::string(name) + " has NaN or infinite entries");
  if ((matrix.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-9) {
    throw py::value_error(std::string(name) + " last row must be [0, 0, 0, 1]");
  }
  const Eigen::Matrix3d rotation = matrix.topLeftCorner<3, 3>();
  if ((rotation * rotation.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-3 ||
      rotation.determinant() < 0) {
    throw py::value_error(std::string(name) + " rotation block is not a rotation");
  }
  return SE3::FromMatrix(matrix);
}

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

}  // namespace

void BindChangeDetector(py::module_& module) {
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
          [](ObjectChangeDetector& self, std::int64_t keyframe, const Eigen::Matrix4d& T_cw,
             const PinholeCamera& camera, const std::vector<ObjectId>& observed,
             const std::map<ObjectId, Eigen::Vector3d>& centroids, double timestamp,
             const std::map<ObjectId, Eigen::Vector3d>& sizes,
             const std::map<ObjectId, int>& classes, const std::vector<ObjectId>& forgotten,
             const std::vector<ObjectId>& restored) {
            KeyframeObservation observation;
            observation.keyframe_id = keyframe;
            observation.timestamp = timestamp;
            observation.T_cw = RigidPose(T_cw, "T_cw");
            camera.Check();
            observation.camera = camera;
            observation.observed = observed;
            observation.forgotten = forgotten;
            observation.restored = restored;
            for (const auto& [id, centroid] : centroids) {
              if (!centroid.allFinite()) {
                throw py::value_error("centroids[" + std::to_string(id) + "] is not finite");
              }
              observation.updates[id].centroid = centroid;
            }
            for (const auto& [id, size] : sizes) {
              if (!size.allFinite() || (size.array() < 0).any()) {
                throw py::value_error("sizes[" + std::to_string(id) +
                                      "] must be finite and non-negative");
              }
              observation.updates[id].size = size;
            }
            for (const auto& [id, class_id] : classes) observation.updates[id].class_id = class_id;
            KeyframeStates states;
            states.keyframe = keyframe;
            states.removed = self.Process(observation).removed;
            states.objects = self.Snapshot();
            return states;
          },
          py::arg("keyframe"), py::arg("T_cw"), py::arg("camera"), py::arg("observed"),
          py::arg("centroids") = std::map<ObjectId, Eigen::Vector3d>{}, py::kw_only(),
          py::arg("timestamp") = 0.0, py::arg("sizes") = std::map<ObjectId, Eigen::Vector3d>{},
          py::arg("classes") = std::map<ObjectId, int>{},
          py::arg("forgotten") = std::vector<ObjectId>{},
          py::arg("restored") = std::vector<ObjectId>{},
          "Updates the graph with one keyframe and returns every object's state.\n\n"
          "keyframe: int, increasing keyframe id.\n"
          "T_cw: (4, 4) float array, world to camera (camera x right, y down, z forward), "
          "metres.\n"
          "camera: PinholeCamera of the keyframe's image.\n"
          "observed: ids of the map objects matched to a detection in this keyframe.\n"
          "centroids: {id: (3,) world-frame centroid, metres} for objects whose centroid is "
          "new or changed; others keep their last one.\n"
          "timestamp: seconds (for the change log); sizes: {id: (3,) world-axis extents, "
          "metres} (mode in_image); classes: {id: COCO-80 id}; forgotten: ids the map "
          "dropped (merged duplicates), removed without a change-log entry; restored: ids of "
          "removed objects found again at their place (mode restore), back with their "
          "edges in state 1.\n"
          "Returns KeyframeStates (objects: state 1-4, doubt, active_edge_rate; removed).\n"
          "Raises ValueError when T_cw is not a rigid motion or a centroid is not finite.")
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
