#include "ocg/features/orb_options.h"

#include "ocg/core/options.h"
#include "ocg/core/settings_file.h"

namespace ocg {

void OrbExtractorOptions::Check() const {
  CheckOptionFields(*this);
  RequireOption(minimum_fast_threshold <= initial_fast_threshold, "ORBextractor.minThFAST",
                "must be in [1, ORBextractor.iniThFAST]");
}

void ReadSettings(const SettingsFile& file, OrbExtractorOptions* options) {
  ReadOptionFields(file, options);
}

}  // namespace ocg
