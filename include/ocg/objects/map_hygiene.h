#pragma once
// Hygiene of the object map: the rules that find one object mapped twice (merge), an
// object with too little evidence (drop), and a candidate that is a map object seen again
// (join). The object map applies them (ObjectMap::MakeKeyframeObservation, AddFrame).

#include <map>
#include <optional>
#include <utility>

#include "ocg/objects/map_object.h"

namespace ocg {

// Two map objects that are one (kept first, absorbed second), the first such pair in id
// order; none when there is none. The same object mapped twice (a lost association, a box
// that jumped, a class the detector confused) shows as two objects at one place that were
// never detected in the same frame: of one class, their box rays meeting as one bundle
// (Objects.merge_rays_ratio; within Objects.merge_distance of each other when 0), of two
// classes within merge_distance; or overlapping by Objects.merge_overlap (one class), or
// one's boxes fitting the other's projection (Objects.merge_along_rays). The one with more
// sightings is kept.
std::optional<std::pair<ObjectId, ObjectId>> FindDuplicate(
    const std::map<ObjectId, MapObject>& objects, const ObjectMapContext& context);

// Whether a map object is dropped: past its probation (Objects.probation_keyframes of
// keyframes_in_map), with fewer than Objects.min_sightings sightings that are not crowded
// (crowded boxes may be the neighbour's: no evidence that this object exists).
bool TooLittleEvidence(const MapObject& object, const ObjectsOptions& options);

// The map object whose projected cuboid a candidate's untruncated boxes fit (see
// Objects.join_candidates), or null; the boxes that fit as partial views are marked
// truncated.
MapObject* HostOf(MapObject& candidate, std::map<ObjectId, MapObject>& objects,
                  const ObjectMapContext& context);

// The sightings of stand_in that are partial views of object's projected cuboid (a part
// of it, the rest hidden by something nearer) become truncated: their centres and extents
// do not tell the object's. As a joining candidate's, so an object merged into another
// does not pull its centre towards the visible part's.
void MarkPartialViews(MapObject& stand_in, const MapObject& object,
                      const ObjectMapContext& context);

}  // namespace ocg
