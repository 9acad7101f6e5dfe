#include "ocg/app/settings.h"

#include <spdlog/spdlog.h>

#include "ocg/core/file_io.h"
#include "ocg/core/options.h"
#include "ocg/core/settings_file.h"

namespace ocg {
namespace {

// ORB-SLAM2/3 keys we read nowhere but that their settings files carry and that do not
// change what a monocular run computes: no warning for them.
bool IsKnownForeignKey(const std::string& key) {
  return key == "Camera.bf" || key == "ThDepth" || key == "DepthMapFactor" ||
         key == "Viewer.imageViewScale";
}

void CheckAll(const Settings& settings) {
  settings.camera.Check();
  settings.system.Check();
  settings.orb.Check();
  settings.matcher.Check();
  settings.vocabulary.Check();
  settings.initializer.Check();
  settings.tracking.Check();
  settings.local_mapping.Check();
  settings.loop_closing.Check();
  settings.objects.Check();
  settings.ocg.Check();
  settings.viewer.Check();
}

LoadedSettings ReadAll(const SettingsFile& file, CameraNeed camera_need) {
  LoadedSettings loaded;
  Settings& settings = loaded.settings;
  settings.source = file.name();
  ReadSettings(file, &settings.camera);
  ReadSettings(file, &settings.system);
  ReadSettings(file, &settings.orb);
  ReadSettings(file, &settings.matcher);
  ReadSettings(file, &settings.vocabulary);
  ReadSettings(file, &settings.initializer);
  ReadSettings(file, &settings.tracking);
  ReadSettings(file, &settings.local_mapping);
  ReadSettings(file, &settings.loop_closing);
  ReadSettings(file, &settings.objects);
  ReadSettings(file, &settings.ocg);
  ReadSettings(file, &settings.viewer);
  try {
    CheckAll(settings);
  } catch (const OptionError& error) {
    throw SettingsError(file.Describe(CameraKeyInFile(file, error.key()), error.message()));
  }
  // After the values: a wrong value is reported where it is, even when keys are missing.
  RequireCamera(file, camera_need);
  loaded.image_size_given = file.Has("Camera.width") && file.Has("Camera.height");
  for (const std::string& key : file.UnreadKeys()) {
    if (IsKnownForeignKey(key)) continue;
    loaded.warnings.push_back(FileLocation(file.name(), file.LineOf(key)) + ": unknown key '" +
                              key + "' ignored");
    spdlog::warn("{}", loaded.warnings.back());
  }
  return loaded;
}

}  // namespace

void Settings::Check() const {
  try {
    CheckAll(*this);
  } catch (const OptionError& error) {
    throw SettingsError(source + ": key '" + error.key() + "': " + error.message());
  }
}

LoadedSettings LoadSettings(const std::string& path, CameraNeed camera_need) {
  return ReadAll(SettingsFile::Load(path), camera_need);
}

LoadedSettings ParseSettings(const std::string& text, const std::string& name,
                             CameraNeed camera_need) {
  return ReadAll(SettingsFile::Parse(text, name), camera_need);
}

SystemConfig MakeSystemConfig(const Settings& settings) {
  SystemConfig config;
  config.camera = settings.camera.model;
  config.fps = settings.camera.fps;
  config.sequential = settings.system.sequential;
  config.orb = settings.orb;
  config.matcher = settings.matcher;
  config.initializer = settings.initializer;
  config.initializer.two_view.seed ^= settings.system.seed;
  config.tracking = settings.tracking;
  config.local_mapping = settings.local_mapping;
  config.loop_closing = settings.loop_closing;
  config.seed = settings.system.seed;
  return config;
}

}  // namespace ocg
