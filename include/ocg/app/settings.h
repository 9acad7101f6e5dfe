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

// What a key that no module reads is: a warning (the default: ORB-SLAM files carry keys of
// other programs) or an error (a batch, where a misspelt key would silently give a run with
// the default value).
enum class UnknownKeys { kWarn, kError };

struct LoadedSettings {
  Settings settings;
  // One per unknown key, with the known key it most likely meant ("did you mean
  // 'LoopClosing.enabled'?"); also logged.
  std::vector<std::string> warnings;
  // Camera.width and Camera.height were both in the file (ORB-SLAM2's TUM files give
  // neither: a command that reads no image must then take the size from elsewhere).
  bool image_size_given = false;
};

// Throws SettingsError naming the file, line and key on a missing file, invalid YAML, a key
// set twice, a wrong type, an impossible value or a camera we cannot model; and naming the
// missing keys when the file lacks the camera keys camera_need asks for (the commands that
// project points: ocg_slam run and objects).
// With UnknownKeys::kError, keys no module reads are a SettingsError listing each with its
// place and the known key it most likely meant.
LoadedSettings LoadSettings(const std::string& path, CameraNeed camera_need = CameraNeed::kNone,
                            UnknownKeys unknown_keys = UnknownKeys::kWarn);
LoadedSettings ParseSettings(const std::string& text, const std::string& name,
                             CameraNeed camera_need = CameraNeed::kNone,
                             UnknownKeys unknown_keys = UnknownKeys::kWarn);
// The same from a file already parsed (and perhaps changed with SettingsFile::Set).
LoadedSettings ReadSettingsFile(const SettingsFile& file, CameraNeed camera_need,
                                UnknownKeys unknown_keys);

// Throws SettingsError naming the settings file and both sizes when the camera's image size
// (Camera.width/height, or the default 640x480 when the file gives neither, as ORB-SLAM2's
// TUM files do) is not the size of image_path (the first image of a sequence): the settings
// are those of another camera. Throws FileError when the image cannot be read.
void CheckCameraFitsImage(const LoadedSettings& loaded, const std::string& image_path);

// Every key the modules read, in reading order (the camera in ORB-SLAM2's layout).
std::vector<std::string> KnownSettingsKeys();

// One module's keys as its field list gives them (ocg/core/option_fields.h): the source of
// the tables of docs/settings.md. The camera is not among them: its keys depend on the
// file's layout (docs/settings.md describes both).
struct SettingsSection {
  std::string name;  // "Tracking", "LocalMapping", ...: the prefix of its keys
  std::vector<OptionFieldDescription> fields;
};
std::vector<SettingsSection> DescribeSettings();

// A section as the Markdown table of docs/settings.md, between its marker lines:
//   <!-- settings-table NAME -->
//   | key | default | values | meaning |
//   ...
//   <!-- end settings-table -->
std::string SettingsTableMarkdown(const SettingsSection& section);

// The SLAM system's part of the settings; the initializer's RANSAC seed mixed with
// System.seed so that one seed changes every random choice of a run.
SystemConfig MakeSystemConfig(const Settings& settings);

}  // namespace ocg
