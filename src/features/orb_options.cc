#include "ocg/features/orb_options.h"

#include "ocg/core/options.h"
#include "ocg/core/settings_file.h"

namespace ocg {

void OrbExtractorOptions::Check() const {
  RequireOption(features > 0, "ORBextractor.nFeatures", "must be positive");
  RequireOption(scale_factor > 1.0, "ORBextractor.scaleFactor", "must be greater than 1");
  RequireOption(levels >= 1 && levels <= 32, "ORBextractor.nLevels", "must be in [1, 32]");
  RequireOption(initial_fast_threshold > 0 && initial_fast_threshold < 256,
                "ORBextractor.iniThFAST", "must be in [1, 255]");
  RequireOption(minimum_fast_threshold > 0 && minimum_fast_threshold <= initial_fast_threshold,
                "ORBextractor.minThFAST", "must be in [1, ORBextractor.iniThFAST]");
}

void ReadSettings(const SettingsFile& file, OrbExtractorOptions* options) {
  file.Read("ORBextractor.nFeatures", &options->features);
  file.Read("ORBextractor.scaleFactor", &options->scale_factor);
  file.Read("ORBextractor.nLevels", &options->levels);
  file.Read("ORBextractor.iniThFAST", &options->initial_fast_threshold);
  file.Read("ORBextractor.minThFAST", &options->minimum_fast_threshold);
}

}  // namespace ocg
