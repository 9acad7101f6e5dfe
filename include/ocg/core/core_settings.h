#pragma once
// Options owned by the core module: the camera and the system-wide run options (System.*).
//
// The camera is read in either of two layouts:
//  - ORB-SLAM2's (and our own): Camera.fx, .fy, .cx, .cy, .k1, .k2, .p1, .p2, .k3;
//  - ORB-SLAM3's File.version "1.0": the same parameters as Camera1.fx ... Camera1.k3.
// Both share Camera.width, .height, .fps, .RGB and Camera.type (only "PinHole").
// A camera is never guessed: another model, a camera key we do not know (k4, newWidth...),
// a key of the other layout, or an incomplete group (fx without cy, k1 without p2) is a
// SettingsError naming the file, line and key.

#include <cstdint>
#include <string>

#include "ocg/core/camera.h"
#include "ocg/core/option_fields.h"

namespace ocg {

class SettingsFile;

// What a command needs from the camera keys of its settings file.
enum class CameraNeed {
  kNone,                    // the defaults (PinholeCamera) may stand in for absent keys
  kIntrinsics,              // fx, fy, cx, cy; the image size comes from the images
  kIntrinsicsAndImageSize,  // also Camera.width and Camera.height: no image is read
};

struct CameraSettings {
  PinholeCamera model;  // Camera.fx .. Camera.k3 (or Camera1.*), Camera.width, Camera.height
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

  // The settings keys, once (ocg/core/option_fields.h).
  template <typename Self, typename Visitor>
  static void VisitFields(Self& self, Visitor&& visit) {
    visit("System.sequential", self.sequential, OptionBound::Any(),
          "run all stages synchronously per keyframe: identical inputs, identical outputs");
    visit("System.seed", self.seed, OptionBound::Any(), "seed of every random choice");
    visit("System.log_level", self.log_level, OptionBound::Any(),
          "trace, debug, info, warn, error, off");
  }
  void Check() const;
};

// Read the keys present in the file over the defaults already in *settings.
// Type errors throw SettingsError naming file, line and key; values are not checked here.
void ReadSettings(const SettingsFile& file, CameraSettings* settings);
void ReadSettings(const SettingsFile& file, SystemOptions* options);

// Throws SettingsError naming the file and every missing key when the file does not give
// the camera keys a command needs.
void RequireCamera(const SettingsFile& file, CameraNeed need);
// The key that holds a camera parameter in this file: "Camera.fx" is "Camera1.fx" in an
// ORB-SLAM3 File.version "1.0" file. Other keys are returned unchanged.
std::string CameraKeyInFile(const SettingsFile& file, const std::string& key);

}  // namespace ocg
