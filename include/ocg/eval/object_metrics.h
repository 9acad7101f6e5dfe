#pragma once
// Object-map metrics of the paper's Table I, computed (SPEC 4): ground-truth places
// (static, and the outdated places moved objects left) against the run's objects (live at
// the end, or removed on the way).

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "ocg/core/lie.h"

namespace ocg {

struct GroundTruthPlace {
  int object_id = 0;  // of the ground-truth object
  int class_id = 0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double radius = 0.0;  // matching distance: distance_factor x largest extent
};

struct ObjectGroundTruth {
  std::vector<GroundTruthPlace> static_places;    // where objects are at the end
  std::vector<GroundTruthPlace> outdated_places;  // where moved objects were before
  // Static places the sequence never shows (left out of static_places; see
  // ObjectMatchOptions::include_never_in_view): ignored, as benchmarks ignore regions no
  // one can label. A live object near one is neither Corr.S nor Redun.S.
  std::vector<GroundTruthPlace> never_in_view_places;
};

struct ObjectMatchOptions {
  // Matching distance = max(distance_factor x the larger GT extent, min_distance).
  double distance_factor = 0.5;
  double min_distance = 0.0;
  // false: a static place whose placement has "frames_in_view": 0 (the generator's count of
  // frames showing it at the detector's least visible size) is not ground truth, as a list
  // made from the frames would not hold it. true: every placed object counts.
  bool include_never_in_view = false;
};

// The generator's objects_gt.json: per object class_id, size and its history of
// placements; the last present placement is a static place, every earlier one an
// outdated place. A placement without "frames_in_view" (older files) counts as in view.
// Throws ParseError naming the file and what is wrong (for a "frames_in_view" that is not
// a non-negative integer, the object's id).
ObjectGroundTruth ReadObjectGroundTruth(const std::string& path,
                                        const ObjectMatchOptions& options = {});

struct RunObject {
  long long id = 0;
  int class_id = 0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  bool live = false;  // in the final map (else removed by change detection)
  // A "moved" entry of changes.json: where the object reappeared (its "to" cuboid's centre).
  std::optional<Eigen::Vector3d> moved_to;
};

// A run folder's objects.json (live) and changes.json ("removed" and "moved" entries; merged
// duplicates are part of the object they joined). Throws FileError / ParseError.
std::vector<RunObject> ReadRunObjects(const std::string& run_dir);

struct ObjectMetrics {
  int corr_s = 0, unident_s = 0, redun_s = 0, corr_m = 0, delet_s = 0, unident_m = 0;
  int redun_duplicates = 0, redun_spurious = 0;  // the two parts of redun_s
  int gt_static = 0, gt_outdated = 0;
  int gt_never_in_view = 0;  // static places left out: never in view in the sequence
  int live_objects = 0, removed_objects = 0;
  // Moves reported right: of the gt_moves ground-truth objects that left a place for
  // another one, those with a "moved" entry from the old place (near it) to the new one
  // (near its static place).
  int gt_moves = 0, moves_right = 0;
  double acc = 0.0, prec = 0.0, recall = 0.0;
  // Per place / object, for reading a result: the ids behind each count.
  std::vector<int> deleted_static_ids, unidentified_static_ids, unidentified_moved_ids;
  std::vector<int> never_in_view_ids;
  // Live objects near a place never in view: ignored (neither Corr.S nor Redun.S).
  std::vector<long long> never_in_view_object_ids;
  std::vector<long long> duplicate_ids, spurious_ids;
};

// Acc, Prec and Recall of SPEC 4 from the six counts (0 when a denominator is 0).
void ComputeRatios(ObjectMetrics* metrics);

// The counts of SPEC 4. Objects must already be in the ground truth's frame.
ObjectMetrics ComputeObjectMetrics(const ObjectGroundTruth& truth,
                                   const std::vector<RunObject>& objects);

// Moves objects into the ground truth's frame: world_from_run applied to every centre.
void TransformObjects(const Sim3& world_from_run, std::vector<RunObject>* objects);

// How a run in its own frame and scale was brought into the ground truth's.
struct RunAlignment {
  std::string trajectory;  // the run's trajectory file that was aligned
  std::size_t pairs = 0;
  double scale = 1.0;
  double ate_rmse = 0.0;  // metres
};

// `ocg_eval objects` for one run folder: the ground truth (objects_gt.json) against the
// run's objects. With a ground-truth trajectory (TUM, camera-to-world) the run's
// KeyFrameTrajectory.txt (else CameraTrajectory.txt) is aligned to it (Sim(3)) and the
// objects moved with it, and *alignment says how; without one the run is taken to be in
// the ground truth's frame. Throws FileError / ParseError naming the file, and
// std::invalid_argument when the trajectories do not align (fewer than 3 pairs).
ObjectMetrics EvaluateRunObjects(const std::string& objects_gt_path, const std::string& run_dir,
                                 const std::string& groundtruth_path,
                                 const ObjectMatchOptions& options,
                                 std::optional<RunAlignment>* alignment = nullptr);

}  // namespace ocg
