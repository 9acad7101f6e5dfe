#include "ocg/core/core_settings.h"

#include <cmath>

#include "ocg/core/options.h"
#include "ocg/core/settings_file.h"

namespace ocg {

void CameraSettings::Check() const {
  model.Check();
  RequireOption(std::isfinite(fps) && fps > 0, "Camera.fps", "must be positive");
}

void SystemOptions::Check() const {
  static const char* const kLevels[] = {"trace", "debug", "info", "warn", "error", "off"};
  bool known = false;
  for (const char* level : kLevels) known = known || log_level == level;
  RequireOption(known, "System.log_level", "must be trace, debug, info, warn, error or off");
}

void ReadSettings(const SettingsFile& file, CameraSettings* settings) {
  PinholeCamera& model = settings->model;
  file.Read("Camera.fx", &model.fx);
  file.Read("Camera.fy", &model.fy);
  file.Read("Camera.cx", &model.cx);
  file.Read("Camera.cy", &model.cy);
  file.Read("Camera.k1", &model.k1);
  file.Read("Camera.k2", &model.k2);
  file.Read("Camera.k3", &model.k3);
  file.Read("Camera.p1", &model.p1);
  file.Read("Camera.p2", &model.p2);
  file.Read("Camera.width", &model.width);
  file.Read("Camera.height", &model.height);
  file.Read("Camera.fps", &settings->fps);
  file.Read("Camera.RGB", &settings->rgb);
}

void ReadSettings(const SettingsFile& file, SystemOptions* options) {
  file.Read("System.sequential", &options->sequential);
  file.Read("System.seed", &options->seed);
  file.Read("System.log_level", &options->log_level);
}

}  // namespace ocg
