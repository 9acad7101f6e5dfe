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

// Parses one line; throws ReplayFormatError saying which field is wrong.
KeyframeObservation ParseObservationJson(const std::string& line);
std::string ObservationToJson(const KeyframeObservation& observation);

// {"keyframe": K, "objects": [{"id", "state", "doubt", "active_edge_rate"}...], "removed": [...]}
std::string StatesLineJson(std::int64_t keyframe_id, const std::vector<ObjectStatus>& objects,
                           const std::vector<RemovalEvent>& removed);

// {"changes": [{"type": "removed", "keyframe", "timestamp", "object_id", "class_id",
// "class", "centroid", "doubt", "reason"}...]}
std::string ChangeLogJson(const std::vector<RemovalEvent>& removals);

}  // namespace ocg
