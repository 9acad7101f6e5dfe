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
  RequireOption(tau_observable > 0 && tau_observable < 1, "OCG.tau_observable",
                "must be in (0, 1)");
  RequireOption(std::isfinite(tau_doubt) && tau_doubt >= 0, "OCG.tau_doubt",
                "must be non-negative");
  RequireOption(rate_high > tau_observable && rate_high < 1, "OCG.rate_high",
                "must be in (OCG.tau_observable, 1)");
  for (const auto& [key, value] :
       {std::pair<const char*, double>{"OCG.increment_full", increment_full},
        {"OCG.increment_high", increment_high},
        {"OCG.increment_low", increment_low}}) {
    RequireOption(std::isfinite(value) && value >= 0, key, "must be non-negative");
  }
  RequireOption(isolated_rate >= 0 && isolated_rate <= 1, "OCG.isolated_rate", "must be in [0, 1]");
  RequireOption(image_margin >= 0, "OCG.image_margin", "must be non-negative");
  RequireOption(distance_slack >= 1, "OCG.distance_slack", "must be at least 1");
  RequireOption(min_box_fraction > 0 && min_box_fraction <= 1, "OCG.min_box_fraction",
                "must be in (0, 1]");
  RequireOption(guard_min_neighbours >= 1, "OCG.guard_min_neighbours", "must be at least 1");
  RequireOption(view_max_angle_deg > 0 && view_max_angle_deg <= 180, "OCG.view_max_angle_deg",
                "must be in (0, 180]");
  RequireOption(reliable_detection_rate > 0 && reliable_detection_rate < 1,
                "OCG.reliable_detection_rate", "must be in (0, 1)");
  RequireOption(dropout_full_share > 0 && dropout_full_share < 1, "OCG.dropout_full_share",
                "must be in (0, 1)");
  RequireOption(max_occluded_share > 0 && max_occluded_share <= 1, "OCG.max_occluded_share",
                "must be in (0, 1]");
  RequireOption(visibility_keyframes >= 1, "OCG.visibility_keyframes", "must be at least 1");
}

void ReadSettings(const SettingsFile& file, OcgOptions* options) {
  VisitOcgOptionFields(*options, [&file](const char* name, auto& member) {
    file.Read(std::string("OCG.") + name, &member);
  });
}

}  // namespace ocg
