#pragma once
#include "ocg/core/option_fields.h"
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

  // The settings keys, once (ocg/core/option_fields.h).
  template <typename Self, typename Visitor>
  static void VisitFields(Self& self, Visitor&& visit) {
    visit("Viewer.KeyFrameSize", self.keyframe_size, OptionBound::Positive(),
          "keyframe frustum size, metres");
    visit("Viewer.KeyFrameLineWidth", self.keyframe_line_width, OptionBound::Positive(),
          "keyframe line width, pixels");
    visit("Viewer.GraphLineWidth", self.graph_line_width, OptionBound::Positive(),
          "covisibility graph line width, pixels");
    visit("Viewer.PointSize", self.point_size, OptionBound::Positive(), "map point size, pixels");
    visit("Viewer.CameraSize", self.camera_size, OptionBound::Positive(),
          "current camera frustum size, metres");
    visit("Viewer.CameraLineWidth", self.camera_line_width, OptionBound::Positive(),
          "current camera line width, pixels");
    visit("Viewer.ViewpointX", self.viewpoint_x, OptionBound::Any(), "snapshot eye, metres");
    visit("Viewer.ViewpointY", self.viewpoint_y, OptionBound::Any(), "snapshot eye, metres");
    visit("Viewer.ViewpointZ", self.viewpoint_z, OptionBound::Any(), "snapshot eye, metres");
    visit("Viewer.ViewpointF", self.viewpoint_f, OptionBound::Positive(),
          "snapshot focal length, pixels");
    visit("Viewer.snapshot_width", self.snapshot_width, OptionBound::Closed(16, 8192),
          "snapshot width, pixels");
    visit("Viewer.snapshot_height", self.snapshot_height, OptionBound::Closed(16, 8192),
          "snapshot height, pixels");
    visit("Viewer.every_keyframes", self.every_keyframes, OptionBound::NonNegative(),
          "a map snapshot every N keyframes (0: final snapshot only)");
  }
  void Check() const;  // throws OptionError naming the key
};

void ReadSettings(const SettingsFile& file, ViewerOptions* options);

}  // namespace ocg
