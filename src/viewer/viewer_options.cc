#include "ocg/viewer/viewer_options.h"

#include "ocg/core/options.h"
#include "ocg/core/settings_file.h"

namespace ocg {

void ViewerOptions::Check() const {
  RequireOption(keyframe_size > 0, "Viewer.KeyFrameSize", "must be positive");
  RequireOption(point_size > 0, "Viewer.PointSize", "must be positive");
  RequireOption(camera_size > 0, "Viewer.CameraSize", "must be positive");
  RequireOption(viewpoint_f > 0, "Viewer.ViewpointF", "must be positive");
  RequireOption(snapshot_width >= 16 && snapshot_width <= 8192, "Viewer.snapshot_width",
                "must be in [16, 8192]");
  RequireOption(snapshot_height >= 16 && snapshot_height <= 8192, "Viewer.snapshot_height",
                "must be in [16, 8192]");
  RequireOption(every_keyframes >= 0, "Viewer.every_keyframes", "must be non-negative");
}

void ReadSettings(const SettingsFile& file, ViewerOptions* options) {
  file.Read("Viewer.KeyFrameSize", &options->keyframe_size);
  file.Read("Viewer.KeyFrameLineWidth", &options->keyframe_line_width);
  file.Read("Viewer.GraphLineWidth", &options->graph_line_width);
  file.Read("Viewer.PointSize", &options->point_size);
  file.Read("Viewer.CameraSize", &options->camera_size);
  file.Read("Viewer.CameraLineWidth", &options->camera_line_width);
  file.Read("Viewer.ViewpointX", &options->viewpoint_x);
  file.Read("Viewer.ViewpointY", &options->viewpoint_y);
  file.Read("Viewer.ViewpointZ", &options->viewpoint_z);
  file.Read("Viewer.ViewpointF", &options->viewpoint_f);
  file.Read("Viewer.snapshot_width", &options->snapshot_width);
  file.Read("Viewer.snapshot_height", &options->snapshot_height);
  file.Read("Viewer.every_keyframes", &options->every_keyframes);
}

}  // namespace ocg
