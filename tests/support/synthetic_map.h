#pragma once
// SLAM keyframes and map points from a SyntheticScene (synthetic_scene.h), for tests of
// the parts that work on a map (loop closing, map files): keyframes whose features are the
// scene's projections, map points at given positions, a map with covisibility and a
// spanning tree as local mapping leaves them.

#include <vector>

#include "ocg/features/bow_database.h"
#include "ocg/features/scale_pyramid.h"
#include "ocg/features/vocabulary.h"
#include "ocg/slam/map.h"
#include "synthetic_scene.h"

namespace ocg::testing {

// A keyframe of the scene's frame at pose T_cw (an estimate; the features are where the
// true pose projects the points): one feature per projection, at level 0, with the point's
// descriptor, the feature grid, BoW and feature vectors from vocabulary. No map points
// yet; not in any map.
KeyFramePtr SyntheticKeyFrame(const SyntheticScene& scene, int frame, const SE3& T_cw,
                              KeyFrameId id, const Vocabulary& vocabulary);

// Makes a map point of scene point `point` at position, observed by every keyframe of
// observers whose features hold that point, with normal, scale distances and descriptor
// set as local mapping sets them. Adds it to the map.
MapPointPtr AddSyntheticPoint(const SyntheticScene& scene, int point,
                              const Eigen::Vector3d& position,
                              const std::vector<KeyFramePtr>& observers,
                              const ScalePyramid& pyramid, Map* map);

// The index of the feature of scene point `point` in a SyntheticKeyFrame of frame, or -1.
int FeatureOfPoint(const SyntheticScene& scene, int frame, int point);

// After the keyframes and points are in: covisibility and the spanning tree (in id order),
// and every keyframe in database.
void ConnectSyntheticMap(Map* map, BowDatabase* database);

}  // namespace ocg::testing
