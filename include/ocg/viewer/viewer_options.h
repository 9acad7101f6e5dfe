#pragma once
// Off-screen viewer options: ORB-SLAM2's Viewer.* keys plus our snapshot settings.

namespace ocg {

class SettingsFile;

struct ViewerOptions {
  double keyframe_size = 0.05;       // Viewer.KeyFrameSize: frustum size, metres
  double keyframe_line_width = 1.0;  // Viewer.KeyFrameLineWidth
  double graph_line_width = 0.9;     // Viewer.GraphLineWidth
  double point_size = 2.0;           // Viewer.PointSize: pixels
  double camera_size = 0.08;         // Viewer.CameraSize
  double camera_line_width = 3.0;    // Viewer.CameraLineWidth
  double viewpoint_x = 0.0;          // Viewer.ViewpointX/Y/Z: eye position of the 3-D view
  double viewpoint_y = -0.7;
  double viewpoint_z = -1.8;
  double viewpoint_f = 500.0;  // Viewer.ViewpointF: focal length of the 3-D view, pixels
  int snapshot_width = 1280;   // Viewer.snapshot_width: PNG size, pixels
  int snapshot_height = 720;   // Viewer.snapshot_height
  int every_keyframes = 0;     // Viewer.every_keyframes: snapshot period, 0 = final only

  void Check() const;  // throws OptionError naming the key
};

void ReadSettings(const SettingsFile& file, ViewerOptions* options);

}  // namespace ocg
