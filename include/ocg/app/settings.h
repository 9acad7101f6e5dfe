#pragma once
// The composition root of settings: every module's options read from one file, checked,
// with warnings for keys nobody reads. Used by the command-line tools.

#include <string>
#include <vector>

#include "ocg/core/core_settings.h"
#include "ocg/features/matcher.h"
#include "ocg/features/orb_options.h"
#include "ocg/features/vocabulary.h"
#include "ocg/objects/objects_options.h"
#include "ocg/ocg/options.h"
#include "ocg/slam/initializer.h"
#include "ocg/slam/local_mapping.h"
#include "ocg/slam/loop_closing.h"
#include "ocg/slam/system.h"
#include "ocg/slam/tracking.h"
#include "ocg/viewer/viewer_options.h"

namespace ocg {

struct Settings {
  std::string source = "(defaults)";  // the file they came from
  CameraSettings camera;
  SystemOptions system;
  OrbExtractorOptions orb;
  MatcherOptions matcher;
  VocabularyOptions vocabulary;
  InitialMapOptions initializer;
  TrackingOptions tracking;
  LocalMappingOptions local_mapping;
  LoopClosingOptions loop_closing;
  ObjectsOptions objects;
  OcgOptions ocg;
  ViewerOptions viewer;

  // Throws SettingsError "file:line: key 'K': message" for the first impossible value.
  void Check() const;
};

struct LoadedSettings {
  Settings settings;
  std::vector<std::string> warnings;  // one per unknown key, also logged
  // Camera.width and Camera.height were both in the file (ORB-SLAM2's TUM files give
  // neither: a command that reads no image must then take the size from elsewhere).
  bool image_size_given = false;
};

// Throws SettingsError naming the file, line and key on a missing file, invalid YAML, a key
// set twice, a wrong type, an impossible value or a camera we cannot model; and naming the
// missing keys when the file lacks the camera keys camera_need asks for (the commands that
// project points: ocg_slam run and objects).
LoadedSettings LoadSettings(const std::string& path, CameraNeed camera_need = CameraNeed::kNone);
LoadedSettings ParseSettings(const std::string& text, const std::string& name,
                             CameraNeed camera_need = CameraNeed::kNone);

// The SLAM system's part of the settings; the initializer's RANSAC seed mixed with
// System.seed so that one seed changes every random choice of a run.
SystemConfig MakeSystemConfig(const Settings& settings);

}  // namespace ocg
