#pragma once
// One object's judgement at one keyframe: ActiveEdgeRate, P, the DoubtValue increment
// and the state transition, with the improved modes applied. The inputs are what the
// graph knows about the object; how they are gathered (incrementally or from scratch)
// is the caller's business.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "ocg/ocg/observation.h"
#include "ocg/ocg/options.h"
#include "ocg/ocg/state_machine.h"

namespace ocg {

class GraphView;  // judgement_terms.h

struct ObjectEvidence {
  bool observed = false;                // in V_k
  std::uint64_t observed_weight = 0;    // sum of E(i, j) over neighbours j in V_k
  std::uint64_t total_weight = 0;       // sum of E(i, j) over all neighbours
  std::size_t degree = 0;               // |N(i)|
  std::size_t observed_neighbours = 0;  // |N(i) ∩ V_k|
  // What a term needs beyond these it gathers itself (judgement_terms.h, GraphView).
};

struct ObjectGeometry {
  std::optional<Eigen::Vector3d> centroid;  // world frame
  std::optional<Eigen::Vector3d> size;      // world-axis extent
  double max_observed_distance = 0.0;       // farthest camera distance it was detected from
  // "view" mode only: unit vectors, world frame, from the centroid towards the cameras it
  // was detected from, no two closer than a third of OCG.view_max_angle_deg (so at most a
  // few hundred, however long it is watched).
  std::vector<Eigen::Vector3d> view_directions;
  // Its detection record, for "reliability": keyframes it was detected in, and keyframes
  // it was expected in (P = 1, r above tau_observable, not guarded) and missed.
  std::uint32_t detected_keyframes = 0;
  std::uint32_t missed_keyframes = 0;
};

struct Judgement {
  StateAndDoubt next;
  double rate = 0.0;  // the rate the transition used
  bool judged_by_geometry = false;
  // Expected and not detected (an increment was due): the caller adds it to the object's
  // missed_keyframes.
  bool missed = false;
};

// "reliability": the weight of one miss of an object with this detection record, in
// (0, 1]: min(1, ln(1 - p) / ln(1 - options.reliable_detection_rate)) with
// p = (detected + 1) / (detected + missed + 2).
double MissWeight(const ObjectGeometry& geometry, const OcgOptions& options);

// "dropout": the weight of one miss when the detector found observed_weight of the
// in_view_weight of the object's in-view neighbours, in [0, 1]: with s their ratio,
// min(1, ln(1 - s) / ln(1 - options.dropout_full_share)); 1 when in_view_weight is 0
// (nothing tells a dropout).
double DropoutWeight(std::uint64_t observed_weight, std::uint64_t in_view_weight,
                     const OcgOptions& options);

// P of the mode, for an object not detected: the share of the object expected in the
// image, 0 when it is not expected (centroid outside the image or behind the camera; with
// "in_image" its box less than min_box_fraction inside, else that fraction; with "view"
// the camera not where it was detected from). 1 or 0 in "paper" (SPEC 3.3).
double ExpectedInView(const ObjectGeometry& geometry, const SE3& T_cw, const PinholeCamera& camera,
                      const OcgOptions& options, const OcgModes& modes);

// modes must be ParseOcgMode(options.mode), parsed once by the caller. The improved modes
// are the terms of JudgementTerms() (judgement_terms.h), applied in their order; those that
// read the keyframe's observation (as "points" does) see object id in *observation, and
// nothing when it is null; those that gather from the graph ("dropout", "occlusion") read
// *graph, and gather nothing when it is null.
Judgement JudgeObject(const StateAndDoubt& current, const ObjectEvidence& evidence,
                      const ObjectGeometry& geometry, const SE3& T_cw, const PinholeCamera& camera,
                      const OcgOptions& options, const OcgModes& modes,
                      const KeyframeObservation* observation = nullptr, ObjectId id = 0,
                      const GraphView* graph = nullptr);

// A detection of the object from a camera at camera_centre (world): one more detected
// keyframe, the farthest distance and, with record_direction, the direction it was seen
// from.
void RecordDetectedView(ObjectGeometry& geometry, const Eigen::Vector3d& camera_centre,
                        const OcgOptions& options, bool record_direction);

// The "view" mode's expectation: the camera is where the object was detected from before,
// no farther than distance_slack times its farthest detection and within
// view_max_angle_deg of a direction it was detected from. True when nothing is known
// (no centroid or no recorded detection), as the paper assumes.
bool InDetectedView(const ObjectGeometry& geometry, const SE3& T_cw, const OcgOptions& options);

// The "fallback" mode's visibility: in front, inside the image by options.image_margin,
// and no farther than distance_slack times the farthest distance it was observed from.
bool GeometricallyVisible(const ObjectGeometry& geometry, const SE3& T_cw,
                          const PinholeCamera& camera, const OcgOptions& options);

}  // namespace ocg
