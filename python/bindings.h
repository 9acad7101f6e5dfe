#pragma once
// The parts of the Python module `ocg`, one function per file, called in order by
// module.cc. A new part (ocg.ObjectSlam) is one more file with one more Bind function.

#include <pybind11/pybind11.h>

namespace ocg::python {

// Error types: ocg.FileError (OSError), ocg.ParseError, ocg.SettingsError (ValueError).
void BindErrors(pybind11::module_& module);
// ocg.PinholeCamera, ocg.OcgOptions, ocg.ChangeDetector and its results.
void BindChangeDetector(pybind11::module_& module);
// ocg.read_tum_trajectory, ocg.ate, ocg.object_metrics.
void BindEvaluation(pybind11::module_& module);

}  // namespace ocg::python
