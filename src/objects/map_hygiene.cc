#include "ocg/objects/map_hygiene.h"

#include <algorithm>
#include <cstddef>
#include <optional>
#include <vector>

#include "ocg/objects/object_geometry.h"

namespace ocg {
namespace {

// The rays' noise floor of a triangulation (IntersectRays' min_sigma, as Reestimate uses).
constexpr double kMinRaySigma = 0.01;
// Two objects of one class whose centres are farther apart than this many times the larger
// one's largest extent are not tested for one bundle of rays (RaysMeetAsOne).
constexpr double kRaysMeetReach = 4.0;

// Whether a box that fits a projected cuboid so counts as a view of that object. A partial
// view counts only for an object of the box's class: a box inside a larger object's
// projection is as often a smaller object of another class in front of it.
bool CountsAsFit(BoxFit fit, bool same_class) {
  return fit == BoxFit::kWhole || (fit == BoxFit::kPartial && same_class);
}

// Whether stand_in's untruncated boxes fit object's projected cuboid (FitOfBox: whole, or
// partial views when of one class; for at least share of them): its detections fit object,
// at object's depth and size, wherever their own rays met.
bool SeenAsProjectionOf(const MapObject& stand_in, const MapObject& object, double min_iou,
                        double share, const Eigen::Matrix3d& R_wg, const PinholeCamera& camera) {
  const auto usable = std::count_if(stand_in.sightings.begin(), stand_in.sightings.end(),
                                    [](const ObjectSighting& s) { return !s.truncated; });
  // Most pairs fail at their first boxes: stop once too many missed.
  const double allowed_misses = (1.0 - share) * static_cast<double>(usable);
  int misses = 0;
  for (const ObjectSighting& sighting : stand_in.sightings) {
    if (sighting.truncated) continue;
    const std::optional<Box2> projected = ProjectCuboid(object.cuboid, R_wg, sighting.T_cw, camera);
    const BoxFit fit = projected ? FitOfBox(sighting.box, *projected, min_iou) : BoxFit::kNone;
    const bool covered = CountsAsFit(fit, stand_in.class_id == object.class_id);
    if (!covered && ++misses > allowed_misses) return false;
  }
  return usable > 0;
}

// How each sighting of track fits object's projected cuboid (truncated ones: kNone). With
// `needed` > 0 (a host search): none once the misses among track's `usable` untruncated
// boxes keep the share of fits (CountsAsFit for same_class, over the usable boxes, as
// HostOf computes it) below needed; most objects of the map miss a waiting candidate's
// first boxes.
std::optional<std::vector<BoxFit>> FitsOfTrack(const MapObject& track, const MapObject& object,
                                               const ObjectMapContext& context,
                                               bool same_class = false, double needed = 0.0,
                                               std::size_t usable = 0) {
  std::vector<BoxFit> fits;
  std::size_t misses = 0;
  for (const ObjectSighting& sighting : track.sightings) {
    const std::optional<Box2> projected =
        sighting.truncated
            ? std::nullopt
            : ProjectCuboid(object.cuboid, context.R_wg, sighting.T_cw, context.camera);
    const BoxFit fit = projected
                           ? FitOfBox(sighting.box, *projected, context.options.min_reacquire_iou)
                           : BoxFit::kNone;
    fits.push_back(fit);
    if (needed <= 0.0 || sighting.truncated || CountsAsFit(fit, same_class)) continue;
    ++misses;
    // The best share still possible, computed as the share itself is.
    if (static_cast<double>(usable - misses) / static_cast<double>(usable) < needed)
      return std::nullopt;
  }
  return fits;
}

// The rays through the centres of an object's untruncated, uncrowded boxes (thinned to
// Objects.max_rays, as for its triangulation), appended to rays.
void AppendBoxRays(const MapObject& object, const ObjectMapContext& context,
                   std::vector<Ray>* rays) {
  std::vector<const ObjectSighting*> usable;
  for (const ObjectSighting& sighting : object.sightings) {
    if (!sighting.truncated && !sighting.crowded) usable.push_back(&sighting);
  }
  for (std::size_t index :
       Thinned(usable.size(), static_cast<std::size_t>(context.options.max_rays))) {
    rays->push_back(PixelRay(usable[index]->box.Centre(), usable[index]->T_cw, context.camera));
  }
}

// Whether the box rays of a and b (one class), pooled, meet at one point about as well as
// each object's rays meet alone (Objects.merge_rays_ratio): one object, which two stretches
// of views triangulated apart (box centres miss the object's centre by a bias of their own
// in each direction of view; a small object's two estimates land a few centimetres apart,
// beyond merge_distance times its size). Two objects give two bundles of rays: one point
// leaves one bundle's rays far from it, or the robust fit takes one bundle alone and the
// other's rays are not its inliers. A test of one point against two, in the rays' own
// noise, so it needs no distance in map units (a monocular map has no metre).
bool RaysMeetAsOne(const MapObject& a, const MapObject& b, const ObjectMapContext& context) {
  std::vector<Ray> rays;
  AppendBoxRays(a, context, &rays);
  const std::size_t from_a = rays.size();
  AppendBoxRays(b, context, &rays);
  const std::size_t from_b = rays.size() - from_a;
  if (from_a < 2 || from_b < 2) return false;
  const double share = context.options.min_inlier_share;
  const RayIntersection joint = IntersectRays(rays, kMinRaySigma, share);
  if (!joint.valid) return false;
  std::size_t inliers_a = 0, inliers_b = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (joint.inliers[i]) ++(i < from_a ? inliers_a : inliers_b);
  }
  if (static_cast<double>(inliers_a) < share * static_cast<double>(from_a) ||
      static_cast<double>(inliers_b) < share * static_cast<double>(from_b)) {
    return false;
  }
  const auto alone = [&](std::size_t begin, std::size_t end) {
    return IntersectRays(std::vector<Ray>(rays.begin() + static_cast<std::ptrdiff_t>(begin),
                                          rays.begin() + static_cast<std::ptrdiff_t>(end)),
                         kMinRaySigma, 0.5)
        .rms_distance;
  };
  const double apart = std::max(alone(0, from_a), alone(from_a, rays.size()));
  return joint.rms_distance <= context.options.merge_rays_ratio * apart;
}

}  // namespace

std::optional<std::pair<ObjectId, ObjectId>> FindDuplicate(
    const std::map<ObjectId, MapObject>& objects, const ObjectMapContext& context) {
  for (auto a = objects.begin(); a != objects.end(); ++a) {
    for (auto b = std::next(a); b != objects.end(); ++b) {
      const MapObject& first = a->second;
      const MapObject& second = b->second;
      if (!first.has_cuboid || !second.has_cuboid) continue;
      const double larger = std::max(first.cuboid.size.maxCoeff(), second.cuboid.size.maxCoeff());
      const double smaller = std::min(first.cuboid.size.maxCoeff(), second.cuboid.size.maxCoeff());
      // One object seen under two classes has one size: of two classes, the smaller one's
      // (a cup within half a television's width of its centre is a cup beside it).
      const double reach =
          context.options.merge_distance * (first.class_id == second.class_id ? larger : smaller);
      const bool one_space =
          first.class_id == second.class_id &&
          OverlapShare(first.cuboid.centre, WorldExtent(first.cuboid, context.R_wg),
                       second.cuboid.centre,
                       WorldExtent(second.cuboid, context.R_wg)) > context.options.merge_overlap;
      bool keep_first = first.sightings.total() >= second.sightings.total();
      if (!one_space) {
        // Most pairs were detected together at some time: the cheap test first.
        if (SeenTogether(first, second, context.options.duplicate_box_iou,
                         context.options.seen_together_frames))
          continue;
        // Two objects of different classes are one object the detector named twice
        // only when a session saw both. Seen in different sessions, the new one near
        // the old one's place is more likely what was put there between the visits:
        // merged, it would count as the old object seen again and reset its doubt.
        if (first.class_id != second.class_id && !SeenInOneSession(first, second)) continue;
        const auto along_rays = [&](const MapObject& stand_in, const MapObject& object) {
          return context.options.merge_along_rays &&
                 SeenAsProjectionOf(stand_in, object, context.options.min_reacquire_iou,
                                    context.options.min_inlier_share, context.R_wg, context.camera);
        };
        if (along_rays(second, first)) {
          keep_first = true;
        } else if (along_rays(first, second)) {
          keep_first = false;
        } else if (first.class_id == second.class_id && context.options.merge_rays_ratio > 0.0) {
          // Of one class, the rays decide (a cheap reach first: beyond it two bundles
          // never meet as one).
          if ((first.cuboid.centre - second.cuboid.centre).norm() > kRaysMeetReach * larger ||
              !RaysMeetAsOne(first, second, context)) {
            continue;
          }
        } else if ((first.cuboid.centre - second.cuboid.centre).norm() > reach) {
          continue;
        }
      }
      return std::make_pair(keep_first ? first.id : second.id, keep_first ? second.id : first.id);
    }
  }
  return std::nullopt;
}

bool TooLittleEvidence(const MapObject& object, const ObjectsOptions& options) {
  // Crowded boxes (beside a more confident box of the class) may be the neighbour's: they
  // are no evidence that this object exists (issue 18, fr3: a bottle in mid-air, promoted from 8
  // boxes of two bottles, kept by 13 boxes beside the front bottle's).
  return object.keyframes_in_map >= options.probation_keyframes &&
         static_cast<int>(object.sightings.uncrowded()) < options.min_sightings;
}

MapObject* HostOf(MapObject& candidate, std::map<ObjectId, MapObject>& objects,
                  const ObjectMapContext& context) {
  const auto usable = std::count_if(candidate.sightings.begin(), candidate.sightings.end(),
                                    [](const ObjectSighting& s) { return !s.truncated; });
  if (usable == 0) return nullptr;
  // The host: its class before any other (a class flip is the rarer story), then the
  // largest share of fitting boxes.
  MapObject* host = nullptr;
  std::vector<BoxFit> host_fits;
  std::pair<bool, double> best{false, context.options.min_inlier_share};
  for (auto& [id, object] : objects) {
    if (!object.has_cuboid || SeenTogether(candidate, object, context.options.duplicate_box_iou,
                                           context.options.seen_together_frames))
      continue;
    const bool same_class = object.class_id == candidate.class_id;
    // As in the keyframe hygiene: another class is the same object misnamed only when
    // one session saw both; across sessions it is what was put at the old one's place.
    if (!same_class && !SeenInOneSession(candidate, object)) continue;
    // Another class never outranks a host of the candidate's class; a rank at least the
    // best's needs that share.
    if (!same_class && best.first) continue;
    const double needed = same_class == best.first ? best.second : context.options.min_inlier_share;
    std::optional<std::vector<BoxFit>> reached = FitsOfTrack(
        candidate, object, context, same_class, needed, static_cast<std::size_t>(usable));
    if (!reached) continue;
    std::vector<BoxFit> fits = std::move(*reached);
    const double share = static_cast<double>(std::count_if(
                             fits.begin(), fits.end(),
                             [same_class](BoxFit fit) { return CountsAsFit(fit, same_class); })) /
                         static_cast<double>(usable);
    const std::pair<bool, double> rank{same_class, share};
    if (share >= context.options.min_inlier_share && rank >= best) {
      best = rank;
      host = &object;
      host_fits = std::move(fits);
    }
  }
  if (host == nullptr) return nullptr;
  for (std::size_t i = 0; i < candidate.sightings.size(); ++i) {
    if (host_fits[i] == BoxFit::kPartial) candidate.sightings[i].truncated = true;
  }
  return host;
}

void MarkPartialViews(MapObject& stand_in, const MapObject& object,
                      const ObjectMapContext& context) {
  if (!object.has_cuboid) return;
  const std::vector<BoxFit> fits = *FitsOfTrack(stand_in, object, context);
  for (std::size_t i = 0; i < stand_in.sightings.size(); ++i) {
    if (fits[i] == BoxFit::kPartial) stand_in.sightings[i].truncated = true;
  }
}

}  // namespace ocg
