#include "ocg/objects/point_presence.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace ocg {

int MatchAtProjection(const Eigen::Vector2d& pixel, const Descriptor& descriptor,
                      const FrameFeatureSearch& frame, const std::vector<bool>& taken) {
  const ExtractedFeatures& features = *frame.features;
  assert(taken.size() == features.size());
  // Without a predicted level (an object point keeps no scale range), every level is
  // searched, each within its own window: the widest bounds the grid query.
  const double widest = frame.radius * frame.pyramid.scale.back();
  int best = -1;
  int best_distance = std::numeric_limits<int>::max();
  int second_distance = std::numeric_limits<int>::max();
  for (int index : features.grid.InArea(pixel.x(), pixel.y(), widest)) {
    const auto i = static_cast<std::size_t>(index);
    if (taken[i]) continue;
    const int level = std::clamp(features.keypoints[i].octave, 0, frame.pyramid.levels() - 1);
    const double window = frame.radius * frame.pyramid.scale[static_cast<std::size_t>(level)];
    const Eigen::Vector2d offset = (features.undistorted[i] - pixel).cwiseAbs();
    if (offset.x() > window || offset.y() > window) continue;
    const int distance = HammingDistance(descriptor, features.descriptors[i]);
    if (distance < best_distance) {
      second_distance = best_distance;
      best_distance = distance;
      best = index;
    } else if (distance < second_distance) {
      second_distance = distance;
    }
  }
  if (best < 0 || best_distance > frame.max_distance) return -1;
  if (second_distance != std::numeric_limits<int>::max() &&
      best_distance > frame.ratio * second_distance)
    return -1;
  return best;
}

PointSearchCount SearchPointsInFrame(const std::vector<PointToFind>& points, const SE3& T_cw,
                                     const PinholeCamera& camera, const FrameFeatureSearch& frame) {
  PointSearchCount count;
  if (frame.features == nullptr || frame.features->size() == 0) return count;
  std::vector<bool> taken(frame.features->size(), false);
  for (const PointToFind& point : points) {
    const Eigen::Vector3d in_camera = T_cw * point.position;
    if (in_camera.z() <= 0.0) continue;
    const Eigen::Vector2d pixel = camera.ProjectUndistorted(in_camera);
    if (!frame.features->grid.bounds().Contains(pixel)) continue;
    ++count.in_image;
    const int match = MatchAtProjection(pixel, point.descriptor, frame, taken);
    if (match < 0) continue;
    taken[static_cast<std::size_t>(match)] = true;
    ++count.found;
  }
  return count;
}

}  // namespace ocg
