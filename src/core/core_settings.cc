#include "ocg/core/core_settings.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>
#include <vector>

#include "ocg/core/options.h"
#include "ocg/core/settings_file.h"

namespace ocg {
namespace {

// Per-camera parameters: "Camera.<name>" in ORB-SLAM2 files, "Camera1.<name>" in
// ORB-SLAM3 File.version "1.0" files.
const std::vector<std::string> kIntrinsics = {"fx", "fy", "cx", "cy"};
// Radial-tangential distortion; k3 may be left out (ORB-SLAM3 reads 4 or 5 coefficients).
const std::vector<std::string> kDistortion = {"k1", "k2", "p1", "p2"};
// Keys of the "Camera." group in both layouts, besides the per-camera parameters.
const std::vector<std::string> kImageKeys = {"width", "height", "fps", "RGB", "type"};
// ORB-SLAM2's stereo and RGB-D baseline times fx: meaningless for a monocular run.
const char* const kStereoBaseline = "bf";

bool Contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

bool IsCameraParameter(const std::string& name) {
  return Contains(kIntrinsics, name) || Contains(kDistortion, name) || name == "k3";
}

// True for an ORB-SLAM3 File.version "1.0" file, false for ORB-SLAM2's layout (no
// File.version); another version is an error rather than a guess.
bool IsVersion1(const SettingsFile& file) {
  std::string version;
  if (!file.Read("File.version", &version)) return false;
  if (version != "1.0") {
    throw SettingsError(
        file.Describe("File.version",
                      "unknown settings file version '" + version +
                          "': ORB-SLAM3 files say \"1.0\", ORB-SLAM2 files have no File.version"));
  }
  return true;
}

std::string ParameterPrefix(bool version1) { return version1 ? "Camera1." : "Camera."; }

bool SameIgnoringCase(const std::string& a, const std::string& b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) ==
                  std::tolower(static_cast<unsigned char>(y));
         });
}

// The camera key a misspelt one meant ("Camera1.Fx" -> "Camera1.fx", "Camera.widht" ->
// "Camera.width"), or "". Short names must match but for case: "k4" is a coefficient of
// another camera model, not a misspelt "k1".
std::string CameraKeySuggestion(const std::string& key, bool version1) {
  std::vector<std::string> known;
  for (const auto* names : {&kIntrinsics, &kDistortion}) {
    for (const std::string& name : *names) known.push_back(ParameterPrefix(version1) + name);
  }
  known.push_back(ParameterPrefix(version1) + "k3");
  for (const std::string& name : kImageKeys) known.push_back("Camera." + name);
  const std::string closest = ClosestKey(key, known);
  if (closest.empty()) return "";
  const std::string name = key.substr(key.find('.') + 1);
  if (name.size() <= 3 && !SameIgnoringCase(name, closest.substr(closest.find('.') + 1))) {
    return "";
  }
  return closest;
}

// Why a key of the "Camera." or "Camera1." group cannot be read, or "" when it can. Keys we
// do not understand there are errors, not warnings: a fisheye coefficient, a resize or a
// parameter of the other layout changes what every pixel means.
std::string CameraKeyProblem(const std::string& key, bool version1) {
  const bool in_camera1 = key.rfind("Camera1.", 0) == 0;
  const std::string name = key.substr(in_camera1 ? 8 : 7);
  if (in_camera1 && !version1) {
    return "Camera1.* keys are ORB-SLAM3's File.version \"1.0\" layout: add the line "
           "'File.version: \"1.0\"', or write Camera." +
           name + " as in ORB-SLAM2 files";
  }
  if (IsCameraParameter(name)) {
    if (!in_camera1 && version1) {
      return "this file says File.version \"1.0\", whose camera parameters are Camera1.* "
             "(write Camera1." +
             name + ", or remove File.version for ORB-SLAM2's layout)";
    }
    return "";
  }
  if (!in_camera1 && (Contains(kImageKeys, name) || name == kStereoBaseline)) return "";
  const std::string suggestion = CameraKeySuggestion(key, version1);
  if (!suggestion.empty()) {
    return "unknown camera key (keys are case-sensitive): did you mean " + suggestion + "?";
  }
  if (name == "newWidth" || name == "newHeight") {
    return "resizing the images is not supported: resize them beforehand and give the "
           "camera of the resized images";
  }
  return "not a parameter of the pinhole camera with radial-tangential distortion (fx, fy, "
         "cx, cy, k1, k2, p1, p2, k3; width, height, fps, RGB); k4 and the like belong to "
         "other camera models, which are not supported";
}

// Throws when some but not all keys of a group are given: the defaults would fill the gap
// with another camera's values.
void RequireWholeGroup(const SettingsFile& file, const std::string& prefix,
                       const std::vector<std::string>& group, const std::string& what) {
  std::string first_given, missing;
  for (const std::string& name : group) {
    if (file.Has(prefix + name)) {
      if (first_given.empty()) first_given = prefix + name;
    } else {
      missing += (missing.empty() ? "" : ", ") + prefix + name;
    }
  }
  if (!first_given.empty() && !missing.empty()) {
    throw SettingsError(file.Describe(first_given, "given without " + missing + ": " + what));
  }
}

}  // namespace

void CameraSettings::Check() const {
  model.Check();
  // A principal point off the image means intrinsics of another image size (a file whose
  // Camera.width/height were left at the defaults, or a calibration of a resized image).
  RequireOption(model.cx >= 0 && model.cx <= model.width, "Camera.cx",
                "must lie inside the image (0 to Camera.width = " + std::to_string(model.width) +
                    "): are the intrinsics and the image size of the same camera?");
  RequireOption(model.cy >= 0 && model.cy <= model.height, "Camera.cy",
                "must lie inside the image (0 to Camera.height = " + std::to_string(model.height) +
                    "): are the intrinsics and the image size of the same camera?");
  RequireOption(std::isfinite(fps) && fps > 0, "Camera.fps", "must be positive");
}

void SystemOptions::Check() const {
  static const char* const kLevels[] = {"trace", "debug", "info", "warn", "error", "off"};
  bool known = false;
  for (const char* level : kLevels) known = known || log_level == level;
  RequireOption(known, "System.log_level", "must be trace, debug, info, warn, error or off");
}

void ReadSettings(const SettingsFile& file, CameraSettings* settings) {
  const bool version1 = IsVersion1(file);
  std::string type;
  if (file.Read("Camera.type", &type) && type != "PinHole") {
    throw SettingsError(file.Describe(
        "Camera.type", "camera model '" + type +
                           "' is not supported: only \"PinHole\" (radial-tangential "
                           "distortion k1, k2, p1, p2, k3); calibrate the camera with that "
                           "model or undistort the images first"));
  }
  for (const char* group : {"Camera.", "Camera1."}) {
    for (const std::string& key : file.KeysUnder(group)) {
      const std::string problem = CameraKeyProblem(key, version1);
      if (!problem.empty()) throw SettingsError(file.Describe(key, problem));
    }
  }
  const std::string prefix = ParameterPrefix(version1);
  PinholeCamera& model = settings->model;
  file.Read(prefix + "fx", &model.fx);
  file.Read(prefix + "fy", &model.fy);
  file.Read(prefix + "cx", &model.cx);
  file.Read(prefix + "cy", &model.cy);
  file.Read(prefix + "k1", &model.k1);
  file.Read(prefix + "k2", &model.k2);
  file.Read(prefix + "k3", &model.k3);
  file.Read(prefix + "p1", &model.p1);
  file.Read(prefix + "p2", &model.p2);
  RequireWholeGroup(file, prefix, kIntrinsics, "a camera needs all four intrinsics");
  RequireWholeGroup(file, prefix, kDistortion,
                    "radial-tangential distortion needs k1, k2, p1 and p2 (k3 optional)");
  if (file.Has(prefix + "k3") && !file.Has(prefix + "k1")) {
    throw SettingsError(file.Describe(
        prefix + "k3", "given without " + prefix + "k1, " + prefix + "k2, " + prefix + "p1, " +
                           prefix + "p2: radial-tangential distortion needs them all"));
  }
  file.Read("Camera.width", &model.width);
  file.Read("Camera.height", &model.height);
  file.Read("Camera.fps", &settings->fps);
  file.Read("Camera.RGB", &settings->rgb);
}

void RequireCamera(const SettingsFile& file, CameraNeed need) {
  if (need == CameraNeed::kNone) return;
  const std::string prefix = ParameterPrefix(IsVersion1(file));
  std::vector<std::string> keys;
  for (const std::string& name : kIntrinsics) keys.push_back(prefix + name);
  if (need == CameraNeed::kIntrinsicsAndImageSize) {
    keys.push_back("Camera.width");
    keys.push_back("Camera.height");
  }
  std::string missing;
  for (const std::string& key : keys) {
    if (!file.Has(key)) missing += (missing.empty() ? "" : ", ") + key;
  }
  if (missing.empty()) return;
  std::string message = file.name() + ": camera keys missing: this command needs " + missing;
  if (need == CameraNeed::kIntrinsicsAndImageSize &&
      (!file.Has("Camera.width") || !file.Has("Camera.height"))) {
    message += " (it reads no image to take the size from)";
  }
  throw SettingsError(message + "; see docs/settings.md");
}

std::string CameraKeyInFile(const SettingsFile& file, const std::string& key) {
  const std::string prefix = "Camera.";
  if (key.rfind(prefix, 0) != 0 || !IsCameraParameter(key.substr(prefix.size()))) return key;
  return ParameterPrefix(IsVersion1(file)) + key.substr(prefix.size());
}

void ReadSettings(const SettingsFile& file, SystemOptions* options) {
  ReadOptionFields(file, options);
}

}  // namespace ocg
