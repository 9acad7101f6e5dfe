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

// World-to-camera pose of a camera at eye looking at target, world up = +z, image y down.
inline SE3 LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - eye).normalized();
  Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ());
  if (x.norm() < 1e-9) x = Eigen::Vector3d::UnitX();
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d rotation_wc;
  rotation_wc << x, y, z;
  return SE3(rotation_wc, eye).Inverse();
}

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
