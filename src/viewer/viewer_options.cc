#include "ocg/viewer/viewer_options.h"

#include "ocg/core/options.h"
#include "ocg/core/settings_file.h"

namespace ocg {

void ViewerOptions::Check() const { CheckOptionFields(*this); }

void ReadSettings(const SettingsFile& file, ViewerOptions* options) {
  ReadOptionFields(file, options);
}

}  // namespace ocg
