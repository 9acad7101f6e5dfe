#pragma once
// An object's appearance from the ORB features inside its detection boxes in the keyframes
// that saw it (docs/sessions.md, "Moves in changes.json"). A flat object carries a few
// map points, mostly the table's; its boxes hold tens of keypoints per keyframe, most on
// its own texture, which goes with it when it is carried elsewhere.
//
// The table around a flat object is in its boxes too, and does not move with it: after
// two objects of one class are carried past each other, A's new boxes hold the table near
// B's old place. Two cues leave that background out: keypoints whose map point lies
// outside the object's cuboid (grown by a margin) are not the object's, and descriptors
// also seen at the object's place in the other session's keyframes (where the object was
// not) are the place's, not the object's (PlaceDescriptors, WithoutBackground).

#include <cstdint>
#include <map>
#include <optional>
#include <vector>

#include "ocg/core/camera.h"
#include "ocg/core/lie.h"
#include "ocg/features/descriptor.h"
#include "ocg/objects/box.h"

namespace ocg {

// One SLAM keyframe's ORB features, as the box appearance reads them.
struct KeyframeFeatures {
  std::int64_t frame = 0;               // its frame over all sessions (as ObjectSighting::frame)
  SE3 T_cw;                             // world to camera
  std::vector<Eigen::Vector2d> pixels;  // keypoints in the image (as detection boxes), pixels
  std::vector<Descriptor> descriptors;  // one per keypoint
  // Per keypoint: the world position of its map point, none when it has none.
  std::vector<std::optional<Eigen::Vector3d>> points;
};

// Keyframes by frame.
using KeyframeFeatureMap = std::map<std::int64_t, KeyframeFeatures>;

struct BoxAppearanceOptions {
  // Share of a box's width and height kept about its centre: the border of a box holds
  // the most background.
  double box_share = 0.8;
  // A keypoint whose map point lies farther outside the cuboid than this share of the
  // cuboid's largest extent is background.
  double cuboid_margin = 0.25;
  // Sightings used, spread evenly over those at keyframes (bounds the work per object).
  int max_keyframes = 30;
  // Leave out what the object's place shows in the other sessions (ObjectMap::BoxAppearances).
  bool place_background = true;
  // Throws std::invalid_argument naming the field.
  void Check() const;
};

// A detection box of the object and the frame it was made in.
struct FrameBox {
  std::int64_t frame = 0;
  Box2 box;
};

// Descriptors of the keypoints inside the boxes (shrunk to box_share) in the keyframes of
// their frames (boxes of other frames are skipped), without keypoints whose map point lies
// outside the cuboid grown by cuboid_margin. R_wg: the gravity frame the cuboid is
// expressed in (ObjectMap::gravity_frame()).
std::vector<Descriptor> BoxDescriptors(const std::vector<FrameBox>& boxes, const Cuboid& cuboid,
                                       const Eigen::Matrix3d& R_wg,
                                       const KeyframeFeatureMap& keyframes,
                                       const BoxAppearanceOptions& options);

// Descriptors seen at a place: the keypoints inside the cuboid's projected box (shrunk to
// box_share) in each of the given keyframes that has the whole cuboid in front of it and
// its box inside the image. Keyframes spread evenly, at most max_keyframes of them.
std::vector<Descriptor> PlaceDescriptors(const Cuboid& cuboid, const Eigen::Matrix3d& R_wg,
                                         const PinholeCamera& camera,
                                         const std::vector<const KeyframeFeatures*>& keyframes,
                                         const BoxAppearanceOptions& options);

// The descriptors of object with none of background within max_distance bits.
std::vector<Descriptor> WithoutBackground(const std::vector<Descriptor>& object,
                                          const std::vector<Descriptor>& background,
                                          int max_distance);

}  // namespace ocg
