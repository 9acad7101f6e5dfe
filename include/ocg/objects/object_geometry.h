#pragma once
// Where an object is and how big, from its boxes in views of known pose: the centre from
// the rays through the box centres (robust multi-view triangulation), refined on the
// boxes' edges (FitCuboidToBoxes); extents and yaw from the box sizes and the depth.

#include <optional>
#include <vector>

#include "ocg/core/camera.h"
#include "ocg/core/lie.h"
#include "ocg/objects/box.h"

namespace ocg {

struct Ray {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // unit
};

struct RayIntersection {
  bool valid = false;  // enough inliers, spread and in front of every inlier camera
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  std::vector<bool> inliers;
  int inlier_count = 0;
  double rms_distance = 0.0;  // of the inliers, metres
  double parallax_deg = 0.0;  // largest angle between two inlier rays
};

// The point nearest to all rays in the least-squares sense, reweighted (Cauchy) so that
// rays that miss the others stop pulling; inliers pass within 3 robust sigmas (at least
// min_sigma). Needs at least 2 rays and min_inlier_share of them inliers.
RayIntersection IntersectRays(const std::vector<Ray>& rays, double min_sigma = 0.01,
                              double min_inlier_share = 0.5);

// Distance from a point to the line of a ray.
double DistanceToRay(const Eigen::Vector3d& point, const Ray& ray);

// The ray through a pixel from a camera.
Ray PixelRay(const Eigen::Vector2d& pixel, const SE3& T_cw, const PinholeCamera& camera);

struct BoxView {
  SE3 T_cw;
  Box2 box;
};

// How well a box seen from a camera of known pose continues a track of boxes whose depth
// is not known yet (a candidate's, bridging a detector gap): at some depth along the ray
// through the centre of the track's last box, the object that box shows there (its width
// and height at that depth) projects into the new view, and into min_share of the track's
// views, as boxes that overlap the boxes seen there by at least min_iou. The depths swept
// run from 1e-3 to 1e3 (scale-free: SLAM maps have none), 2 % apart. iou: the new box's
// IoU at the best such depth, 0 when there is none; point: the object's centre there.
// With views from one place this asks a box of about the same size where the last one
// was; as the track's views spread, they fix the depth, and the new box must lie where
// the track's object projects.
struct TrackFit {
  double iou = 0.0;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
};
TrackFit FitOfBoxToTrack(const std::vector<BoxView>& track, const BoxView& view,
                         const PinholeCamera& camera, double min_iou, double min_share);

// The angle (degrees) under which a point sees the centres of two cameras.
double ParallaxDeg(const Eigen::Vector3d& point, const SE3& T_cw_a, const SE3& T_cw_b);

// Extents and yaw of a gravity-aligned cuboid centred at centre from untruncated boxes:
// each box gives the width and height it spans at the centre's depth; the footprint
// (a, b, yaw) is fitted to the widths seen from every azimuth, the height to the heights
// once the footprint's share (seen from above) is taken out. With views from too narrow a
// range of azimuths the footprint is taken square, yaw 0. Needs at least one view.
// known_yaw (from the object's map points, see MinAreaRectangle) fixes the yaw: only the
// sides are fitted, and a square footprint from narrow views is turned to it.
Cuboid EstimateCuboid(const Eigen::Vector3d& centre, const std::vector<BoxView>& views,
                      const PinholeCamera& camera, const Eigen::Matrix3d& R_wg,
                      std::optional<double> known_yaw = std::nullopt);

// The cuboid whose projected corners best bound the boxes (centre and extents; yaw kept):
// Levenberg-Marquardt (Ceres) from initial on the four edges of every view's box, the
// corners projected with the camera's distortion, each residual a share of that box's
// width or height, under a Cauchy loss of scale edge_loss_scale (a box that does not fit
// stops pulling). Why not the rays through the box centres alone: a box's centre is not
// where the object's centre projects (an object seen from above and aside shows more of
// its top and one side), and that offset turns with the view, so rays from stretches of
// views a few degrees apart meet beside the object, mostly in depth (docs/objects.md,
// "Edges, not centres"). The edges carry that offset. Views must be untruncated boxes (a
// cut box's edge is the image's), as many as the caller thought worth their cost
// (Reestimate: Objects.max_rays). Each extent stays within a factor 2 of initial's (a side
// seen from too few directions is not fixed by the edges). Returns initial when there are
// no views, when the fit does not lower the cost, or when its projections overlap the
// boxes less (summed IoU) than initial's.
Cuboid FitCuboidToBoxes(const Cuboid& initial, const std::vector<BoxView>& views,
                        const PinholeCamera& camera, const Eigen::Matrix3d& R_wg,
                        double edge_loss_scale = 0.1);

// The smallest-area rectangle holding 2-D points (rotating calipers on their convex hull):
// yaw of its first side in [0, 90) degrees, the side lengths along yaw and across it.
struct Rectangle2 {
  bool valid = false;  // at least 3 points not on one line
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double yaw = 0.0;
  double length = 0.0;  // along yaw
  double width = 0.0;   // across
};
Rectangle2 MinAreaRectangle(const std::vector<Eigen::Vector2d>& points);

}  // namespace ocg
