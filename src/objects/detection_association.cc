#include "ocg/objects/detection_association.h"

#include <optional>

#include "ocg/objects/assignment.h"
#include "ocg/objects/object_geometry.h"

namespace ocg {
namespace {

constexpr double kCandidatePenalty = 0.05;  // a map object wins a tie against a candidate

// Whether one of box_points is a point on the object (voted for, within its largest
// extent of its centre).
bool HoldsOwnPoint(const MapObject& object, const std::vector<const PointObservation*>& box_points,
                   const ObjectMapContext& context) {
  const double reach = object.cuboid.size.maxCoeff();  // as ObjectPointSet: on the object
  for (const PointObservation* point : box_points) {
    const auto own = object.points.find(point->id);
    if (own != object.points.end() && own->second.votes >= context.options.min_point_votes &&
        (own->second.position - object.cuboid.centre).norm() <= reach) {
      return true;
    }
  }
  return false;
}

double AssociationScore(const MapObject& object, const ObjectDetection& detection,
                        std::int64_t frame, const SE3& T_cw, int session,
                        const std::vector<const PointObservation*>& box_points, bool with_points,
                        const ObjectMapContext& context) {
  if (object.has_cuboid) {
    // Geometry first: the ray through the box centre must pass near the object's centre.
    // Without this gate a detection of the same class close by (the object's new place
    // after a move) keeps matching through the predicted box and feeds the old object.
    const Ray ray = PixelRay(detection.box.Centre(), T_cw, context.camera);
    const bool in_front = (object.cuboid.centre - ray.origin).dot(ray.direction) > 0;
    if (!in_front || DistanceToRay(object.cuboid.centre, ray) >
                         context.options.max_ray_distance * object.cuboid.size.maxCoeff()) {
      return 0.0;
    }
  }
  const ObjectSighting& last = object.sightings.back();
  // Past the gate (most objects of the class are elsewhere), the point cue. The object's
  // own points (enough votes) are counted, and its point set bounded, once for the frames
  // between changes of its points (ObjectPoints): a frame meets about a hundred objects
  // and candidates in a revisited room, most unchanged since the last.
  const int min_votes = context.options.min_point_votes;
  const bool points_cue =
      with_points && box_points.size() >= 3 && object.points.VotedCount(min_votes) >= 5;
  if (object.has_cuboid && last.session < session && points_cue &&
      !HoldsOwnPoint(object, box_points, context)) {
    // Found again in a later session: between the visits an object of its class may have
    // been put down anywhere along this view's ray, and one view has no depth, so the
    // projected cuboid matches it just as well. The map points relocalized with the map
    // decide: an object that stayed shows some of its own in its box.
    return 0.0;
  }
  double sum = 0.0;
  int cues = 0;
  if (frame - last.frame <= context.options.predicted_box_frames) {
    Box2 predicted = last.box;
    if (object.has_cuboid) {
      // Move the last box with the centre's projection and scale it with its depth.
      const Eigen::Vector3d before = last.T_cw * object.cuboid.centre;
      const Eigen::Vector3d now = T_cw * object.cuboid.centre;
      if (before.z() > 1e-3 && now.z() > 1e-3) {
        const Eigen::Vector2d shift =
            context.camera.ProjectUndistorted(now) - context.camera.ProjectUndistorted(before);
        const double scale = before.z() / now.z();
        const Eigen::Vector2d centre = last.box.Centre() + shift;
        const double half_width = 0.5 * last.box.Width() * scale;
        const double half_height = 0.5 * last.box.Height() * scale;
        predicted = {centre.x() - half_width, centre.y() - half_height, centre.x() + half_width,
                     centre.y() + half_height};
      }
    }
    sum += IntersectionOverUnion(predicted, detection.box);
    ++cues;
  }
  if (object.has_cuboid) {
    const std::optional<Box2> projected =
        ProjectCuboid(object.cuboid, context.R_wg, T_cw, context.camera);
    const double overlap = projected ? IntersectionOverUnion(*projected, detection.box) : 0.0;
    // Found again after a gap, with nothing but the cuboid to go by: the detection must
    // cover it well, or an object of the class put down nearby would be taken for it.
    if (cues == 0 && overlap < context.options.min_reacquire_iou) return 0.0;
    sum += overlap;
    ++cues;
  }
  // Map points: the box holds the object's own points, and they lie where its points do.
  // Too few on either side says nothing (untextured objects, a new object).
  if (points_cue) {
    const RobustBounds& bounds = PointSetOf(object, min_votes).bounds;
    int shared = 0, inside = 0;
    for (const PointObservation* point : box_points) {
      const auto own = object.points.find(point->id);
      shared += own != object.points.end() && own->second.votes >= min_votes;
      inside += bounds.Contains(point->position) ? 1 : 0;
    }
    const double count = static_cast<double>(box_points.size());
    sum += shared / count + inside / count;
    cues += 2;
  }
  return cues > 0 ? sum / cues : 0.0;
}

}  // namespace

std::vector<int> AssociateDetections(
    const std::vector<MapObject*>& entities, std::size_t object_count,
    const std::vector<ObjectDetection>& detections,
    const std::vector<std::vector<const PointObservation*>>& box_points, bool with_points,
    std::int64_t frame, const SE3& T_cw, int session, const ObjectMapContext& context) {
  Eigen::MatrixXd cost =
      Eigen::MatrixXd::Constant(static_cast<Eigen::Index>(detections.size()),
                                static_cast<Eigen::Index>(entities.size()), kForbiddenCost);
  for (std::size_t d = 0; d < detections.size(); ++d) {
    for (std::size_t e = 0; e < entities.size(); ++e) {
      if (entities[e]->class_id != detections[d].class_id) continue;
      const double score = AssociationScore(*entities[e], detections[d], frame, T_cw, session,
                                            box_points[d], with_points, context);
      if (score < context.options.min_association_score) continue;
      cost(static_cast<Eigen::Index>(d), static_cast<Eigen::Index>(e)) =
          1.0 - score + (e >= object_count ? kCandidatePenalty : 0.0);
    }
  }
  return SolveAssignment(cost);
}

}  // namespace ocg
