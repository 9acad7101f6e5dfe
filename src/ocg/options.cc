#include "ocg/ocg/options.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "ocg/core/options.h"
#include "ocg/core/settings_file.h"
#include "ocg/ocg/judgement_terms.h"

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
  const std::vector<JudgementTerm>& terms = JudgementTerms();
  for (const std::string& part : parts) {
    const bool known = part == "paper" || part == "improved" ||
                       std::any_of(terms.begin(), terms.end(),
                                   [&](const JudgementTerm& term) { return part == term.name; });
    RequireOption(known, "OCG.mode",
                  "unknown mode '" + part + "' (use paper, or " + JudgementTermNames() +
                      " joined with '+', or improved; baselines: off, visibility)");
  }
  RequireOption(parts.count("paper") == 0 || parts.size() == 1, "OCG.mode",
                "'paper' cannot be combined with improvements");
  const bool all = parts.count("improved") > 0;
  for (std::size_t i = 0; i < terms.size(); ++i) {
    if (!(parts.count(terms[i].name) > 0 || (all && terms[i].in_improved))) continue;
    modes.terms |= 1u << i;
    if (terms[i].flag) modes.*terms[i].flag = true;
  }
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
