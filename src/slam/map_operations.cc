#include "ocg/slam/map_operations.h"

#include <spdlog/fmt/ranges.h>
#include <spdlog/spdlog.h>

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

KeyFrameAdjustment PrepareAdjustment(const Map& map, const PinholeCamera& camera,
                                     const ScalePyramid& pyramid,
                                     const std::vector<KeyFramePtr>& keyframes) {
  KeyFrameAdjustment adjustment;
  if (map.keyframes().empty()) return adjustment;
  adjustment.first_new_keyframe = map.keyframes().rbegin()->first + 1;
  adjustment.first_new_point = map.points().empty() ? 0 : map.points().rbegin()->first + 1;
  BundleAdjustmentProblem& problem = adjustment.problem;
  std::vector<KeyFramePtr>& local = adjustment.keyframes;
  local = keyframes;
  std::map<KeyFrameId, int> keyframe_index;
  problem.camera = camera;
  for (const KeyFramePtr& k : local) {
    keyframe_index[k->id] = static_cast<int>(problem.keyframes.size());
    // Each map's first keyframe holds its gauge.
    problem.keyframes.push_back({k->T_cw, k->id == map.FirstKeyFrame(k->map)});
  }
  std::vector<MapPointPtr>& points = adjustment.points;
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
      adjustment.observation_owner.emplace_back(points[p], k);
    }
  }
  return adjustment;
}

bool SolveAdjustment(KeyFrameAdjustment* adjustment, int iterations, int refine_iterations) {
  BundleAdjustmentOptions options;
  options.max_iterations = iterations;
  options.refine_iterations = refine_iterations;
  return SolveAdjustment(adjustment, options);
}

bool SolveAdjustment(KeyFrameAdjustment* adjustment, const BundleAdjustmentOptions& options) {
  if (adjustment->keyframes.empty()) return false;
  adjustment->report = BundleAdjust(&adjustment->problem, options);
  if (!adjustment->report.solved) {
    // The map keeps its poses; say which keyframes were left unadjusted and why.
    std::vector<KeyFrameId> free_ids;
    for (std::size_t i = 0; i < adjustment->keyframes.size(); ++i) {
      if (!adjustment->problem.keyframes[i].fixed) free_ids.push_back(adjustment->keyframes[i]->id);
    }
    spdlog::warn("bundle adjustment of keyframes [{}] failed, map left unchanged: {}",
                 fmt::join(free_ids, ", "), adjustment->report.message);
  }
  return adjustment->report.solved;
}

int ApplyAdjustment(Map& map, const ScalePyramid& pyramid, const KeyFrameAdjustment& adjustment) {
  const BundleAdjustmentProblem& problem = adjustment.problem;
  // Each keyframe's pose before and after, for what hangs from it.
  std::map<KeyFrameId, std::pair<SE3, SE3>> moved;
  for (std::size_t i = 0; i < adjustment.keyframes.size(); ++i) {
    const KeyFramePtr& k = adjustment.keyframes[i];
    if (problem.keyframes[i].fixed || k->bad) continue;
    moved.emplace(k->id, std::make_pair(k->T_cw, problem.keyframes[i].T_cw));
    k->T_cw = problem.keyframes[i].T_cw;
    map.journal().KeyFrame(k->id);
  }
  for (std::size_t p = 0; p < adjustment.points.size(); ++p) {
    if (adjustment.points[p]->bad) continue;
    adjustment.points[p]->position = problem.points[p].position;
    map.NotePointMoved(*adjustment.points[p]);
  }
  for (std::size_t i = 0; i < adjustment.report.outlier.size(); ++i) {
    if (!adjustment.report.outlier[i]) continue;
    const auto& [point, owner] = adjustment.observation_owner[i];
    if (!point->bad && !owner->bad) map.EraseObservation(owner, point);
  }
  for (const MapPointPtr& point : adjustment.points) {
    if (!point->bad) map.UpdatePointGeometry(point, pyramid);
  }
  // Added meanwhile (only when the adjustment ran without the map): parents come before
  // their children in id order.
  int followed = 0;
  for (auto it = map.keyframes().lower_bound(adjustment.first_new_keyframe);
       it != map.keyframes().end(); ++it) {
    const KeyFramePtr& k = it->second;
    if (k->bad || !k->has_parent) continue;
    const auto parent = moved.find(k->parent);
    if (parent == moved.end()) continue;
    const SE3 before = k->T_cw;
    k->T_cw = k->T_cw * parent->second.first.Inverse() * parent->second.second;
    map.journal().KeyFrame(k->id);
    moved.emplace(k->id, std::make_pair(before, k->T_cw));
    ++followed;
  }
  for (auto it = map.points().lower_bound(adjustment.first_new_point); it != map.points().end();
       ++it) {
    const MapPointPtr& point = it->second;
    const auto reference = moved.find(point->reference);
    if (point->bad || reference == moved.end()) continue;
    point->position =
        reference->second.second.Inverse() * (reference->second.first * point->position);
    map.NotePointMoved(*point);
    map.UpdatePointGeometry(point, pyramid);
    ++followed;
  }
  return followed;
}

bool AdjustKeyFrames(Map& map, const PinholeCamera& camera, const ScalePyramid& pyramid,
                     const std::vector<KeyFramePtr>& keyframes, int iterations,
                     int refine_iterations) {
  KeyFrameAdjustment adjustment = PrepareAdjustment(map, camera, pyramid, keyframes);
  if (!SolveAdjustment(&adjustment, iterations, refine_iterations)) return false;
  ApplyAdjustment(map, pyramid, adjustment);
  return true;
}

}  // namespace ocg
