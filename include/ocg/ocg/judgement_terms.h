#pragma once
// The judgement terms of OCG.mode, listed once. Each improved mode ("fallback", "in_image",
// ..., "occlusion") is one JudgementTerm: its mode name, whether "improved" includes it,
// what it reads, and its effect on the judgement of an object not detected, as hooks that
// JudgeObject and ExpectedInView call in the list's order. ParseOcgMode and its error
// message are driven by the same list, so a new term is one entry in
// src/ocg/judgement_terms.cc (docs/architecture.md, "Adding an evidence source").

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "ocg/core/camera.h"
#include "ocg/core/lie.h"
#include "ocg/ocg/observation.h"
#include "ocg/ocg/options.h"

namespace ocg {

struct ObjectEvidence;
struct ObjectGeometry;

// What a term's hooks see of one object at one keyframe; T_cw maps world to camera.
// observation is the keyframe's input when the caller has it (null otherwise), so a term
// can read its own field of KeyframeObservation directly.
struct TermInput {
  ObjectId id;
  const KeyframeObservation* observation;
  const ObjectEvidence& evidence;
  const ObjectGeometry& geometry;
  const SE3& T_cw;
  const PinholeCamera& camera;
  const OcgOptions& options;
};

// One improved mode. Every hook may be null (the term does not act there); hooks are
// applied in the order of JudgementTerms(), which fixes the order of the floating-point
// products, so the order is part of the outputs.
struct JudgementTerm {
  const char* name;      // its part of OCG.mode
  bool in_improved;      // part of "improved"
  bool OcgModes::*flag;  // its named switch in OcgModes, or null (then only the bit)
  const char* reads;     // the evidence it reads (ObjectEvidence or ObjectGeometry fields)
  const char* effect;    // on P, the rate or the increment: one line, for errors and docs
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

}  // namespace ocg
