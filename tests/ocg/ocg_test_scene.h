#pragma once
// Small scenes for the OCG tests: a camera that looks at points, and keyframe
// observations built from it.

#include <vector>

#include "ocg/ocg/observation.h"
#include "test_support.h"

namespace ocg::testing {

using ::ocg::LookAt;

inline KeyframeObservation MakeObservation(std::int64_t keyframe, const SE3& T_cw,
                                           std::vector<ObjectId> observed) {
  KeyframeObservation observation;
  observation.keyframe_id = keyframe;
  observation.timestamp = 0.5 * static_cast<double>(keyframe);
  observation.T_cw = T_cw;
  observation.camera = TestCamera();
  observation.observed = std::move(observed);
  return observation;
}

}  // namespace ocg::testing
