// Trajectories and the evaluation metrics (ocg_eval's numbers, from Python).

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "bindings.h"
#include "ocg/eval/object_metrics.h"
#include "ocg/eval/trajectory_error.h"
#include "ocg/io/trajectory.h"

namespace py = pybind11;

namespace ocg::python {
namespace {
// A trajectory argument: a TUM file's path, or an (N, 8) array of TUM rows.
std::vector<StampedPose> ToPoses(const py::object& given, const char* name) {
  if (py::isinstance<py::str>(given) || py::hasattr(given, "__fspath__")) {
    const std::string path = py::str(py::module_::import("os").attr("fspath")(given));
    return ReadTumTrajectory(path);
  }
  const TumRows rows = given.cast<TumRows>();
  if (rows.ndim() != 2 || rows.shape(1) != 8) {
    throw py::value_error(std::string(name) +
                          ": expected a TUM file path or an (N, 8) array "
                          "[timestamp tx ty tz qx qy qz qw]");
  }
  const auto in = rows.unchecked<2>();
  std::vector<StampedPose> poses(static_cast<std::size_t>(rows.shape(0)));
  for (py::ssize_t i = 0; i < rows.shape(0); ++i) {
    for (int c = 0; c < 8; ++c) {
      if (!std::isfinite(in(i, c))) {
        throw py::value_error(std::string(name) + ": row " + std::to_string(i) + " column " +
                              std::to_string(c) + " is not finite");
      }
    }
    if (i > 0 && in(i, 0) <= in(i - 1, 0)) {
      throw py::value_error(std::string(name) + ": row " + std::to_string(i) +
                            ": timestamps must increase strictly");
    }
    const Eigen::Quaterniond q(in(i, 7), in(i, 4), in(i, 5), in(i, 6));
    if (q.norm() < 1e-9) {
      throw py::value_error(std::string(name) + ": row " + std::to_string(i) +
                            ": the quaternion is zero");
    }
    poses[i].timestamp = in(i, 0);
    poses[i].T_wc = SE3(q.normalized(), Eigen::Vector3d(in(i, 1), in(i, 2), in(i, 3)));
  }
  return poses;
}

py::dict MetricsDict(const ObjectMetrics& m, const std::optional<RunAlignment>& alignment) {
  py::dict d;
  d["corr_s"] = m.corr_s, d["unident_s"] = m.unident_s, d["redun_s"] = m.redun_s;
  d["redun_duplicates"] = m.redun_duplicates, d["redun_spurious"] = m.redun_spurious;
  d["corr_m"] = m.corr_m, d["delet_s"] = m.delet_s, d["unident_m"] = m.unident_m;
  d["acc"] = m.acc, d["prec"] = m.prec, d["recall"] = m.recall;
  d["gt_static"] = m.gt_static, d["gt_outdated"] = m.gt_outdated;
  d["gt_never_in_view"] = m.gt_never_in_view, d["never_in_view_ids"] = m.never_in_view_ids;
  d["never_in_view_object_ids"] = m.never_in_view_object_ids;
  d["live_objects"] = m.live_objects, d["removed_objects"] = m.removed_objects;
  d["gt_moves"] = m.gt_moves, d["moves_right"] = m.moves_right;
  d["deleted_static_ids"] = m.deleted_static_ids;
  d["unidentified_static_ids"] = m.unidentified_static_ids;
  d["unidentified_moved_ids"] = m.unidentified_moved_ids;
  d["duplicate_ids"] = m.duplicate_ids, d["spurious_ids"] = m.spurious_ids;
  if (alignment) {
    py::dict a;
    a["trajectory"] = alignment->trajectory, a["pairs"] = alignment->pairs;
    a["scale"] = alignment->scale, a["ate_rmse"] = alignment->ate_rmse;
    d["alignment"] = a;
  } else {
    d["alignment"] = py::none();
  }
  return d;
}

}  // namespace

TumRows ToTumRows(const std::vector<StampedPose>& poses) {
  TumRows rows({static_cast<py::ssize_t>(poses.size()), static_cast<py::ssize_t>(8)});
  auto out = rows.mutable_unchecked<2>();
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const Eigen::Vector3d& t = poses[i].T_wc.translation();
    const Eigen::Quaterniond& q = poses[i].T_wc.quaternion();
    const double values[8] = {poses[i].timestamp, t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()};
    for (int c = 0; c < 8; ++c) out(i, c) = values[c];
  }
  return rows;
}

void BindEvaluation(py::module_& module) {
  module.def(
      "read_tum_trajectory",
      [](const py::object& path) {
        return ToTumRows(
            ReadTumTrajectory(py::str(py::module_::import("os").attr("fspath")(path))));
      },
      py::arg("path"),
      "Reads a TUM trajectory file (camera-to-world poses T_wc).\n\n"
      "Returns an (N, 8) float64 array, one row per pose: timestamp (s), tx ty tz (m), "
      "qx qy qz qw (unit quaternion).\n"
      "Raises ocg.FileError when the file is missing, ocg.ParseError naming file and line "
      "when it is malformed or its timestamps do not increase.");

  py::class_<AteResult>(module, "AteResult", "Absolute trajectory error of the positions.")
      .def_property_readonly(
          "rmse", [](const AteResult& r) { return r.translation.rmse; }, "m")
      .def_property_readonly(
          "mean", [](const AteResult& r) { return r.translation.mean; }, "m")
      .def_property_readonly(
          "median", [](const AteResult& r) { return r.translation.median; }, "m")
      .def_property_readonly(
          "std", [](const AteResult& r) { return r.translation.std; },
          "population standard deviation, m")
      .def_property_readonly(
          "min", [](const AteResult& r) { return r.translation.min; }, "m")
      .def_property_readonly(
          "max", [](const AteResult& r) { return r.translation.max; }, "m")
      .def_property_readonly(
          "count", [](const AteResult& r) { return r.pairs.size(); }, "associated pose pairs")
      .def_property_readonly(
          "scale", [](const AteResult& r) { return r.reference_from_estimate.scale(); },
          "scale of the alignment (1 for se3 and none)")
      .def_property_readonly(
          "alignment", [](const AteResult& r) { return r.reference_from_estimate.Matrix(); },
          "(4, 4) similarity taking estimate positions into the reference frame: "
          "p_ref = alignment @ [p_est, 1]")
      .def_property_readonly(
          "errors",
          [](const AteResult& r) {
            return py::array_t<double>(static_cast<py::ssize_t>(r.errors.size()), r.errors.data());
          },
          "(K,) position error of each pair, m")
      .def_property_readonly(
          "pairs",
          [](const AteResult& r) {
            py::array_t<std::int64_t> pairs(
                {static_cast<py::ssize_t>(r.pairs.size()), static_cast<py::ssize_t>(2)});
            auto out = pairs.mutable_unchecked<2>();
            for (std::size_t i = 0; i < r.pairs.size(); ++i) {
              out(i, 0) = static_cast<std::int64_t>(r.pairs[i].reference_index);
              out(i, 1) = static_cast<std::int64_t>(r.pairs[i].estimate_index);
            }
            return pairs;
          },
          "(K, 2) row indices (reference, estimate) of the associated poses")
      .def("__repr__", [](const AteResult& r) {
        return "AteResult(rmse=" + std::to_string(r.translation.rmse) +
               " m, count=" + std::to_string(r.pairs.size()) +
               ", scale=" + std::to_string(r.reference_from_estimate.scale()) + ")";
      });

  module.def(
      "ate",
      [](const py::object& gt, const py::object& est, const std::string& align, double max_dt) {
        AteOptions options;
        options.alignment = ParseAlignmentMode(align);
        if (!(max_dt > 0)) throw py::value_error("max_dt must be positive (seconds)");
        options.max_dt = max_dt;
        const std::vector<StampedPose> reference = ToPoses(gt, "gt");
        const std::vector<StampedPose> estimate = ToPoses(est, "est");
        py::gil_scoped_release release;
        return ComputeAte(reference, estimate, options);
      },
      py::arg("gt"), py::arg("est"), py::arg("align") = "sim3", py::arg("max_dt") = 0.02,
      "Absolute trajectory error of the positions, as `ocg_eval ate` (TUM's evaluate_ate.py "
      "and evo_ape).\n\n"
      "gt, est: a TUM file path or an (N, 8) array as read_tum_trajectory returns "
      "(camera-to-world).\n"
      "align: 'sim3' (monocular: scale too), 'se3' or 'none'.\n"
      "max_dt: largest timestamp difference of an associated pair, seconds.\n"
      "Returns AteResult (metres, in the ground truth's frame).\n"
      "Raises ValueError when align is unknown or fewer than 3 poses associate, "
      "ocg.FileError / ocg.ParseError for unreadable files.");

  module.def(
      "object_metrics",
      [](const py::object& objects_gt, const py::object& run, const py::object& groundtruth,
         double distance_factor, double min_distance, bool include_never_in_view) {
        const auto fspath = py::module_::import("os").attr("fspath");
        if (!(distance_factor > 0)) throw py::value_error("distance_factor must be positive");
        if (!(min_distance >= 0)) throw py::value_error("min_distance must be non-negative");
        ObjectMatchOptions options;
        options.distance_factor = distance_factor;
        options.min_distance = min_distance;
        options.include_never_in_view = include_never_in_view;
        std::optional<RunAlignment> alignment;
        const std::string groundtruth_path =
            groundtruth.is_none() ? std::string() : std::string(py::str(fspath(groundtruth)));
        const ObjectMetrics metrics =
            EvaluateRunObjects(py::str(fspath(objects_gt)), py::str(fspath(run)), groundtruth_path,
                               options, &alignment);
        return MetricsDict(metrics, alignment);
      },
      py::arg("objects_gt"), py::arg("run"), py::arg("groundtruth") = py::none(),
      py::arg("distance_factor") = 0.5, py::arg("min_distance") = 0.0,
      py::arg("include_never_in_view") = false,
      "Object-map metrics of the paper's Table I (SPEC 4), as `ocg_eval objects --json`.\n\n"
      "objects_gt: the generator's objects_gt.json.\n"
      "run: a run folder (objects.json, changes.json).\n"
      "groundtruth: ground-truth TUM trajectory; when given, the run's KeyFrameTrajectory.txt "
      "(else CameraTrajectory.txt) is aligned to it (Sim(3)) and the objects moved with it. "
      "Leave None for runs on ground-truth poses.\n"
      "distance_factor, min_distance (m): matching distance = max(distance_factor x the "
      "larger ground-truth extent, min_distance).\n"
      "Returns a dict: corr_s, unident_s, redun_s (redun_duplicates + redun_spurious), "
      "corr_m, delet_s, unident_m, acc, prec, recall, the ground-truth counts, the ids behind "
      "each count, the static objects left out as never in view (gt_never_in_view, "
      "never_in_view_ids) and the live objects at their places, ignored "
      "(never_in_view_object_ids), and alignment (trajectory, pairs, scale, ate_rmse) or "
      "None.\n"
      "Raises ocg.FileError / ocg.ParseError naming the file, ValueError when the "
      "trajectories do not align.");
}

}  // namespace ocg::python
