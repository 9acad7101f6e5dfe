#pragma once
// Image boxes, the detections the object layer accepts, and cuboids.

#include <array>
#include <optional>
#include <utility>
#include <vector>

#include "ocg/core/box2.h"
#include "ocg/core/camera.h"
#include "ocg/core/lie.h"
#include "ocg/io/detections.h"
#include "ocg/objects/objects_options.h"

namespace ocg {

// How a detection box fits the projection of an object's cuboid (both pixels):
// kWhole: IoU at least min_iou; kPartial: a view of the object partly hidden behind
// something nearer, whose box covers only its visible part: the box lies inside the
// projection (kPartialViewInside of its area, for jitter) and spans it across one image
// axis (kPartialViewSpan of its width or height: a side or the top is hidden, not the
// whole object shrunk, as a farther object of the class on the same ray would be), or is
// flush with a vertical and a horizontal edge of it (a corner of the object, hidden on two
// sides; the shrunk whole touches no edge).
// "Inside" is measured against the projection grown by kProjectionSlack of its width and
// height on each side: the projected cuboid is an estimate, off by a share of the object's
// size, and the first sliver of an object coming out from behind another (a box a few
// pixels wide) pokes out of it by those pixels, a large share of the sliver's own area.
// "Spans" is measured against the projection shrunk by the same slack: an object mapped
// from a short stretch of views has a footprint taken square (object_geometry.h), its
// projection up to a quarter too large, and a side view of the real object spans less of
// it (round_2's cell phone, issue 18). A farther object of the class on the same ray still
// fails when its box is at most about half the projection on both axes.
enum class BoxFit { kNone, kWhole, kPartial };
constexpr double kPartialViewInside = 0.8;
constexpr double kPartialViewSpan = 0.7;
constexpr double kProjectionSlack = 0.1;
BoxFit FitOfBox(const Box2& box, const Box2& projected, double min_iou);

// A detection the object layer uses.
struct ObjectDetection {
  int class_id = 0;
  Box2 box;
  double confidence = 0.0;
  bool truncated = false;  // touches the image border (ObjectsOptions::border_margin)
};

// Keeps the detections of mapped classes at or above the minimum confidence, clips boxes
// to the image, flags the ones at its border and suppresses same-class duplicates
// (Objects.nms_iou). Order is kept.
std::vector<ObjectDetection> FilterDetections(const std::vector<Detection>& detections,
                                              const ObjectsOptions& options,
                                              const PinholeCamera& camera);

// Whether detections[index]'s box shares area with a more confident box of its class (of
// two as confident, the earlier one wins): two objects of a class standing together or one
// behind the other, whose boxes the detector splits its own way in every frame, or its
// second box on one object. As in the suppression (Objects.nms_iou), the more confident
// box is the detector's best word on that part of the image; the other may be on either
// object.
bool BesideAMoreConfidentBoxOfItsClass(const std::vector<ObjectDetection>& detections,
                                       std::size_t index);

// A gravity-aligned box: size along its own axes, yaw about the up direction.
struct Cuboid {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // world
  Eigen::Vector3d size = Eigen::Vector3d::Zero();    // full extents: x, y horizontal, z up
  double yaw = 0.0;                                  // radians, about up
};

// Rotation from a gravity frame (z = up) to the world; x is the world axis least aligned
// with up, projected on the horizontal plane, so that for up = world z it is the identity.
Eigen::Matrix3d GravityFrame(const Eigen::Vector3d& up);

// Corner i is at -+ half the size along the cuboid's x (bit 0 of i), y (bit 1), z (bit 2).
std::array<Eigen::Vector3d, 8> CuboidCorners(const Cuboid& cuboid, const Eigen::Matrix3d& R_wg);
// The 12 edges, as pairs of corners.
std::array<std::pair<Eigen::Vector3d, Eigen::Vector3d>, 12> CuboidEdges(
    const Cuboid& cuboid, const Eigen::Matrix3d& R_wg);

// The bounding rectangle of the cuboid's projected corners, not clipped, with the camera's
// distortion or without; none when a corner is behind the camera (z <= 1 mm).
std::optional<Box2> CuboidImageBounds(const Cuboid& cuboid, const Eigen::Matrix3d& R_wg,
                                      const SE3& T_cw, const PinholeCamera& camera,
                                      bool with_distortion);

// The bounding rectangle of the cuboid's projected corners, clipped to the image; none
// when a corner is behind the camera or the rectangle misses the image.
std::optional<Box2> ProjectCuboid(const Cuboid& cuboid, const Eigen::Matrix3d& R_wg,
                                  const SE3& T_cw, const PinholeCamera& camera);

}  // namespace ocg
