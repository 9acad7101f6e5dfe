#include "ocg/objects/objects_options.h"

#include <algorithm>
#include <cmath>

#include "ocg/core/options.h"
#include "ocg/core/settings_file.h"

namespace ocg {

bool ObjectsOptions::MapsClass(int class_id) const {
  if (classes.empty()) return class_id != 0;
  return std::find(classes.begin(), classes.end(), class_id) != classes.end();
}

void ObjectsOptions::Check() const {
  CheckOptionFields(*this);
  for (int class_id : classes) {
    RequireOption(class_id >= 0 && class_id < 80, "Objects.classes",
                  "COCO-80 class ids are 0 to 79, got " + std::to_string(class_id));
  }
  RequireOption(max_rays >= candidate_min_observations, "Objects.max_rays",
                "must be at least Objects.candidate_min_observations");
  RequireOption(max_sightings == 0 || max_sightings >= std::max(8, max_rays),
                "Objects.max_sightings", "must be 0 (keep all) or at least Objects.max_rays and 8");
  RequireOption(up.allFinite() && up.norm() > 1e-9, "Objects.up", "must be a non-zero vector");
}

void ReadSettings(const SettingsFile& file, ObjectsOptions* options) {
  ReadOptionFields(file, options);
}

}  // namespace ocg
