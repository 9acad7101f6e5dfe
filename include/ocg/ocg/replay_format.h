#pragma once
// The JSON forms of the OCG's input and output (SPEC 3.1, docs/ocg.md):
//  - one keyframe observation per line of a JSON-lines stream (ocg_replay's input),
//  - one states line per keyframe (states.jsonl),
//  - the change log (changes.json).

#include <stdexcept>
#include <string>
#include <vector>

#include "ocg/ocg/change_detector.h"
#include "ocg/ocg/observation.h"

namespace ocg {

class ReplayFormatError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Parses one line; throws ReplayFormatError naming the field that is wrong, missing or
// unknown. Reads every field VisitObservationFields and VisitObjectUpdateFields list.
KeyframeObservation ParseObservationJson(const std::string& line);
// One line (no newline) holding every field those lists give; its bytes are those the
// replay format has always had (keys in alphabetical order, empty optional lists left out).
std::string ObservationToJson(const KeyframeObservation& observation);

// One line per field of the observation, in the list's order: "name: type, unit
// (optional); meaning." (ocg_replay --fields, Python's help).
std::string ObservationFieldsHelp();

// The same as the fields table of docs/ocg.md (field, form, unit, absent, meaning), between
// the lines `<!-- settings-table observation -->` and `<!-- end settings-table -->`
// (tools/settings_docs.py writes it there).
std::string ObservationFieldsMarkdown();

// T_cw from a 4x4 matrix (world to camera), refusing what is not a rigid motion rather
// than re-orthonormalising a wrong matrix: throws std::invalid_argument saying what is
// wrong, the caller names the field.
SE3 RigidMotionFromMatrix(const Eigen::Matrix4d& matrix);

// {"keyframe": K, "objects": [{"id", "state", "doubt", "active_edge_rate"}...], "removed": [...]}
std::string StatesLineJson(std::int64_t keyframe_id, const std::vector<ObjectStatus>& objects,
                           const std::vector<RemovalEvent>& removed);

// {"changes": [{"type": "removed", "keyframe", "timestamp", "object_id", "class_id",
// "class", "centroid", "doubt", "reason"}...]}
std::string ChangeLogJson(const std::vector<RemovalEvent>& removals);

}  // namespace ocg
