#pragma once
// One map object (or candidate) and what every part of the object map does with one: its
// point set, its estimate from its sightings, another record of it absorbed, its entry in
// the change log. The object map (object_map.h) holds them; its parts (association,
// candidates, hygiene, restore, evidence) work on them.

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "ocg/core/camera.h"
#include "ocg/core/lie.h"
#include "ocg/features/descriptor.h"
#include "ocg/objects/box.h"
#include "ocg/objects/colour_signature.h"
#include "ocg/objects/map_cues.h"
#include "ocg/objects/object_change.h"
#include "ocg/objects/object_points.h"
#include "ocg/objects/objects_options.h"
#include "ocg/objects/sighting_history.h"
#include "ocg/ocg/observation.h"

namespace ocg {

// A map object, or a candidate (id < 0) not yet triangulated.
struct MapObject {
  ObjectId id = 0;
  int class_id = 0;  // the most frequent class of its sightings
  // In frame order; beyond Objects.max_sightings a bounded sample with exact counts.
  SightingHistory sightings;
  Cuboid cuboid;
  bool has_cuboid = false;
  bool yaw_from_points = false;  // else from the boxes' widths
  std::int64_t first_frame = 0;
  std::int64_t last_frame = 0;
  double first_timestamp = 0.0;
  double last_timestamp = 0.0;
  std::int64_t keyframes_in_map = 0;  // keyframes since promotion
  ObjectPoints points;                // by SLAM map point id
  // Objects.reestimate_share: the inputs changed since the last estimate and the sightings
  // that estimate had (ObjectMap; map files keep them from version 6 on).
  int changes_since_estimate = 0;
  std::size_t sightings_at_estimate = 0;
};

// What every part of the object map reads of it: its options, its camera and its gravity
// frame (R_wg: the cuboids' up). References into the map: valid while it is unchanged.
struct ObjectMapContext {
  const ObjectsOptions& options;
  const PinholeCamera& camera;
  const Eigen::Matrix3d& R_wg;
};

// The object's point set: its map points with at least min_votes votes, within its largest
// extent of its centre once it has a cuboid, and within 3 robust sigmas of their median
// (the background caught in its boxes left out).
std::vector<Eigen::Vector3d> ObjectPointSet(const MapObject& object, int min_votes);
// The same points' ids (SLAM map point ids), in id order.
std::vector<std::uint64_t> ObjectPointIds(const MapObject& object, int min_votes);
// Both, with the set's robust bounds (3 robust sigmas), kept by the object's points until
// they or its cuboid change: valid until then.
const ObjectPoints::PointSet& PointSetOf(const MapObject& object, int min_votes);
// The object's appearance: the descriptors of its point set (points without one left
// out). An object keeps its texture when it is carried elsewhere, so the points of its new
// place match these far better than those of another object of its class.
std::vector<Descriptor> ObjectAppearance(const MapObject& object, int min_votes);

// Re-estimates centre and cuboid from the sightings (yaw from the point set when it tells
// one); false when they do not meet. A candidate triangulates from its uncrowded boxes
// alone, and must meet Objects.candidate_min_observations and candidate_min_parallax_deg.
bool Reestimate(MapObject& object, bool candidate, const ObjectMapContext& context);

// Another record of the same object, from: its sightings (in frame order) and point votes
// join into's, whose class becomes its sightings' majority. Geometry is left to the caller.
// max_sightings: Objects.max_sightings.
void Absorb(MapObject& into, const MapObject& from, int max_sightings);
// A vote of the object for each point in its box, which takes the point's position.
void AddPointVotes(MapObject& object, const std::vector<const PointObservation*>& box_points);
// Keeps the object's max_points most voted points (Objects.max_object_points; 0 keeps all),
// pruned once it holds a quarter more, so its point set's cost stays bounded however long
// it is watched.
void BoundPoints(MapObject& object, int max_points);
// Every n-th index of count so that at most limit remain, first and last kept.
std::vector<std::size_t> Thinned(std::size_t count, std::size_t limit);

// The cuboid's extent along the world axes.
Eigen::Vector3d WorldExtent(const Cuboid& cuboid, const Eigen::Matrix3d& R_wg);
// The share of the smaller box's volume inside the other (world-axis boxes from centre and
// extent); 0 when either is flat.
double OverlapShare(const Eigen::Vector3d& centre_a, const Eigen::Vector3d& extent_a,
                    const Eigen::Vector3d& centre_b, const Eigen::Vector3d& extent_b);
// Whether a and b were detected together, with boxes that tell two objects apart, in at
// least min_frames frames (Objects.seen_together_frames). Boxes overlapping by
// duplicate_box_iou or more (the detector's second box on one object, which the
// non-maximum suppression let through) do not: each fed its own object, and one such
// frame kept the object's two halves apart for good. Nor does one frame alone: a stray
// second box is an event of one frame, two objects side by side are detected together
// whenever the detector finds both.
bool SeenTogether(const MapObject& a, const MapObject& b, double duplicate_box_iou, int min_frames);
// Whether one session saw both.
bool SeenInOneSession(const MapObject& a, const MapObject& b);

// A change-log entry of the object as it is now.
ObjectChange ChangeOf(const char* type, std::int64_t keyframe_id, double timestamp,
                      const MapObject& object, int session);

}  // namespace ocg
