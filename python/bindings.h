#pragma once
// The parts of the Python module `ocg`, one function per file, called in order by
// module.cc. A new part is one more file with one more Bind function.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "ocg/io/trajectory.h"
#include "ocg/ocg/observation.h"

namespace ocg::python {

// Error types: ocg.FileError (OSError), ocg.ParseError, ocg.SettingsError (ValueError).
void BindErrors(pybind11::module_& module);
// ocg.PinholeCamera, ocg.OcgOptions, ocg.ChangeDetector and its results.
void BindChangeDetector(pybind11::module_& module);
// ocg.observation_fields, ocg.observation_to_json, ocg.observation_from_json.
void BindObservation(pybind11::module_& module);
// The OCG's keyframe input from and to a dict keyed by the replay format's field names
// (VisitObservationFields); raises ValueError naming the field that is missing, unknown or
// wrong.
KeyframeObservation ObservationFromPython(pybind11::handle value);
pybind11::dict ObservationToPython(const KeyframeObservation& observation);
// ocg.read_tum_trajectory, ocg.ate, ocg.object_metrics.
void BindEvaluation(pybind11::module_& module);
// ocg.ObjectSlam: SLAM, objects and the OCG fed frame by frame.
void BindObjectSlam(pybind11::module_& module);
// ocg.Detector, ocg.detect_images: the detector of ocg_detect.
void BindDetector(pybind11::module_& module);

using TumRows = pybind11::array_t<double, pybind11::array::c_style | pybind11::array::forcecast>;
// Poses as an (N, 8) array of TUM rows [timestamp, tx, ty, tz, qx, qy, qz, qw] (T_wc).
TumRows ToTumRows(const std::vector<StampedPose>& poses);

}  // namespace ocg::python
