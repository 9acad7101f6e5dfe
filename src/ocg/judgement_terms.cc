#include "ocg/ocg/judgement_terms.h"

#include <algorithm>
#include <sstream>
#include <stdexcept>

#include "ocg/ocg/judgement.h"
#include "ocg/ocg/observability.h"

namespace ocg {
namespace {

// "dropout": the summed weight of the object's edges to neighbours detected in this
// keyframe or expected in view (ExpectedInView of the mode). O(degree).
std::uint64_t InViewNeighbourWeight(const TermInput& in) {
  std::uint64_t weight = 0;
  for (const CovisibilityEdge& edge : in.graph->Neighbours(in.id)) {
    // A detected neighbour is in view even when its centroid projects outside the image.
    if (in.graph->Detected(edge.neighbour) ||
        ExpectedInView(in.graph->Geometry(edge.neighbour), in.T_cw, in.camera, in.options,
                       in.graph->modes()) > 0.0) {
      weight += edge.weight;
    }
  }
  return weight;
}

// "occlusion": the share of the object's image outline that the outlines of the graph's
// objects (each with a centroid and a size), wholly in front of it, cover. The outlines
// are projected once per keyframe (O(objects in the graph)). 0 without geometry.
double OccludedShareOf(const TermInput& in) {
  if (!in.geometry.centroid || !in.geometry.size) return 0.0;
  const std::optional<ImageFootprint> own =
      ProjectBox(*in.geometry.centroid, *in.geometry.size, in.T_cw, in.camera);
  if (!own) return 0.0;
  const auto& footprints =
      KeyframeValue<std::vector<ImageFootprint>>(*in.graph, "occlusion.footprints", [&in] {
        std::vector<ImageFootprint> made;
        in.graph->ForEachObject([&](ObjectId, const ObjectGeometry& geometry) {
          if (!geometry.centroid || !geometry.size) return;
          if (auto footprint = ProjectBox(*geometry.centroid, *geometry.size, in.T_cw, in.camera))
            made.push_back(std::move(*footprint));
        });
        return made;
      });
  // Its own footprint is among them but never in front of its own centre.
  return OccludedShare(*own, footprints, in.camera);
}

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

  // Acts in the change detector at a session's end (EndSession), not here.
  terms.push_back({"successor", true, &OcgModes::successor,
                   "class, first and last observed keyframes, edges",
                   "at a session's end, a suspicious object above tau_doubt is removed when an "
                   "object of its class, never seen with it, entered after its last observation"});

  JudgementTerm dropout{"dropout", true, &OcgModes::dropout_discount,
                        "observed_weight; gathers the weight of the neighbours in view",
                        "a miss weighs by the detected share of the neighbours in view"};
  // Missed together with most of what is in view: the detector failed across the view,
  // which says little about this object. No detected neighbour: nothing tells a dropout.
  dropout.miss_weight = [](const TermInput& in) {
    if (in.graph == nullptr || in.evidence.observed_weight == 0) return 1.0;
    return DropoutWeight(in.evidence.observed_weight, InViewNeighbourWeight(in), in.options);
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

  JudgementTerm occlusion{"occlusion", true, &OcgModes::occlusion,
                          "centroid, size; gathers every object's image outline",
                          "P is 0 for an object hidden behind nearer objects"};
  // Hidden behind objects nearer the camera: a detector cannot find it there.
  occlusion.expected_now = [](double fraction, const TermInput& in) {
    if (in.graph == nullptr) return fraction;
    return OccludedShareOf(in) >= in.options.max_occluded_share ? 0.0 : fraction;
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

std::string JudgementTermsMarkdown() {
  std::ostringstream out;
  out << "<!-- settings-table OCG.mode -->\n"
      << "| mode | in `improved` | reads | effect on an object not detected |\n"
      << "|---|---|---|---|\n";
  for (const JudgementTerm& term : JudgementTerms()) {
    out << "| `" << term.name << "` | " << (term.in_improved ? "yes" : "no") << " | " << term.reads
        << " | " << term.effect << " |\n";
  }
  out << "<!-- end settings-table -->\n";
  return out.str();
}

}  // namespace ocg
