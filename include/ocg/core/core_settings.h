#pragma once
// Options owned by the core module: the camera (ORB-SLAM2's Camera.* keys) and the
// system-wide run options (System.*).

#include <cstdint>
#include <string>

#include "ocg/core/camera.h"

namespace ocg {

class SettingsFile;

struct CameraSettings {
  PinholeCamera model;  // Camera.fx .. Camera.k3, Camera.width, Camera.height
  double fps = 30.0;    // Camera.fps: frame rate of the input
  bool rgb = true;      // Camera.RGB: colour order of the images (true RGB, false BGR)

  void Check() const;
};

struct SystemOptions {
  // System.sequential: run local mapping, loop closing and the OCG synchronously after
  // each keyframe, so that identical inputs give identical outputs. On by default:
  // evaluation wants reproducibility; real-time users switch it off.
  bool sequential = true;
  // System.seed: the seed every random choice (RANSAC, sampling) derives from.
  std::uint64_t seed = 42;
  // System.log_level: trace, debug, info, warn, error or off.
  std::string log_level = "info";

  void Check() const;
};

// Read the keys present in the file over the defaults already in *settings.
// Type errors throw SettingsError naming file, line and key; values are not checked here.
void ReadSettings(const SettingsFile& file, CameraSettings* settings);
void ReadSettings(const SettingsFile& file, SystemOptions* options);

}  // namespace ocg
