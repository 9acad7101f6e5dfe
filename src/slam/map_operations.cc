#include "ocg/slam/map_operations.h"

#include <map>

namespace ocg {

ProjectedPoint SearchWindow(const PointProjection& projection, const MapPoint& point,
                            const ScalePyramid& pyramid, double radius_pixels) {
  const int level = pyramid.PredictLevel(projection.distance, point.max_distance);
  ProjectedPoint window;
  window.pixel = projection.pixel;
  window.radius = radius_pixels * pyramid.scale[static_cast<std::size_t>(level)];
  window.min_level = std::max(0, level - 1);
  window.max_level = level + 1;
  window.descriptor = point.descriptor;
  return window;
}

int FusePoints(Map& map, const PinholeCamera& camera, const ScalePyramid& pyramid,
               const MatcherOptions& matcher, double radius_pixels, const KeyFramePtr& target,
               const std::vector<MapPointPtr>& points) {
  std::vector<ProjectedPoint> projected;
  std::vector<MapPointPtr> sources;
  for (const MapPointPtr& point : points) {
    if (!point || point->bad || point->observations.count(target->id) != 0) continue;
    const auto projection =
        ProjectPoint(camera, target->features.grid.bounds(), target->T_cw, *point, true);
    if (!projection) continue;
    projected.push_back(SearchWindow(*projection, *point, pyramid, radius_pixels));
    sources.push_back(point);
  }
  MatcherOptions options = matcher;
  options.check_orientation = false;
  const std::vector<int> matches = SearchByProjection(target->features, projected, nullptr, 0.0,
                                                      matcher.strict_distance, options);
  int fused = 0;
  for (std::size_t q = 0; q < matches.size(); ++q) {
    if (matches[q] == kNoMatch) continue;
    const MapPointPtr& source = sources[q];
    if (source->bad) continue;
    const MapPointPtr existing = target->points[static_cast<std::size_t>(matches[q])];
    if (existing && !existing->bad) {
      if (existing == source) continue;
      if (existing->observations.size() > source->observations.size()) {
        map.ReplacePoint(source, existing);
      } else {
        map.ReplacePoint(existing, source);
      }
    } else {
      map.AddObservation(target, matches[q], source);
    }
    ++fused;
  }
  return fused;
}

bool AdjustKeyFrames(Map& map, const PinholeCamera& camera, const ScalePyramid& pyramid,
                     const std::vector<KeyFramePtr>& keyframes, int iterations) {
  if (map.keyframes().empty()) return false;
  std::vector<KeyFramePtr> local = keyframes;
  std::map<KeyFrameId, int> keyframe_index;
  BundleAdjustmentProblem problem;
  problem.camera = camera;
  const KeyFrameId first_id = map.keyframes().begin()->first;
  for (const KeyFramePtr& k : local) {
    keyframe_index[k->id] = static_cast<int>(problem.keyframes.size());
    problem.keyframes.push_back({k->T_cw, k->id == first_id});
  }
  std::vector<MapPointPtr> points;
  std::map<MapPointId, int> point_index;
  for (const KeyFramePtr& k : keyframes) {
    for (const MapPointPtr& point : k->points) {
      if (!point || point->bad || point_index.count(point->id) != 0) continue;
      point_index[point->id] = static_cast<int>(points.size());
      points.push_back(point);
      problem.points.push_back({point->position, false});
    }
  }
  // Keyframes outside the set that see its points hold the gauge, fixed.
  std::vector<std::pair<MapPointPtr, KeyFramePtr>> observation_owner;
  for (std::size_t p = 0; p < points.size(); ++p) {
    for (const auto& [keyframe_id, feature] : points[p]->observations) {
      const KeyFramePtr k = map.GetKeyFrame(keyframe_id);
      if (!k || k->bad) continue;
      auto found = keyframe_index.find(keyframe_id);
      if (found == keyframe_index.end()) {
        found =
            keyframe_index.emplace(keyframe_id, static_cast<int>(problem.keyframes.size())).first;
        problem.keyframes.push_back({k->T_cw, true});
        local.push_back(k);
      }
      const cv::KeyPoint& kp = k->features.keypoints[static_cast<std::size_t>(feature)];
      problem.observations.push_back({found->second, static_cast<int>(p),
                                      k->features.undistorted[static_cast<std::size_t>(feature)],
                                      pyramid.inverse_sigma2[static_cast<std::size_t>(kp.octave)]});
      observation_owner.emplace_back(points[p], k);
    }
  }
  BundleAdjustmentOptions options;
  options.max_iterations = iterations;
  const BundleAdjustmentReport report = BundleAdjust(&problem, options);
  if (!report.solved) return false;
  for (std::size_t i = 0; i < local.size(); ++i) {
    if (!problem.keyframes[i].fixed) local[i]->T_cw = problem.keyframes[i].T_cw;
  }
  for (std::size_t p = 0; p < points.size(); ++p) points[p]->position = problem.points[p].position;
  for (std::size_t i = 0; i < report.outlier.size(); ++i) {
    if (!report.outlier[i]) continue;
    const auto& [point, owner] = observation_owner[i];
    if (!point->bad) map.EraseObservation(owner, point);
  }
  for (const MapPointPtr& point : points) {
    if (!point->bad) map.UpdatePointGeometry(point, pyramid);
  }
  return true;
}

}  // namespace ocg
