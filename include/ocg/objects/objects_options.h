#pragma once
// Options of the object layer (settings section Objects.*).

#include <vector>

#include <Eigen/Core>
#include "ocg/core/option_fields.h"

namespace ocg {

class SettingsFile;

struct ObjectsOptions {
  // Objects.classes: COCO-80 ids to map. Empty: every class except person (0), which
  // walks about and is never a landmark.
  std::vector<int> classes;
  // Objects.min_confidence: detections below it are ignored.
  double min_confidence = 0.4;
  // Objects.border_margin: a box within this many pixels of the image edge is truncated:
  // it still associates, but its centre and extent do not say where the object is or how
  // big it is, so it feeds neither the triangulation nor the size.
  double border_margin = 4.0;
  // Objects.nms_iou: of two boxes of one class overlapping by more than this IoU, the less
  // confident is dropped (the detector's duplicates).
  double nms_iou = 0.5;

  // Association (Hungarian, one-to-one per frame): the score of a detection for an object
  // of the same class is the mean of the available cues, each an IoU in [0, 1]: the box
  // predicted from the object's recent observations (available while the last one is at
  // most predicted_box_frames old) and the projection of its cuboid.
  double min_association_score = 0.15;  // Objects.min_association_score
  int predicted_box_frames = 5;         // Objects.predicted_box_frames
  // Objects.max_ray_distance: a detection is only associated to a map object when the ray
  // through its box centre passes within this share of the object's largest extent of the
  // object's centre.
  double max_ray_distance = 0.5;
  // Objects.min_reacquire_iou: when the predicted box is not available (the object was not
  // detected for a while), the detection must overlap the projected cuboid by this IoU.
  double min_reacquire_iou = 0.4;

  // Candidates: an unassociated detection starts one; it becomes a map object after
  // candidate_min_observations usable (untruncated) observations whose rays spread by at
  // least candidate_min_parallax_deg and meet at one point; it is dropped after
  // candidate_max_missed_frames frames without a detection.
  int candidate_min_observations = 8;       // Objects.candidate_min_observations
  double candidate_min_parallax_deg = 4.0;  // Objects.candidate_min_parallax_deg
  int candidate_max_missed_frames = 15;     // Objects.candidate_max_missed_frames
  // Objects.candidate_min_points (SLAM runs): with rays spread by less than
  // candidate_min_parallax_deg (a camera turning on the spot), an object is placed along
  // its rays at the median range of its point set when that holds this many map points.
  int candidate_min_points = 10;
  // Objects.candidate_gap_seconds: a candidate not detected for longer than
  // predicted_box_frames (no predicted box any more) still takes a box that continues its
  // track (object_geometry.h FitOfBoxToTrack: the box fits, at some depth along its rays,
  // where its boxes put the object and how big) for this many seconds after its last
  // sighting, and is kept that long (or candidate_max_missed_frames, the longer). A real
  // detector finds a hard object in one frame of ten, in runs seconds apart: each box
  // started a candidate of its own and none reached candidate_min_observations, so the
  // object was never mapped (issue 18). 0: candidates take boxes through the predicted
  // box only.
  double candidate_gap_seconds = 30.0;
  // Objects.fit_cuboid_to_edges: an object's centre is fitted to its boxes' edges
  // (object_geometry.h FitCuboidToBoxes) after the rays through their centres placed it,
  // and its extents are taken from the boxes at that centre: box centres are off the
  // object's projected centre by a share of its size that changes with the view
  // (docs/objects.md, "Edges, not centres"). False: the centre is where those rays meet.
  bool fit_cuboid_to_edges = true;

  // Objects.min_inlier_share: of a candidate's rays, the share that must meet at its centre
  // for promotion (a candidate fed by two objects of one class meets nowhere).
  double min_inlier_share = 0.75;
  // Objects.min_sightings, Objects.probation_keyframes: hygiene drops a map object with
  // fewer sightings than min_sightings once it has been in the map for probation_keyframes
  // keyframes (a burst of false detections that happened to triangulate).
  int min_sightings = 20;
  int probation_keyframes = 30;

  // Objects.max_rays: the rays used to triangulate an object's centre (evenly thinned
  // beyond this, so an object's cost stays bounded however long it is watched).
  int max_rays = 60;
  // Objects.max_sightings: the sightings an object keeps at most (SightingHistory: beyond
  // it a sample spread evenly over the run, the newest quarter whole, with exact counts),
  // so a long run that keeps revisiting an object does not grow with it. 0: keep all.
  // 4096 keeps every sighting of the presets' objects: 256 changed which moves the
  // pose-given runs pair (held-out seeds 21-25 and 31-35: 193 -> 183 of 319 right).
  int max_sightings = 4096;
  // Objects.max_object_points: the map points an object keeps at most (SLAM runs), the most
  // voted (beyond it by a quarter, the least voted are dropped), so its point set and the
  // map's changes it follows stay bounded however long it is watched. 0: keep all.
  int max_object_points = 512;

  // Objects.merge_distance: two objects never seen in the same frame whose centres are
  // closer than this share of the larger one's largest extent (of the smaller one's when
  // their classes differ: one object under two classes has one size) are one object seen
  // twice: merged. Of one class it applies only with merge_rays_ratio 0.
  double merge_distance = 0.5;
  // Objects.merge_rays_ratio: two objects of one class never seen in the same frame are one
  // object seen twice when the rays through their box centres, pooled, meet at one point
  // (Objects.min_inlier_share of each object's rays its inliers) with an RMS distance at
  // most this many times the larger of the two objects' own (map_hygiene.cc RaysMeetAsOne):
  // one object that two stretches of views triangulated apart. It replaces merge_distance
  // for one class; 0 turns it off (merge_distance again).
  double merge_rays_ratio = 1.5;
  // Objects.merge_overlap: two objects of the same class whose boxes (world-axis extents
  // of their cuboids) share more than this share of the smaller one's volume are one
  // object, even when seen in the same frame: two solid objects cannot take up the same
  // space, but a real detector puts a second, nested box on one object now and then (two
  // boxes per bottle), and each box feeds its own object. 1 turns it off.
  double merge_overlap = 0.5;
  // Objects.duplicate_box_iou: two objects detected in one frame are two objects (never
  // merged as one seen twice, nor joined) unless their boxes there overlap by this IoU or
  // more: a detector now and then puts a second box on an object (shifted, rescaled, its
  // IoU with the first below Objects.nms_iou, so both are kept), the second box feeds or
  // starts another object, and that one frame kept the two apart for good (a cup mapped as
  // two objects 7 cm apart, issue 18). 1 turns it off (only identical boxes).
  double duplicate_box_iou = 0.3;
  // Objects.seen_together_frames: two objects are "seen together" (never merged as one seen
  // twice, nor joined) once detected together, with boxes that tell them apart (above), in
  // this many frames. A detector's stray second box is an event of one frame; two objects
  // side by side are detected together whenever both are found. 1: any such frame.
  int seen_together_frames = 2;
  // Objects.merge_along_rays: an object never seen in the same frame as another, whose
  // untruncated boxes fit the other's projected cuboid (IoU at least min_reacquire_iou, or,
  // of one class, partial views: box.h FitOfBox; for min_inlier_share of them) is the other
  // seen again, any class: merged. A detector that calls an object by another class for a
  // while (a persistent class flip), or finds it again after a gap, makes a second object
  // from a short stretch of views, at the depth its narrow rays happen to meet, beyond
  // merge_distance; its boxes still fit the first object where it is. An object moved away
  // (by at least its size) is seen elsewhere: its boxes there do not fit its old place.
  bool merge_along_rays = true;
  // Objects.join_candidates: before a candidate becomes a map object, it joins the map
  // object whose projected cuboid its untruncated boxes fit (IoU at least
  // min_reacquire_iou, or a partial view: inside the projection and spanning it across one
  // axis; for min_inlier_share of them), if it was never detected in the same frame as it;
  // its class or, failing that, another (a persistent class flip). A re-detection that
  // missed the re-acquire gate (the object coming out from behind another, its box
  // covering only the visible part) starts a candidate, which then keeps the track through
  // its predicted box and is triangulated from a short stretch of views at a wrong depth:
  // a second object of the class on the first one's rays. The partial views join as
  // truncated sightings (their centre and extent do not tell the object's).
  bool join_candidates = true;
  // Restore (OCG.mode "restore"): an object the OCG removed is brought back, with its id
  // and history, when within Objects.restore_window seconds of the removal a map object of
  // its class first detected after its last sighting takes up its place: their boxes
  // (world-axis extents of the cuboids) share more than Objects.restore_overlap of the
  // smaller one's volume. A detector that lost an object for a while finds it again where
  // it was; an object moved away is found elsewhere, outside its old cuboid.
  double restore_window = 60.0;
  double restore_overlap = 0.5;

  // Objects.up: the world's up direction (gravity-aligned cuboids, yaw about it). In
  // pose-given mode the given trajectory's world frame decides it.
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();

  // SLAM runs (`ocg_slam run --detections`) only. Objects.point_box_shrink: map points
  // count as inside a box when inside it shrunk by this share of its size on every side.
  // Objects.min_point_votes: a map point belongs to an object once it was inside that
  // many of its boxes; the object's point set is those points within 3 robust sigmas.
  double point_box_shrink = 0.1;
  int min_point_votes = 3;
  // OCG.mode "points": an object not detected in a keyframe is present by its points when
  // the keyframe shows at least Objects.presence_min_points of its point set and at least
  // Objects.presence_min_share of those of them that project inside the image: tracked, or
  // found by descriptor among the keypoints within Objects.presence_search_radius level-0
  // pixels (times the keypoint's level scale) of the point's projection.
  int presence_min_points = 5;
  double presence_min_share = 0.5;
  double presence_search_radius = 4.0;
  // Yaw from the map: once an object's point set has Objects.yaw_min_points points whose
  // footprint's smallest rectangle is Objects.yaw_min_elongation times longer than wide,
  // that rectangle's yaw is the cuboid's (the boxes' widths only fit the sides); rounder
  // footprints say nothing about yaw and leave it to the boxes.
  int yaw_min_points = 10;
  double yaw_min_elongation = 1.5;
  // Up from the map: the supporting plane (RANSAC on the map points) whose normal is within
  // Objects.plane_max_tilt_deg of the cameras' up; inliers within
  // Objects.plane_inlier_share of the map's robust spread; Objects.plane_iterations tries.
  double plane_max_tilt_deg = 40.0;
  double plane_inlier_share = 0.02;
  int plane_iterations = 300;
  // SLAM runs: the plane is kept from keyframe to keyframe and fitted again once this share
  // of the map's points (as many as at the last fit) were added or removed since, or when
  // the whole map moved (a loop correction, a merge); 0: at every keyframe (a fit costs
  // what the map holds: RANSAC scores at most 4,000 points, the medians read them all).
  double plane_refit_share = 0.1;
  // SLAM runs: the object layer's copy of the SLAM map follows a change only when it moves
  // things by more than this (map units): a keyframe whose camera moved less (its centre's
  // shift plus its turn in radians times one map unit of depth; a monocular map's unit is
  // about the scene's depth when tracking started) leaves its frames' poses as they were
  // given, a map point that moved less leaves its position; so the copy stays within two
  // tolerances of the map, and the many tiny moves a local bundle adjustment makes deep in
  // a revisited map re-estimate no object. 0: every change is followed.
  double follow_tolerance = 0.001;
  // Objects.reestimate_share: an object is estimated again once the inputs that changed
  // since its last estimate (new sightings, re-posed sightings, moved counted points) reach
  // this share of the sightings it was estimated from, and at least one changed. A mature object's
  // estimate then costs a bounded amount per new input (its estimate's cost grows with its inputs,
  // its estimates become rarer in proportion), so the per-keyframe cost stays flat as objects
  // gather sightings (issue 37, point 3). Changes still waiting are estimated before outputs are
  // read (ObjectMap::EstimatePending). 0: every change is estimated at once.
  double reestimate_share = 0.1;

  // Objects.keyframe_interval: pose-given mode has no SLAM keyframes; every N-th frame is
  // one (about 3 per second at 30 Hz).
  int keyframe_interval = 10;

  // Whether detections of this class are mapped.
  bool MapsClass(int class_id) const;
  // Throws OptionError naming the key.

  // The settings keys, once (ocg/core/option_fields.h).
  template <typename Self, typename Visitor>
  static void VisitFields(Self& self, Visitor&& visit) {
    const auto share = OptionBound::Between(0, true, 1, false);  // (0, 1]
    visit("Objects.classes", self.classes, OptionBound::Any(),
          "COCO-80 ids to map; empty: every class but person (0)");
    visit("Objects.min_confidence", self.min_confidence, OptionBound::Closed(0, 1),
          "detections below it are ignored");
    visit("Objects.border_margin", self.border_margin, OptionBound::NonNegative(),
          "pixels: a box this close to the image edge is truncated (associates, but gives "
          "neither centre ray nor size)");
    visit("Objects.nms_iou", self.nms_iou, share,
          "same-class boxes overlapping more than this: the less confident is dropped");
    visit("Objects.min_association_score", self.min_association_score, share,
          "least mean IoU of the cues for an association");
    visit("Objects.predicted_box_frames", self.predicted_box_frames, OptionBound::NonNegative(),
          "the predicted-box cue is used while the last sighting is at most this many frames "
          "old");
    visit("Objects.max_ray_distance", self.max_ray_distance, OptionBound::Positive(),
          "the ray through the box centre must pass within this share of the object's largest "
          "extent of its centre");
    visit("Objects.min_reacquire_iou", self.min_reacquire_iou, OptionBound::Closed(0, 1),
          "after a gap (no predicted box), the detection must overlap the projected cuboid by "
          "this IoU");
    visit("Objects.candidate_min_observations", self.candidate_min_observations,
          OptionBound::AtLeast(2).Because("a centre needs two rays"),
          "untruncated sightings a candidate needs to become a map object");
    visit("Objects.candidate_min_parallax_deg", self.candidate_min_parallax_deg,
          OptionBound::Between(0, false, 90, true), "spread of its rays, degrees");
    visit("Objects.candidate_min_points", self.candidate_min_points, OptionBound::AtLeast(1),
          "SLAM runs: a candidate (or object) whose rays spread by less than "
          "`Objects.candidate_min_parallax_deg` (a camera turning on the spot) is placed along "
          "its rays at the median range of its map points when it has this many "
          "([objects.md](objects.md)); with fewer it waits for parallax");
    visit("Objects.candidate_max_missed_frames", self.candidate_max_missed_frames,
          OptionBound::AtLeast(1),
          "a candidate not detected for this many frames is dropped (but see the next key)");
    visit("Objects.candidate_gap_seconds", self.candidate_gap_seconds, OptionBound::NonNegative(),
          "a candidate whose predicted box is gone (older than `Objects.predicted_box_frames`) "
          "still takes an unassociated box that continues its track (at some depth on its rays "
          "its boxes' object projects onto it, IoU >= `Objects.min_reacquire_iou`, seen from "
          "within `Objects.candidate_min_parallax_deg` of one of its views or its own spread of "
          "views) for this many seconds after its last box, and is kept that long; kept "
          "candidates whose boxes fit a map object's projection join it at the next keyframe. 0: "
          "the rule before it (predicted box only, dropped after "
          "`Objects.candidate_max_missed_frames`)");
    visit("Objects.fit_cuboid_to_edges", self.fit_cuboid_to_edges, OptionBound::Any(),
          "an object's centre is fitted to its boxes' edges after the rays through their "
          "centres placed it, its extents taken from the boxes there (box centres are off the "
          "object's projected centre by a share of its size that changes with the view; "
          "objects.md, \"Edges, not centres\"). false: the centre is where those rays meet");
    visit("Objects.min_inlier_share", self.min_inlier_share, share,
          "share of a candidate's rays that must meet at its centre");
    visit("Objects.min_sightings", self.min_sightings, OptionBound::NonNegative(),
          "a map object with fewer sightings after `Objects.probation_keyframes` keyframes is "
          "dropped (hygiene); sightings whose box shares area with a more confident box of its "
          "class do not count (objects.md)");
    visit("Objects.probation_keyframes", self.probation_keyframes, OptionBound::NonNegative(),
          "keyframes after which `min_sightings` applies");
    visit("Objects.max_rays", self.max_rays, OptionBound::AtLeast(2),
          "rays used per triangulation (evenly thinned beyond; at least "
          "`candidate_min_observations`)");
    visit("Objects.max_sightings", self.max_sightings, OptionBound::NonNegative(),
          "sightings an object keeps at most (0 keeps all, else at least `Objects.max_rays` and "
          "8); beyond it the first, the newest quarter and a sample spread evenly over the run "
          "(the same frames for every object), with exact counts (observations, classes, "
          "sessions, first and last seen), so memory stays bounded on a long run that keeps "
          "revisiting it ([robustness.md](robustness.md) \"Long runs\")");
    visit("Objects.max_object_points", self.max_object_points, OptionBound::NonNegative(),
          "SLAM runs: map points an object keeps at most, the most voted (0 keeps all), so its "
          "cost per keyframe stays bounded on a long run");
    visit("Objects.merge_distance", self.merge_distance, OptionBound::NonNegative(),
          "two objects never seen in the same frame, closer than this share of the larger one's "
          "largest extent (of the smaller one's when their classes differ: one object under two "
          "classes has one size), are merged (the majority class wins); of one class only with "
          "`Objects.merge_rays_ratio` 0");
    visit("Objects.merge_rays_ratio", self.merge_rays_ratio, OptionBound::NonNegative(),
          "two objects of one class never seen in the same frame are merged when the rays "
          "through their box centres, pooled, meet at one point (`Objects.min_inlier_share` of "
          "each one's rays its inliers) with an RMS distance at most this many times the larger "
          "of the two objects' own: one object two stretches of views triangulated apart; it "
          "replaces `Objects.merge_distance` for one class; 0 turns it off");
    visit("Objects.merge_overlap", self.merge_overlap, share,
          "two objects of one class whose boxes (world-axis extents) share more than this share "
          "of the smaller one's volume are merged even when seen in the same frame (a detector's "
          "nested double boxes); 1 turns it off");
    visit("Objects.duplicate_box_iou", self.duplicate_box_iou, share,
          "two objects detected in one frame count as \"seen together\" (never merged as one "
          "object seen twice, nor joined) only when their boxes there overlap by less than this "
          "IoU: a detector's second box on an object (IoU below `Objects.nms_iou`, so both kept) "
          "feeds another object, and that frame kept the two apart for good; 1 turns it off");
    visit("Objects.seen_together_frames", self.seen_together_frames, OptionBound::AtLeast(1),
          "two objects are \"seen together\" (never merged as one object seen twice, nor "
          "joined) once detected together, with boxes that tell them apart, in this many "
          "frames: a stray second box is an event of one frame, two objects side by side are "
          "detected together whenever both are found; 1: any such frame");
    visit("Objects.merge_along_rays", self.merge_along_rays, OptionBound::Any(),
          "an object never seen in the same frame as another, whose boxes fit the other's "
          "projected cuboid (IoU >= `Objects.min_reacquire_iou`, or of one class a partial view: "
          "inside it and spanning it across one axis; for `Objects.min_inlier_share` of them) is "
          "merged into it, any class (a persistent class flip, a stand-in triangulated at the "
          "wrong depth)");
    visit("Objects.join_candidates", self.join_candidates, OptionBound::Any(),
          "before a candidate becomes a map object, it joins the map object (never detected in "
          "the same frame) whose projected cuboid its boxes fit as above: a re-detection that "
          "missed the re-acquire gate (a partly hidden object, a class flip) is that object, not "
          "a new one on its rays; the partial views join as truncated sightings");
    visit("Objects.restore_window", self.restore_window, OptionBound::NonNegative(),
          "`OCG.mode` `restore`: an object the OCG removed comes back (its id, history, edges) "
          "when within this many seconds of the removal a map object of its class, first "
          "detected after its last sighting, takes up its place (`Objects.restore_overlap`)");
    visit("Objects.restore_overlap", self.restore_overlap, share,
          "`OCG.mode` `restore`: ... their boxes (world-axis extents) share more than this share "
          "of the smaller one's volume");
    visit("Objects.up", self.up, OptionBound::Any(),
          "pose-given mode: the world's up direction (gravity-aligned cuboids); SLAM runs find "
          "it from the map");
    visit("Objects.point_box_shrink", self.point_box_shrink,
          OptionBound::Between(0, false, 0.5, true),
          "SLAM runs: map points count as inside a box shrunk by this share of its size on "
          "every side");
    visit("Objects.min_point_votes", self.min_point_votes, OptionBound::AtLeast(1),
          "SLAM runs: boxes a map point must have been inside to belong to the object");
    visit("Objects.presence_min_points", self.presence_min_points, OptionBound::AtLeast(1),
          "`OCG.mode` `points` (SLAM runs): an object not detected in a keyframe is present by "
          "its points when the keyframe's frame shows at least this many of its point set "
          "(tracked, or found by descriptor near their projections) "
          "([ocg.md](ocg.md#modes-ocgmode))");
    visit("Objects.presence_min_share", self.presence_min_share, share,
          "`OCG.mode` `points`: ... and at least this share of those of its points that project "
          "into the image");
    visit("Objects.presence_search_radius", self.presence_search_radius, OptionBound::Positive(),
          "`OCG.mode` `points` (SLAM runs): an object point is searched among the keyframe's "
          "keypoints within this many pixels of its projection");
    visit("Objects.yaw_min_points", self.yaw_min_points, OptionBound::AtLeast(3),
          "SLAM runs: an object's yaw comes from its point set's smallest footprint rectangle "
          "once the set has this many points");
    visit("Objects.yaw_min_elongation", self.yaw_min_elongation, OptionBound::AtLeast(1),
          "... and the rectangle is this many times longer than wide (rounder footprints "
          "leave yaw to the boxes)");
    visit("Objects.plane_max_tilt_deg", self.plane_max_tilt_deg, OptionBound::Open(0, 90),
          "SLAM runs: the supporting plane's normal is within this angle of the cameras' up");
    visit("Objects.plane_inlier_share", self.plane_inlier_share, OptionBound::Positive(),
          "SLAM runs: plane inliers lie within this share of the map's robust spread");
    visit("Objects.plane_iterations", self.plane_iterations, OptionBound::AtLeast(1),
          "SLAM runs: RANSAC hypotheses (seeded from `System.seed`)");
    visit("Objects.plane_refit_share", self.plane_refit_share, OptionBound::NonNegative(),
          "SLAM runs: the plane is fitted again once this share of the map's points were "
          "added or removed since the last fit (or the whole map moved); 0: every keyframe");
    visit("Objects.reestimate_share", self.reestimate_share, OptionBound::Closed(0, 1),
          "an object is estimated again once the inputs changed since its last estimate (new "
          "or re-posed sightings, moved points) reach this share of the sightings it was "
          "estimated from; 0: at every change");
    visit("Objects.follow_tolerance", self.follow_tolerance, OptionBound::NonNegative(),
          "SLAM runs: keyframes whose camera moved less than this (centre shift plus turn in "
          "radians times one map unit) and map points that moved less leave the object "
          "layer's copy as it was (map units); 0: every change is followed");
    visit("Objects.keyframe_interval", self.keyframe_interval, OptionBound::AtLeast(1),
          "every N-th (tracked) frame is a keyframe for the OCG");
  }
  void Check() const;
};

void ReadSettings(const SettingsFile& file, ObjectsOptions* options);

}  // namespace ocg
