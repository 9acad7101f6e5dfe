#include "ocg/ocg/judgement_terms.h"

#include <algorithm>
#include <stdexcept>

#include "ocg/ocg/judgement.h"
#include "ocg/ocg/observability.h"

namespace ocg {
namespace {

std::vector<JudgementTerm> MakeTerms() {
  std::vector<JudgementTerm> terms;

  JudgementTerm fallback{"fallback", true, &OcgModes::isolated_fallback,
                         "degree, centroid, max_observed_distance",
                         "a neighbourless object is judged by geometric visibility"};
  fallback.rate = [](const TermInput& in) -> std::optional<double> {
    if (in.evidence.degree != 0) return std::nullopt;
    return GeometricallyVisible(in.geometry, in.T_cw, in.camera, in.options)
               ? in.options.isolated_rate
               : 0.0;
  };
  terms.push_back(fallback);

  JudgementTerm in_image{"in_image", true, &OcgModes::box_in_image, "centroid, size",
                         "P needs the projected box mostly inside the image, scaled by it"};
  in_image.expected = [](double fraction, const ObjectGeometry& geometry, const SE3& T_cw,
                         const PinholeCamera& camera, const OcgOptions& options) {
    if (!geometry.size) return fraction;
    const double inside = BoxFractionInImage(*geometry.centroid, *geometry.size, T_cw, camera);
    return inside < options.min_box_fraction ? 0.0 : fraction * inside;
  };
  terms.push_back(in_image);

  JudgementTerm guard{"guard", true, &OcgModes::dropout_guard, "degree, observed_neighbours",
                      "an increment needs enough neighbours detected"};
  guard.blocks_increment = [](const TermInput& in) {
    if (in.evidence.degree == 0) return false;
    const std::size_t required = std::min<std::size_t>(
        static_cast<std::size_t>(in.options.guard_min_neighbours), in.evidence.degree);
    return in.evidence.observed_neighbours < required;
  };
  terms.push_back(guard);

  JudgementTerm view{"view", true, &OcgModes::detected_view, "centroid, view_directions",
                     "P needs the camera where the object was detected from"};
  // A detector finds an object from where it found it before: farther away it is too
  // small, from another side it looks different or is hidden by what it stands behind.
  view.expected = [](double fraction, const ObjectGeometry& geometry, const SE3& T_cw,
                     const PinholeCamera&, const OcgOptions& options) {
    return InDetectedView(geometry, T_cw, options) ? fraction : 0.0;
  };
  terms.push_back(view);

  JudgementTerm reliability{"reliability", false, &OcgModes::detection_reliability,
                            "detected_keyframes, missed_keyframes",
                            "a miss weighs by the object's own detection rate"};
  // A miss says little about an object the detector often misses: the doubt grows by
  // how unlikely its absence is under its own detection rate.
  reliability.miss_weight = [](const TermInput& in) { return MissWeight(in.geometry, in.options); };
  terms.push_back(reliability);

  // Acts in the change detector and the object map (removed objects kept), not here.
  terms.push_back({"restore", true, &OcgModes::restore, "restored",
                   "an object removed and detected again comes back with its history"});

  JudgementTerm dropout{"dropout", true, &OcgModes::dropout_discount,
                        "observed_weight, in_view_weight",
                        "a miss weighs by the detected share of the neighbours in view"};
  // Missed together with most of what is in view: the detector failed across the view,
  // which says little about this object.
  dropout.miss_weight = [](const TermInput& in) {
    return DropoutWeight(in.evidence.observed_weight, in.evidence.in_view_weight, in.options);
  };
  terms.push_back(dropout);

  JudgementTerm points{"points", true, &OcgModes::point_presence, "present_by_points",
                       "an object whose own map points were tracked is present"};
  // Its own points are where they were and look as they did: the detector missed it.
  // Present, as if detected; the caller gives it no edge and no detection record (only
  // detections feed the graph).
  points.candidates = [](const KeyframeObservation& observation, std::vector<ObjectId>& ids) {
    ids.insert(ids.end(), observation.present_by_points.begin(),
               observation.present_by_points.end());
  };
  points.present = [](const TermInput& in) {
    if (!in.observation) return false;
    const std::vector<ObjectId>& present = in.observation->present_by_points;
    return std::find(present.begin(), present.end(), in.id) != present.end();
  };
  terms.push_back(points);

  JudgementTerm occlusion{"occlusion", true, &OcgModes::occlusion, "occluded_share",
                          "P is 0 for an object hidden behind nearer objects"};
  // Hidden behind objects nearer the camera: a detector cannot find it there.
  occlusion.expected_now = [](double fraction, const TermInput& in) {
    return in.evidence.occluded_share >= in.options.max_occluded_share ? 0.0 : fraction;
  };
  terms.push_back(occlusion);
  return terms;
}

}  // namespace

const std::vector<JudgementTerm>& JudgementTerms() {
  static const std::vector<JudgementTerm> terms = [] {
    std::vector<JudgementTerm> made = MakeTerms();
    if (made.size() > kMaxJudgementTerms) throw std::logic_error("too many judgement terms");
    return made;
  }();
  return terms;
}

std::string JudgementTermNames() {
  std::string names;
  for (const JudgementTerm& term : JudgementTerms()) {
    if (!names.empty()) names += ", ";
    names += term.name;
  }
  return names;
}

}  // namespace ocg
