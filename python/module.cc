// The native part of the Python package `ocg` (python/ocg/__init__.py re-exports it).

#include "bindings.h"

PYBIND11_MODULE(_ocg, module) {
  module.doc() =
      "OCG-SLAM from Python: the whole system frame by frame (ObjectSlam), the Object Covisibility "
      "Graph change detector for any SLAM "
      "system, TUM trajectories, ATE and the object-map metrics (docs/python.md).";
  ocg::python::BindErrors(module);
  ocg::python::BindChangeDetector(module);
  ocg::python::BindObservation(module);
  ocg::python::BindEvaluation(module);
  ocg::python::BindObjectSlam(module);
  ocg::python::BindDetector(module);
}
