#pragma once
// A finished run's map, read back from its output folder, for `ocg_render`.

#include <string>

#include "ocg/viewer/map_view.h"

namespace ocg {

// Reads RUN_DIR/map_points.ply, KeyFrameTrajectory.txt, CameraTrajectory.txt,
// objects.json (live objects, their state, "up") and changes.json (removed objects, as
// ghosts; moved ones as ghosts with an arrow to where they went). Every file but
// KeyFrameTrajectory.txt may be missing (a SLAM run without detections has no objects). Throws
// FileError / ParseError naming the file.
MapScene ReadRunScene(const std::string& run_dir);

}  // namespace ocg
