#pragma once
// The judgement terms of OCG.mode, listed once. Each improved mode ("fallback", "in_image",
// ..., "occlusion") is one JudgementTerm: its mode name, whether "improved" includes it,
// what it reads, and its effect on the judgement of an object not detected, as hooks that
// JudgeObject and ExpectedInView call in the list's order. ParseOcgMode and its error
// message and the modes table of docs/ocg.md (JudgementTermsMarkdown) are driven by the
// same list, so a new term is one entry in src/ocg/judgement_terms.cc (docs/architecture.md,
// "Adding an evidence source"). A term that needs more of the graph than ObjectEvidence
// gathers it itself through GraphView.

#include <any>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "ocg/core/camera.h"
#include "ocg/core/lie.h"
#include "ocg/ocg/graph.h"
#include "ocg/ocg/observation.h"
#include "ocg/ocg/options.h"

namespace ocg {

struct ObjectEvidence;
struct ObjectGeometry;

// The graph as a term may read it at one keyframe, to gather evidence of its own ("dropout":
// the weight of the neighbours in view; "occlusion": the image outlines of every object).
// The change detector gives one per keyframe (the from-scratch reference of the tests gives
// its own), so such a term adds nothing to ObjectEvidence or to the change detector.
class GraphView {
 public:
  virtual ~GraphView() = default;
  // The object's edges; id is in the graph.
  virtual const std::vector<CovisibilityEdge>& Neighbours(ObjectId id) const = 0;
  // The object's geometry; id is in the graph.
  virtual const ObjectGeometry& Geometry(ObjectId id) const = 0;
  // Detected in this keyframe (in its observed list).
  virtual bool Detected(ObjectId id) const = 0;
  // visit(id, geometry) for every object in the graph, in an order fixed for equal inputs.
  virtual void ForEachObject(
      const std::function<void(ObjectId, const ObjectGeometry&)>& visit) const = 0;
  virtual const OcgModes& modes() const = 0;
  // A value kept for this keyframe only, empty until a term sets it: what a term computes
  // once per keyframe (every object's outline) and reads for each object it judges.
  virtual std::any& KeyframeMemo(const char* key) const = 0;
};

// KeyframeMemo(key) as a T, made by make() at the keyframe's first call.
template <typename T, typename Make>
const T& KeyframeValue(const GraphView& graph, const char* key, Make&& make) {
  std::any& slot = graph.KeyframeMemo(key);
  if (!slot.has_value()) slot = make();
  return std::any_cast<const T&>(slot);
}

// What a term's hooks see of one object at one keyframe; T_cw maps world to camera.
// observation is the keyframe's input when the caller has it (null otherwise), so a term
// can read its own field of KeyframeObservation directly; graph likewise (null: the term
// gathers nothing and acts as if its evidence were absent).
struct TermInput {
  ObjectId id;
  const KeyframeObservation* observation;
  const ObjectEvidence& evidence;
  const ObjectGeometry& geometry;
  const SE3& T_cw;
  const PinholeCamera& camera;
  const OcgOptions& options;
  const GraphView* graph = nullptr;
};

// One improved mode. Every hook may be null (the term does not act there); hooks are
// applied in the order of JudgementTerms(), which fixes the order of the floating-point
// products, so the order is part of the outputs.
struct JudgementTerm {
  const char* name;      // its part of OCG.mode
  bool in_improved;      // part of "improved"
  bool OcgModes::*flag;  // its named switch in OcgModes, or null (then only the bit)
  // The evidence it reads: ObjectEvidence or ObjectGeometry fields, its observation field,
  // or what it gathers from the graph.
  const char* reads;
  const char* effect;  // on P, the rate or the increment: one line, for errors and docs
  // Objects of the graph this keyframe's observation makes worth judging (besides the
  // detected ones and their neighbours), appended to ids; ids not in the graph are skipped.
  void (*candidates)(const KeyframeObservation&, std::vector<ObjectId>& ids) = nullptr;
  // Not detected, but present: judged as if detected (no increment, doubt cleared).
  bool (*present)(const TermInput&) = nullptr;
  // The rate to judge by instead of ActiveEdgeRate (judged by geometry), or none.
  std::optional<double> (*rate)(const TermInput&) = nullptr;
  // P from the geometry alone (ExpectedInView): the fraction expected in the image so far,
  // in (0, 1], to the new one in [0, 1].
  double (*expected)(double fraction, const ObjectGeometry&, const SE3& T_cw, const PinholeCamera&,
                     const OcgOptions&) = nullptr;
  // P from this keyframe's evidence (after `expected`): as `expected`.
  double (*expected_now)(double fraction, const TermInput&) = nullptr;
  // True when no increment is due whatever P says.
  bool (*blocks_increment)(const TermInput&) = nullptr;
  // The weight of a miss (an increment due), in [0, 1], multiplied into the increment.
  double (*miss_weight)(const TermInput&) = nullptr;
};

// Every term, in the order they apply; at most kMaxJudgementTerms.
const std::vector<JudgementTerm>& JudgementTerms();

// "a, b, c": the terms' names in order, for messages and docs.
std::string JudgementTermNames();

// The modes table of docs/ocg.md (mode, in improved, reads, effect), between the lines
// `<!-- settings-table OCG.mode -->` and `<!-- end settings-table -->`
// (tools/settings_docs.py writes it there).
std::string JudgementTermsMarkdown();

}  // namespace ocg
