#include "ocg/ocg/options.h"

#include <cmath>
#include <set>
#include <sstream>

#include "ocg/core/options.h"
#include "ocg/core/settings_file.h"

namespace ocg {
namespace {

std::set<std::string> ModeParts(const std::string& mode) {
  std::set<std::string> parts;
  std::istringstream stream(mode);
  for (std::string part; std::getline(stream, part, '+');) parts.insert(part);
  return parts;
}

}  // namespace

OcgModes ParseOcgMode(const std::string& mode) {
  static const std::set<std::string> kKnown = {
      "paper",   "fallback", "in_image",  "guard",    "view", "reliability", "restore",
      "dropout", "points",   "occlusion", "improved", "off",  "visibility"};
  const std::set<std::string> parts = ModeParts(mode);
  RequireOption(!parts.empty(), "OCG.mode", "must not be empty");
  OcgModes modes;
  for (const auto& [name, strategy] : {std::pair{"off", ChangeStrategy::kOff},
                                       std::pair{"visibility", ChangeStrategy::kVisibility}}) {
    if (parts.count(name) == 0) continue;
    RequireOption(parts.size() == 1, "OCG.mode",
                  std::string("the baseline '") + name + "' cannot be combined with other modes");
    modes.strategy = strategy;
    return modes;
  }
  for (const std::string& part : parts) {
    RequireOption(kKnown.count(part) > 0, "OCG.mode",
                  "unknown mode '" + part +
                      "' (use paper, or fallback, in_image, guard, view, reliability, restore, "
                      "dropout, points, occlusion joined with "
                      "'+', or improved; "
                      "baselines: off, visibility)");
  }
  RequireOption(parts.count("paper") == 0 || parts.size() == 1, "OCG.mode",
                "'paper' cannot be combined with improvements");
  const bool all = parts.count("improved") > 0;
  modes.isolated_fallback = all || parts.count("fallback") > 0;
  modes.box_in_image = all || parts.count("in_image") > 0;
  modes.dropout_guard = all || parts.count("guard") > 0;
  modes.detected_view = all || parts.count("view") > 0;
  modes.detection_reliability = parts.count("reliability") > 0;  // not in "improved"
  modes.restore = all || parts.count("restore") > 0;
  modes.dropout_discount = all || parts.count("dropout") > 0;
  modes.point_presence = all || parts.count("points") > 0;  // SLAM runs only: docs/ocg.md
  modes.occlusion = all || parts.count("occlusion") > 0;
  return modes;
}

void OcgOptions::Check() const {
  ParseOcgMode(mode);
  CheckOptionFields(*this);
  RequireOption(rate_high > tau_observable, "OCG.rate_high", "must be in (OCG.tau_observable, 1)");
}

void ReadSettings(const SettingsFile& file, OcgOptions* options) {
  ReadOptionFields(file, options);
}

}  // namespace ocg
