#pragma once
// OCG.mode "points" (SLAM runs): whether a keyframe still shows an object the detector
// missed, by its own map points. Each point of the object's point set that projects into
// the image is searched among the frame's ORB keypoints near its projection (the window
// grows with the keypoint's pyramid level, as tracking's search by projection) and its
// descriptor compared with theirs. A detector that misses an object does not change its
// texture; an object carried away leaves other texture at its place, and its points, which
// no longer stand there, find nothing like them.

#include <cstdint>
#include <vector>

#include "ocg/core/camera.h"
#include "ocg/core/lie.h"
#include "ocg/features/descriptor.h"
#include "ocg/features/orb_extractor.h"
#include "ocg/features/scale_pyramid.h"

namespace ocg {

// The frame a keyframe observation is made at, as the point search reads it: its ORB
// features (undistorted positions, levels, descriptors, grid), the pyramid they were
// extracted with, and the matcher's thresholds.
struct FrameFeatureSearch {
  const ExtractedFeatures* features = nullptr;  // null: no image (pose-given runs)
  ScalePyramid pyramid;
  // Objects.presence_search_radius: half-width of the window, level-0 pixels, times the
  // scale of the keypoint's level (a point seen at a coarse level is placed less exactly).
  double radius = 4.0;
  // Hamming distance a match may have (Matcher.looseDistance, as tracking's search by
  // projection): the map points tracking matches in a frame lie 50-100 bits from their
  // descriptor on the generated sequences, few within Matcher.strictDistance (50).
  int max_distance = 100;
  double ratio = 0.8;  // best / second best within the window (Matcher.projectionRatio)
};

// One object point to look for: where it is (world) and what it looks like.
struct PointToFind {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Descriptor descriptor{};
};

struct PointSearchCount {
  int in_image = 0;  // points in front of the camera that project inside the image
  int found = 0;     // of those, matched to a keypoint near their projection
};

// Searches each point in the frame seen from T_cw. A keypoint matches at most one point.
PointSearchCount SearchPointsInFrame(const std::vector<PointToFind>& points, const SE3& T_cw,
                                     const PinholeCamera& camera, const FrameFeatureSearch& frame);

// The keypoint that matches descriptor near pixel (undistorted), or -1: within
// frame.radius times the scale of the keypoint's own level, at most frame.max_distance
// bits, and better than frame.ratio times the second best in the window. taken (one per
// keypoint) marks keypoints already matched.
int MatchAtProjection(const Eigen::Vector2d& pixel, const Descriptor& descriptor,
                      const FrameFeatureSearch& frame, const std::vector<bool>& taken);

}  // namespace ocg
