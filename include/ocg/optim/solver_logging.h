#pragma once
// Ceres reports through glog, which by itself writes to stderr (or to log files once
// initialized). RouteSolverLogging initializes glog once per process (unless the program
// did), turns its files and stderr output off below FATAL, and forwards every message to
// the spdlog default logger: warnings as warnings, errors as errors, INFO as debug.
// Every solve of this module calls it first; a program may call it earlier. Thread-safe
// and idempotent.

namespace ocg {

void RouteSolverLogging();

}  // namespace ocg
