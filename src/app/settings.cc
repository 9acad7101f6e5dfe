#include "ocg/app/settings.h"

#include <spdlog/spdlog.h>

#include <opencv2/imgcodecs.hpp>
#include <type_traits>

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

// Every module's options with a field list, in reading order, with its section name (the
// prefix of its keys): the one list of modules behind reading, checking and the docs tables.
// The camera, read first, has no field list (its keys depend on the file's layout).
template <typename SettingsType, typename Visit>
void ForEachModule(SettingsType& settings, Visit&& visit) {
  visit("System", settings.system);
  visit("ORBextractor", settings.orb);
  visit("Matcher", settings.matcher);
  visit("Vocabulary", settings.vocabulary);
  visit("Initializer", settings.initializer);
  visit("Tracking", settings.tracking);
  visit("LocalMapping", settings.local_mapping);
  visit("LoopClosing", settings.loop_closing);
  visit("Objects", settings.objects);
  visit("OCG", settings.ocg);
  visit("Viewer", settings.viewer);
}

void CheckAll(const Settings& settings) {
  settings.camera.Check();
  ForEachModule(settings, [](const char*, const auto& options) { options.Check(); });
}

void ReadEveryModule(const SettingsFile& file, Settings* settings) {
  ReadSettings(file, &settings->camera);
  ForEachModule(*settings, [&file](const char*, auto& options) { ReadSettings(file, &options); });
}

}  // namespace

LoadedSettings ReadSettingsFile(const SettingsFile& file, CameraNeed camera_need,
                                UnknownKeys unknown_keys) {
  LoadedSettings loaded;
  Settings& settings = loaded.settings;
  settings.source = file.name();
  try {
    ReadEveryModule(file, &settings);  // some readers check a value's shape (Objects.up)
    CheckAll(settings);
  } catch (const OptionError& error) {
    throw SettingsError(file.Describe(CameraKeyInFile(file, error.key()), error.message()));
  }
  // After the values: a wrong value is reported where it is, even when keys are missing.
  RequireCamera(file, camera_need);
  loaded.image_size_given = file.Has("Camera.width") && file.Has("Camera.height");
  // Every reader has asked for its keys: they are the known keys, spelt once, in the readers.
  const std::vector<std::string> known = file.AskedKeys();
  std::string unknown;
  for (const std::string& key : file.UnreadKeys()) {
    if (IsKnownForeignKey(key)) continue;
    const std::string closest = ClosestKey(key, known);
    const std::string suggestion = closest.empty() ? "" : "; did you mean '" + closest + "'?";
    if (unknown_keys == UnknownKeys::kError) {
      unknown += "\n  " + file.Where(key) + ": unknown key '" + key + "'" + suggestion;
      continue;
    }
    const std::string message =
        file.Where(key) + ": unknown key '" + key + "' ignored" + suggestion;
    loaded.warnings.push_back(message);
    spdlog::warn("{}", message);
  }
  if (!unknown.empty()) {
    throw SettingsError(file.name() +
                        ": unknown settings keys (no module reads them; "
                        "docs/settings.md lists the keys):" +
                        unknown);
  }
  return loaded;
}

void CheckCameraFitsImage(const LoadedSettings& loaded, const std::string& image_path) {
  const cv::Mat image = cv::imread(image_path, cv::IMREAD_UNCHANGED);
  if (image.empty()) throw FileError("cannot read the image '" + image_path + "'");
  const PinholeCamera& camera = loaded.settings.camera.model;
  if (image.cols == camera.width && image.rows == camera.height) return;
  const auto size = [](int width, int height) {
    return std::to_string(width) + "x" + std::to_string(height);
  };
  throw SettingsError(loaded.settings.source + ": the camera of these settings is " +
                      size(camera.width, camera.height) +
                      (loaded.image_size_given
                           ? " (Camera.width, Camera.height)"
                           : " (the default: the file gives no Camera.width and "
                             "Camera.height, as ORB-SLAM2's TUM files for 640x480 images)") +
                      ", but the images are " + size(image.cols, image.rows) + " ('" + image_path +
                      "'): give the settings of the camera that took these images");
}

std::vector<std::string> KnownSettingsKeys() {
  const SettingsFile empty = SettingsFile::Parse("", "(defaults)");
  Settings settings;
  ReadEveryModule(empty, &settings);
  return empty.AskedKeys();
}

std::vector<SettingsSection> DescribeSettings() {
  std::vector<SettingsSection> sections;
  const Settings defaults;
  ForEachModule(defaults, [&sections](const char* name, const auto& options) {
    sections.push_back({name, DescribeOptionFields<std::decay_t<decltype(options)>>()});
  });
  return sections;
}

std::string SettingsTableMarkdown(const SettingsSection& section) {
  std::string table = "<!-- settings-table " + section.name + " -->\n" +
                      "| key | default | values | meaning |\n|---|---|---|---|\n";
  for (const OptionFieldDescription& field : section.fields) {
    table += "| `" + field.key + "` | " + field.default_value + " | " + field.values + " | " +
             field.meaning + " |\n";
  }
  return table + "<!-- end settings-table -->\n";
}

void Settings::Check() const {
  try {
    CheckAll(*this);
  } catch (const OptionError& error) {
    throw SettingsError(source + ": key '" + error.key() + "': " + error.message());
  }
}

LoadedSettings LoadSettings(const std::string& path, CameraNeed camera_need,
                            UnknownKeys unknown_keys) {
  return ReadSettingsFile(SettingsFile::Load(path), camera_need, unknown_keys);
}

LoadedSettings ParseSettings(const std::string& text, const std::string& name,
                             CameraNeed camera_need, UnknownKeys unknown_keys) {
  return ReadSettingsFile(SettingsFile::Parse(text, name), camera_need, unknown_keys);
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
