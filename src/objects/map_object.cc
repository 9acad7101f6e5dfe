#include "ocg/objects/map_object.h"

#include <algorithm>
#include <functional>
#include <optional>

#include "ocg/objects/object_geometry.h"

namespace ocg {
namespace {

// The yaw the point set's footprint tells (its minimum-area rectangle, when elongated
// enough), else none.
std::optional<double> PointSetYaw(const MapObject& object, const ObjectMapContext& context) {
  const std::vector<Eigen::Vector3d> point_set =
      ObjectPointSet(object, context.options.min_point_votes);
  if (static_cast<int>(point_set.size()) < context.options.yaw_min_points) return std::nullopt;
  std::vector<Eigen::Vector2d> footprint;
  for (const Eigen::Vector3d& point : point_set)
    footprint.push_back((context.R_wg.transpose() * point).head<2>());
  const Rectangle2 rectangle = MinAreaRectangle(footprint);
  const double long_side = std::max(rectangle.length, rectangle.width);
  const double short_side = std::min(rectangle.length, rectangle.width);
  if (!rectangle.valid || long_side < context.options.yaw_min_elongation * short_side)
    return std::nullopt;
  return rectangle.yaw;
}

}  // namespace

const ObjectPoints::PointSet& PointSetOf(const MapObject& object, int min_votes) {
  return object.points.Set(min_votes,
                           object.has_cuboid ? std::optional(object.cuboid.centre) : std::nullopt,
                           object.has_cuboid ? object.cuboid.size.maxCoeff() : 0.0);
}

std::vector<std::uint64_t> ObjectPointIds(const MapObject& object, int min_votes) {
  return PointSetOf(object, min_votes).ids;
}

std::vector<Eigen::Vector3d> ObjectPointSet(const MapObject& object, int min_votes) {
  return PointSetOf(object, min_votes).positions;
}

std::vector<Descriptor> ObjectAppearance(const MapObject& object, int min_votes) {
  std::vector<Descriptor> descriptors;
  for (std::uint64_t id : ObjectPointIds(object, min_votes)) {
    const ObjectPoint& point = object.points.at(id);
    if (point.descriptor) descriptors.push_back(*point.descriptor);
  }
  return descriptors;
}

namespace {

// Where along its rays (inliers of meet) the object is by its map points (SLAM runs): on
// the latest inlier ray, at the median range of its point set; nullopt with fewer than
// Objects.candidate_min_points points.
std::optional<Eigen::Vector3d> AlongRaysByPoints(const MapObject& object,
                                                 const std::vector<Ray>& rays,
                                                 const RayIntersection& meet,
                                                 const ObjectsOptions& options) {
  const std::vector<Eigen::Vector3d> point_set = ObjectPointSet(object, options.min_point_votes);
  if (point_set.empty() || static_cast<int>(point_set.size()) < options.candidate_min_points) {
    return std::nullopt;
  }
  std::size_t last = rays.size();
  while (last > 0 && !meet.inliers[last - 1]) --last;
  if (last == 0) return std::nullopt;
  const Ray& ray = rays[last - 1];  // the latest inlier view
  std::vector<double> ranges;
  for (const Eigen::Vector3d& point : point_set) {
    ranges.push_back((point - ray.origin).dot(ray.direction));
  }
  std::nth_element(ranges.begin(), ranges.begin() + ranges.size() / 2, ranges.end());
  const double range = ranges[ranges.size() / 2];
  if (range <= 0.0) return std::nullopt;
  return ray.origin + range * ray.direction;
}

}  // namespace

bool Reestimate(MapObject& object, bool candidate, const ObjectMapContext& context) {
  std::vector<const ObjectSighting*> usable;
  for (const ObjectSighting& sighting : object.sightings) {
    // A candidate triangulates from its uncrowded boxes alone: the centre of a box beside a
    // more confident one of its class may be on that object (a detector's second box on
    // it, or a box sliding onto it as the view changes), and its ray then meets the others
    // in front of both (issue 18, fr3: a bottle 1.3 m short, from second boxes on
    // another).
    if (!sighting.truncated && !(candidate && sighting.crowded)) usable.push_back(&sighting);
  }
  if (candidate && static_cast<int>(usable.size()) < context.options.candidate_min_observations) {
    return false;
  }
  std::vector<Ray> rays;
  std::vector<const ObjectSighting*> used;
  for (std::size_t index :
       Thinned(usable.size(), static_cast<std::size_t>(context.options.max_rays))) {
    used.push_back(usable[index]);
    rays.push_back(PixelRay(usable[index]->box.Centre(), usable[index]->T_cw, context.camera));
  }
  RayIntersection intersection =
      IntersectRays(rays, 0.01, candidate ? context.options.min_inlier_share : 0.5);
  if (!intersection.valid) return false;
  if (candidate && intersection.inlier_count < context.options.candidate_min_observations) {
    return false;
  }
  if (intersection.parallax_deg < context.options.candidate_min_parallax_deg) {
    // A camera turning on the spot (hand-held video) gives rays that barely diverge: where
    // they meet is noise. SLAM's map points in the boxes were triangulated over the whole
    // track's baseline, so they tell how far along the rays the object is.
    const std::optional<Eigen::Vector3d> along =
        AlongRaysByPoints(object, rays, intersection, context.options);
    if (along) {
      intersection.point = *along;
    } else if (candidate) {
      return false;
    }
  }
  std::vector<BoxView> views;
  for (std::size_t i = 0; i < used.size(); ++i) {
    if (intersection.inliers[i]) views.push_back({used[i]->T_cw, used[i]->box});
  }
  const std::optional<double> yaw = PointSetYaw(object, context);
  object.cuboid = EstimateCuboid(intersection.point, views, context.camera, context.R_wg, yaw);
  if (context.options.fit_cuboid_to_edges) {
    // The edges place the centre; the extents are taken again from the boxes at that
    // centre. The cuboid that bounds a cylinder's (a cup's, a bottle's) boxes from every
    // side has a footprint smaller than its diameter, and association and merging compare
    // the cuboid with the boxes' widths: with the fitted extents, fr3 long_office lost two
    // bottles' detections to their neighbours and removed them.
    const Cuboid fitted = FitCuboidToBoxes(object.cuboid, views, context.camera, context.R_wg);
    // A refused fit returns its start, whose extents are already the boxes' there.
    if (fitted.centre != object.cuboid.centre)
      object.cuboid = EstimateCuboid(fitted.centre, views, context.camera, context.R_wg, yaw);
  }
  object.yaw_from_points = yaw.has_value();
  object.has_cuboid = true;
  return true;
}

void Absorb(MapObject& into, const MapObject& from, int max_sightings) {
  into.sightings.Merge(from.sightings, static_cast<std::size_t>(max_sightings));
  for (const auto& [id, point] : from.points) into.points.Join(id, point);
  into.class_id = into.sightings.MajorityClass();
  into.first_frame = std::min(into.first_frame, from.first_frame);
  into.first_timestamp = std::min(into.first_timestamp, from.first_timestamp);
  into.last_frame = std::max(into.last_frame, from.last_frame);
  into.last_timestamp = std::max(into.last_timestamp, from.last_timestamp);
}

void AddPointVotes(MapObject& object, const std::vector<const PointObservation*>& box_points) {
  for (const PointObservation* point : box_points)
    object.points.Vote(point->id, 1, point->position);
}

void BoundPoints(MapObject& object, int max_points) {
  const auto limit = static_cast<std::size_t>(max_points);
  // A quarter over the bound before pruning: one prune per many added points.
  if (max_points <= 0 || object.points.size() <= limit + limit / 4) return;
  // The most voted kept; of equal votes the newer points (higher ids: the map culls the
  // old ones first).
  std::vector<std::pair<int, std::uint64_t>> ranked;
  ranked.reserve(object.points.size());
  for (const auto& [id, point] : object.points) ranked.emplace_back(point.votes, id);
  std::nth_element(ranked.begin(), ranked.begin() + static_cast<std::ptrdiff_t>(limit),
                   ranked.end(), std::greater<>());
  for (auto dropped = ranked.begin() + static_cast<std::ptrdiff_t>(limit); dropped != ranked.end();
       ++dropped)
    object.points.erase(dropped->second);
}

std::vector<std::size_t> Thinned(std::size_t count, std::size_t limit) {
  std::vector<std::size_t> indices;
  if (count <= limit) {
    for (std::size_t i = 0; i < count; ++i) indices.push_back(i);
    return indices;
  }
  for (std::size_t k = 0; k < limit; ++k) indices.push_back(k * (count - 1) / (limit - 1));
  return indices;
}

Eigen::Vector3d WorldExtent(const Cuboid& cuboid, const Eigen::Matrix3d& R_wg) {
  Eigen::Vector3d low = Eigen::Vector3d::Constant(1e300), high = -low;
  for (const Eigen::Vector3d& corner : CuboidCorners(cuboid, R_wg)) {
    low = low.cwiseMin(corner);
    high = high.cwiseMax(corner);
  }
  return high - low;
}

double OverlapShare(const Eigen::Vector3d& centre_a, const Eigen::Vector3d& extent_a,
                    const Eigen::Vector3d& centre_b, const Eigen::Vector3d& extent_b) {
  const Eigen::Vector3d low = (centre_a - 0.5 * extent_a).cwiseMax(centre_b - 0.5 * extent_b);
  const Eigen::Vector3d high = (centre_a + 0.5 * extent_a).cwiseMin(centre_b + 0.5 * extent_b);
  const double smaller = std::min(extent_a.prod(), extent_b.prod());
  if (smaller <= 0.0 || (high - low).minCoeff() <= 0.0) return 0.0;
  return (high - low).prod() / smaller;
}

bool SeenTogether(const MapObject& a, const MapObject& b, double duplicate_box_iou,
                  int min_frames) {
  int frames = 0;
  auto i = a.sightings.begin();
  auto j = b.sightings.begin();
  while (i != a.sightings.end() && j != b.sightings.end()) {
    if (i->frame == j->frame) {
      if (IntersectionOverUnion(i->box, j->box) < duplicate_box_iou && ++frames >= min_frames)
        return true;
      ++i;
      ++j;
    } else if (i->frame < j->frame) {
      ++i;
    } else {
      ++j;
    }
  }
  return false;
}

bool SeenInOneSession(const MapObject& a, const MapObject& b) {
  return a.sightings.SharesASessionWith(b.sightings);
}

ObjectChange ChangeOf(const char* type, std::int64_t keyframe_id, double timestamp,
                      const MapObject& object, int session) {
  ObjectChange change;
  change.type = type;
  change.keyframe_id = keyframe_id;
  change.timestamp = timestamp;
  change.object_id = object.id;
  change.class_id = object.class_id;
  change.cuboid = object.cuboid;
  change.sightings = object.sightings.total();
  change.session = session;
  return change;
}

}  // namespace ocg
