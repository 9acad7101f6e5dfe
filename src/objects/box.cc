#include "ocg/objects/box.h"

#include <algorithm>
#include <cmath>

namespace ocg {

bool BesideAMoreConfidentBoxOfItsClass(const std::vector<ObjectDetection>& detections,
                                       std::size_t index) {
  const ObjectDetection& detection = detections[index];
  for (std::size_t other = 0; other < detections.size(); ++other) {
    const ObjectDetection& neighbour = detections[other];
    if (other == index || neighbour.class_id != detection.class_id) continue;
    const bool more_confident = neighbour.confidence > detection.confidence ||
                                (neighbour.confidence == detection.confidence && other < index);
    if (more_confident && SharedArea(detection.box, neighbour.box) > 0) return true;
  }
  return false;
}

BoxFit FitOfBox(const Box2& box, const Box2& projected, double min_iou) {
  if (IntersectionOverUnion(box, projected) >= min_iou) return BoxFit::kWhole;
  const double slack_x = kProjectionSlack * projected.Width();
  const double slack_y = kProjectionSlack * projected.Height();
  const Box2 with_slack{projected.x0 - slack_x, projected.y0 - slack_y, projected.x1 + slack_x,
                        projected.y1 + slack_y};
  if (box.Area() <= 0 || SharedArea(box, with_slack) < kPartialViewInside * box.Area()) {
    return BoxFit::kNone;
  }
  // Across the projection the estimate may be too large by the slack on both sides.
  const bool spans = box.Width() >= kPartialViewSpan * (projected.Width() - 2.0 * slack_x) ||
                     box.Height() >= kPartialViewSpan * (projected.Height() - 2.0 * slack_y);
  if (spans) return BoxFit::kPartial;
  // A corner of the object, the rest hidden by something nearer on two sides: the box is
  // flush (within the slack) with a vertical and a horizontal edge of the projection. The
  // whole shape shrunk about the centre (a farther object on the same ray) touches none.
  const auto flush = [](double a, double b, double slack) { return std::abs(a - b) <= slack; };
  const bool flush_x = flush(box.x0, projected.x0, slack_x) || flush(box.x1, projected.x1, slack_x);
  const bool flush_y = flush(box.y0, projected.y0, slack_y) || flush(box.y1, projected.y1, slack_y);
  return flush_x && flush_y ? BoxFit::kPartial : BoxFit::kNone;
}

std::vector<ObjectDetection> FilterDetections(const std::vector<Detection>& detections,
                                              const ObjectsOptions& options,
                                              const PinholeCamera& camera) {
  const double width = camera.width, height = camera.height, margin = options.border_margin;
  std::vector<ObjectDetection> kept;
  for (const Detection& detection : detections) {
    if (!options.MapsClass(detection.class_id) || detection.confidence < options.min_confidence) {
      continue;
    }
    ObjectDetection object;
    object.class_id = detection.class_id;
    object.confidence = detection.confidence;
    const Box2 raw{detection.x, detection.y, detection.x + detection.width,
                   detection.y + detection.height};
    object.box = {std::max(raw.x0, 0.0), std::max(raw.y0, 0.0), std::min(raw.x1, width),
                  std::min(raw.y1, height)};
    if (object.box.Area() <= 0) continue;  // entirely outside the image
    object.truncated = raw.x0 <= margin || raw.y0 <= margin || raw.x1 >= width - margin ||
                       raw.y1 >= height - margin;
    kept.push_back(object);
  }
  // Non-maximum suppression per class: the detector's duplicates would otherwise go to a
  // second object of the class nearby.
  std::vector<std::size_t> order(kept.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&kept](std::size_t a, std::size_t b) {
    return kept[a].confidence > kept[b].confidence;
  });
  std::vector<bool> suppressed(kept.size(), false);
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (suppressed[order[i]]) continue;
    for (std::size_t j = i + 1; j < order.size(); ++j) {
      const ObjectDetection& best = kept[order[i]];
      const ObjectDetection& other = kept[order[j]];
      if (other.class_id == best.class_id &&
          IntersectionOverUnion(best.box, other.box) > options.nms_iou) {
        suppressed[order[j]] = true;
      }
    }
  }
  std::vector<ObjectDetection> result;
  for (std::size_t i = 0; i < kept.size(); ++i) {
    if (!suppressed[i]) result.push_back(kept[i]);
  }
  return result;
}

Eigen::Matrix3d GravityFrame(const Eigen::Vector3d& up) {
  const Eigen::Vector3d z = up.normalized();
  Eigen::Index least = 0;
  z.cwiseAbs().minCoeff(&least);
  Eigen::Vector3d x = Eigen::Vector3d::Unit(least);
  x = (x - x.dot(z) * z).normalized();
  Eigen::Matrix3d R_wg;
  R_wg.col(0) = x;
  R_wg.col(1) = z.cross(x);
  R_wg.col(2) = z;
  return R_wg;
}

std::array<Eigen::Vector3d, 8> CuboidCorners(const Cuboid& cuboid, const Eigen::Matrix3d& R_wg) {
  const Eigen::Matrix3d rotation =
      R_wg * Eigen::AngleAxisd(cuboid.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  std::array<Eigen::Vector3d, 8> corners;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d sign((i & 1) ? 0.5 : -0.5, (i & 2) ? 0.5 : -0.5, (i & 4) ? 0.5 : -0.5);
    corners[static_cast<std::size_t>(i)] =
        cuboid.centre + rotation * sign.cwiseProduct(cuboid.size);
  }
  return corners;
}

std::array<std::pair<Eigen::Vector3d, Eigen::Vector3d>, 12> CuboidEdges(
    const Cuboid& cuboid, const Eigen::Matrix3d& R_wg) {
  const std::array<Eigen::Vector3d, 8> corners = CuboidCorners(cuboid, R_wg);
  std::array<std::pair<Eigen::Vector3d, Eigen::Vector3d>, 12> edges;
  std::size_t next = 0;
  for (int i = 0; i < 8; ++i) {
    for (int bit : {1, 2, 4}) {
      if ((i & bit) == 0)
        edges[next++] = {corners[static_cast<std::size_t>(i)],
                         corners[static_cast<std::size_t>(i | bit)]};
    }
  }
  return edges;
}

std::optional<Box2> CuboidImageBounds(const Cuboid& cuboid, const Eigen::Matrix3d& R_wg,
                                      const SE3& T_cw, const PinholeCamera& camera,
                                      bool with_distortion) {
  Box2 box{1e300, 1e300, -1e300, -1e300};
  for (const Eigen::Vector3d& corner : CuboidCorners(cuboid, R_wg)) {
    const Eigen::Vector3d point = T_cw * corner;
    if (point.z() <= 1e-3) return std::nullopt;
    const Eigen::Vector2d pixel =
        with_distortion ? camera.Project(point) : camera.ProjectUndistorted(point);
    box = {std::min(box.x0, pixel.x()), std::min(box.y0, pixel.y()), std::max(box.x1, pixel.x()),
           std::max(box.y1, pixel.y())};
  }
  return box;
}

std::optional<Box2> ProjectCuboid(const Cuboid& cuboid, const Eigen::Matrix3d& R_wg,
                                  const SE3& T_cw, const PinholeCamera& camera) {
  // Undistorted projection: boxes are compared in the image the detector saw, but for
  // the mild distortion of the cameras in use the difference is a pixel or two.
  std::optional<Box2> box = CuboidImageBounds(cuboid, R_wg, T_cw, camera, false);
  if (!box) return std::nullopt;
  box = Box2{std::max(box->x0, 0.0), std::max(box->y0, 0.0),
             std::min(box->x1, static_cast<double>(camera.width)),
             std::min(box->y1, static_cast<double>(camera.height))};
  if (box->Area() <= 0) return std::nullopt;
  return box;
}

}  // namespace ocg
