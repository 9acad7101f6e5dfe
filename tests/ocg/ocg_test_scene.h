#pragma once
// Small scenes for the OCG tests: a camera that looks at points, and keyframe
// observations built from it.

#include <vector>

#include "ocg/ocg/observation.h"

namespace ocg::testing {

inline PinholeCamera TestCamera() {
  PinholeCamera camera;
  camera.fx = camera.fy = 500.0;
  camera.cx = 320.0;
  camera.cy = 240.0;
  camera.width = 640;
  camera.height = 480;
  return camera;
}

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
