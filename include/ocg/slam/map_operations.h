#pragma once
// Map operations shared by local mapping and loop closing. Callers hold Map::mutex().

#include <vector>

#include "ocg/features/matcher.h"
#include "ocg/features/scale_pyramid.h"
#include "ocg/optim/bundle_adjustment.h"
#include "ocg/slam/map.h"

namespace ocg {

// Where to look for a point seen at projection: radius_pixels times the scale of the
// pyramid level its distance predicts, on that level or one either side.
ProjectedPoint SearchWindow(const PointProjection& projection, const MapPoint& point,
                            const ScalePyramid& pyramid, double radius_pixels);

// Projects points into target (its current pose) and matches them to its features
// within radius_pixels x the predicted level's scale: an unmatched feature gains the
// point as an observation; a feature that already has another point merges the two
// (the one with more observations is kept). Returns the number of points fused.
int FusePoints(Map& map, const PinholeCamera& camera, const ScalePyramid& pyramid,
               const MatcherOptions& matcher, double radius_pixels, const KeyFramePtr& target,
               const std::vector<MapPointPtr>& points);

// Bundle adjustment of the given keyframes and every point they see; keyframes outside
// the set that see those points are held fixed, as is the map's first keyframe (the
// gauge). Outlier observations are removed afterwards. False when Ceres gave no usable
// solution (the map is then unchanged).
bool AdjustKeyFrames(Map& map, const PinholeCamera& camera, const ScalePyramid& pyramid,
                     const std::vector<KeyFramePtr>& keyframes, int iterations,
                     int refine_iterations = 0);

// The same in three steps, so that a long (global) adjustment need not hold the map:
// prepare under Map::mutex(), solve without it, apply under it again.
struct KeyFrameAdjustment {
  BundleAdjustmentProblem problem;
  std::vector<KeyFramePtr> keyframes;                                  // one per problem keyframe
  std::vector<MapPointPtr> points;                                     // one per problem point
  std::vector<std::pair<MapPointPtr, KeyFramePtr>> observation_owner;  // per observation
  KeyFrameId first_new_keyframe = 0;  // ids from here on were added after preparing
  MapPointId first_new_point = 0;
  BundleAdjustmentReport report;
};
KeyFrameAdjustment PrepareAdjustment(const Map& map, const PinholeCamera& camera,
                                     const ScalePyramid& pyramid,
                                     const std::vector<KeyFramePtr>& keyframes);
// Needs no lock: touches the adjustment only. iterations of the robust solve, then
// refine_iterations without the outliers (BundleAdjustmentOptions). False when Ceres gave
// no usable solution.
bool SolveAdjustment(KeyFrameAdjustment* adjustment, int iterations, int refine_iterations = 0);
// The same with every option of the solve (iterations, tolerance, stop request).
bool SolveAdjustment(KeyFrameAdjustment* adjustment, const BundleAdjustmentOptions& options);
// Writes a solved adjustment into the map: poses and positions of what is still there,
// outlier observations removed. What was added since it was prepared follows the
// correction of what it hangs from: a keyframe that of its spanning-tree parent, a point
// that of its reference keyframe. Returns the number of keyframes and points that
// followed.
int ApplyAdjustment(Map& map, const ScalePyramid& pyramid, const KeyFrameAdjustment& adjustment);

}  // namespace ocg
