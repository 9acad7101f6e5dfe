#pragma once
// Options of the Object Covisibility Graph (settings section OCG.*).

#include <cstddef>
#include <cstdint>
#include <string>
#include <type_traits>

#include "ocg/core/option_fields.h"

namespace ocg {

class SettingsFile;

// How objects are judged: the OCG (paper and improved modes) or one of the baselines.
enum class ChangeStrategy {
  kGraph,       // "paper" and the improved modes: SPEC 3
  kOff,         // "off": no change detection (EAO-SLAM keeps every object)
  kVisibility,  // "visibility": the naive test, no graph (see OcgOptions::visibility_keyframes)
};

// The most judgement terms (ocg/ocg/judgement_terms.h) OcgModes can switch on.
inline constexpr std::size_t kMaxJudgementTerms = 32;

// The strategy and improvements named by OCG.mode, parsed once (the hot loop must not
// parse strings).
struct OcgModes {
  ChangeStrategy strategy = ChangeStrategy::kGraph;
  // Bit i: JudgementTerms()[i] is on. The named switches below say the same for the
  // terms other parts ask about by name.
  std::uint32_t terms = 0;
  bool has(std::size_t term) const { return (terms >> term) & 1u; }
  bool isolated_fallback = false;      // "fallback"
  bool box_in_image = false;           // "in_image"
  bool dropout_guard = false;          // "guard"
  bool detected_view = false;          // "view"
  bool detection_reliability = false;  // "reliability"
  bool restore = false;                // "restore"
  bool dropout_discount = false;       // "dropout"
  bool point_presence = false;         // "points"
  bool occlusion = false;              // "occlusion"
  bool successor = false;              // "successor"
};

// Parses OCG.mode; throws OptionError naming the key when it is not a valid mode.
OcgModes ParseOcgMode(const std::string& mode);

struct OcgOptions {
  // OCG.mode: "paper" (SPEC 3 exactly) or improvements joined with '+'. The improvements
  // are the judgement terms, listed once with what each reads and does
  // (src/ocg/judgement_terms.cc; the modes table of docs/ocg.md is made from that list, and
  // the prose there tells the case each fixes). "improved", the default, is every term
  // marked so (on TUM fr3 long_office's real detections it removes no object of that static
  // scene, paper removes 14; docs/results.md); "improved+reliability" adds "reliability".
  // Baselines for comparison: "off" (nothing is ever removed) and "visibility" (an object
  // is removed after visibility_keyframes keyframes in which it should have been seen and
  // was not, no graph involved).
  std::string mode = "improved";

  // OCG.tau_observable: ActiveEdgeRate threshold for entering/leaving the observable region.
  double tau_observable = 0.2;
  // OCG.tau_doubt: DoubtValue above which an object is declared an outlier on leaving.
  double tau_doubt = 50.0;
  // OCG.increment_full / _high / _low: Eq. (2) increments for r = 1, r in [rate_high, 1),
  // and r in (tau_observable, rate_high).
  double increment_full = 30.0;
  double increment_high = 20.0;
  double increment_low = 10.0;
  // OCG.rate_high: lower bound of the middle band of Eq. (2).
  double rate_high = 0.5;

  // "fallback": ActiveEdgeRate assigned to a neighbourless object that is geometrically
  // visible (in front, inside the image by image_margin pixels, no farther than
  // distance_slack times the farthest distance it was observed from).
  double isolated_rate = 0.5;
  double image_margin = 10.0;
  double distance_slack = 1.1;
  // "in_image": the smallest fraction of the projected box inside the image for P = 1.
  double min_box_fraction = 0.5;
  // "guard": neighbours that must be detected in the keyframe for an increment (capped at
  // the object's degree).
  int guard_min_neighbours = 2;
  // "view": the largest angle, at the object, between the camera's direction and one the
  // object was detected from, for P = 1 (distance: distance_slack, as for "fallback").
  double view_max_angle_deg = 30.0;
  // "reliability": an object detected at least this share of the keyframes it was expected
  // in (P = 1, r > tau_observable, not guarded) takes the full increment; the rate counts
  // one detection and one miss more than seen, so a young object is not trusted fully.
  double reliable_detection_rate = 0.9;
  // "dropout": the detected share of the in-view neighbours' edge weight from which a
  // miss counts fully; below it a miss weighs by how likely the detector was to find the
  // object at the rate it found its neighbours (docs/ocg.md: real and generated figures).
  double dropout_full_share = 0.7;
  // "occlusion": the share of an object's image rectangle (inside the image) covered by
  // nearer objects' rectangles from which it counts as hidden (P = 0).
  double max_occluded_share = 0.5;
  // "visibility": keyframes since the last detection in which the object was geometrically
  // visible (as for "fallback") and not detected, after which it is removed.
  int visibility_keyframes = 5;

  // The parsed mode. Throws OptionError when mode is invalid.
  OcgModes modes() const { return ParseOcgMode(mode); }

  // The settings keys, once (ocg/core/option_fields.h); ocg.json names them without
  // "OCG." (VisitOcgOptionFields).
  template <typename Self, typename Visitor>
  static void VisitFields(Self& self, Visitor&& visit) {
    visit("OCG.mode", self.mode, OptionBound::Any(),
          "`improved` (every mode the [modes table](ocg.md#modes-ocgmode) marks so; the "
          "default: no removal on the static fr3 long_office with real detections, where "
          "`paper` removes 14), `paper` (the paper's OCG exactly), or modes of that table "
          "joined with `+` (also `improved+reliability`); baselines `off` (nothing removed, "
          "like EAO-SLAM) and `visibility` (the naive test); see [ocg.md](ocg.md) |");
    visit("OCG.tau_observable", self.tau_observable, OptionBound::Open(0, 1),
          "ActiveEdgeRate threshold");
    visit("OCG.tau_doubt", self.tau_doubt, OptionBound::NonNegative(),
          "DoubtValue threshold for removal");
    visit("OCG.increment_full", self.increment_full, OptionBound::NonNegative(),
          "Eq. (2) increment at r = 1");
    visit("OCG.increment_high", self.increment_high, OptionBound::NonNegative(),
          "increment for r in [`rate_high`, 1)");
    visit("OCG.increment_low", self.increment_low, OptionBound::NonNegative(),
          "increment for r in (`tau_observable`, `rate_high`)");
    visit("OCG.rate_high", self.rate_high, OptionBound::Open(0, 1),
          "lower bound of the middle band (above `tau_observable`)");
    visit("OCG.isolated_rate", self.isolated_rate, OptionBound::Closed(0, 1),
          "`fallback`: rate given to a visible neighbourless object");
    visit("OCG.image_margin", self.image_margin, OptionBound::NonNegative(),
          "`fallback`: pixels the centroid must be inside the image border");
    visit("OCG.distance_slack", self.distance_slack, OptionBound::AtLeast(1),
          "`fallback` and `view`: visible up to this times the farthest observation distance");
    visit("OCG.min_box_fraction", self.min_box_fraction, OptionBound::Between(0, true, 1, false),
          "`in_image`: share of the projected box inside the image for P = 1");
    visit("OCG.guard_min_neighbours", self.guard_min_neighbours, OptionBound::AtLeast(1),
          "`guard`: detected neighbours needed for an increment");
    visit("OCG.view_max_angle_deg", self.view_max_angle_deg,
          OptionBound::Between(0, true, 180, false),
          "`view`: P = 1 only within this angle (at the object) of a direction it was detected "
          "from");
    visit("OCG.reliable_detection_rate", self.reliable_detection_rate, OptionBound::Open(0, 1),
          "`reliability`: an object detected at least this share of the keyframes it was "
          "expected in takes the full increment");
    visit("OCG.dropout_full_share", self.dropout_full_share, OptionBound::Open(0, 1),
          "`dropout`: a miss counts fully when at least this share of the in-view neighbours' "
          "edge weight was detected; below, it weighs ln(1 − s) / ln(1 − this)");
    visit("OCG.max_occluded_share", self.max_occluded_share,
          OptionBound::Between(0, true, 1, false),
          "`occlusion`: P is 0 for an object not detected when at least this share of its image "
          "rectangle is covered by objects wholly in front of it");
    visit("OCG.visibility_keyframes", self.visibility_keyframes, OptionBound::AtLeast(1),
          "`visibility`: keyframes since the last detection in which the object was visible (as "
          "for `fallback`) and not detected, after which it is removed");
  }

  // Throws OptionError naming the key.
  void Check() const;
};

void ReadSettings(const SettingsFile& file, OcgOptions* options);

// Calls visit(name, member) for every field of OcgOptions::VisitFields, with the name
// without the "OCG." prefix: the names of ocg.json's options. Options may be const.
template <typename Options, typename Visitor>
void VisitOcgOptionFields(Options& options, Visitor&& visit) {
  std::remove_const_t<Options>::VisitFields(
      options, [&visit](const char* key, auto& member, const OptionBound&, const char*) {
        visit(key + 4, member);  // past "OCG."
      });
}

}  // namespace ocg
