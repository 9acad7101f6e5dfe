#pragma once
// Local mapping: takes each new keyframe, links it into the map (observations,
// covisibility, the place-recognition database), culls recently created points that do
// not track, triangulates new points with covisible keyframes, fuses duplicates, runs
// local bundle adjustment and culls redundant keyframes.
//
// Threading: in sequential mode the tracking thread calls ProcessKeyFrame directly. In
// threaded mode Start() runs a worker that waits on a condition variable for keyframes
// given to Insert() (a bounded queue: Insert blocks while it is full); Stop() finishes
// the queue and joins. Every map access holds Map::mutex(); local bundle adjustment
// solves on a copy without it (tracking runs meanwhile) and writes back under it.
// Catching up, as ORB-SLAM2's local mapping: while more keyframes wait in the queue, a
// keyframe is linked, its points triangulated and fused, but its local adjustment and
// keyframe culling are skipped (the next keyframe's adjustment covers the same window);
// a keyframe inserted while an adjustment solves stops it after the current iteration,
// keeping the state reached. Sequentially the queue is always empty: nothing changes.

#include <atomic>
#include <functional>
#include <list>

#include "ocg/core/option_fields.h"
#include "ocg/core/statistics.h"
#include "ocg/features/bow_database.h"
#include "ocg/features/matcher.h"
#include "ocg/optim/bundle_adjustment.h"
#include "ocg/slam/keyframe_worker.h"
#include "ocg/slam/map.h"

namespace ocg {

class SettingsFile;

// LocalMapping.* settings (ORB-SLAM2's values).
struct LocalMappingOptions {
  int triangulation_neighbours = 20;  // LocalMapping.triangulationNeighbours
  double min_baseline_ratio = 0.01;   // LocalMapping.minBaselineRatio: to median depth
  double triangulation_ratio = 0.6;   // LocalMapping.triangulationRatio: BoW ratio test
  // LocalMapping.maxCosParallax: of the rays of a new point (ORB-SLAM2: 0.9998, 1.15
  // degrees). 0.99995 (0.57 degrees): a hand-held camera turning fast sees a place for a
  // few centimetres of baseline only, and at 1.15 degrees the map starved (fr1_rpy lost
  // tracking three times in 330 frames); the local adjustment refines these points.
  double max_cos_parallax = 0.99995;
  double scale_consistency = 1.5;  // LocalMapping.scaleConsistency: x scale factor
  double min_found_ratio = 0.25;   // LocalMapping.minFoundRatio: for recent points
  double fuse_radius = 3.0;        // LocalMapping.fuseRadius: pixels at level 0
  int local_ba_iterations = 5;     // LocalMapping.baIterations: robust (Huber) solve
  // LocalMapping.baRefineIterations: then without the outliers, plain squared loss
  // (BundleAdjustmentOptions::refine_iterations; 0: none)
  int local_ba_refine_iterations = 10;
  // LocalMapping.baRefineMinChi2Decrease: the refining solve also ends after an iteration
  // that lowers the chi-square by less than this
  // (BundleAdjustmentOptions::refine_min_chi2_decrease; 0: off)
  double local_ba_refine_min_chi2_decrease = 1.0;
  double redundant_ratio = 0.9;    // LocalMapping.redundantRatio: keyframe culling
  int redundant_observers = 3;     // LocalMapping.redundantObservers
  std::size_t queue_capacity = 8;  // LocalMapping.queueCapacity (threaded mode)

  // The settings keys, once (ocg/core/option_fields.h).
  template <typename Self, typename Visitor>
  static void VisitFields(Self& self, Visitor&& visit) {
    visit("LocalMapping.triangulationNeighbours", self.triangulation_neighbours,
          OptionBound::AtLeast(1), "covisible keyframes searched for new points");
    visit("LocalMapping.minBaselineRatio", self.min_baseline_ratio, OptionBound::NonNegative(),
          "baseline / median depth below which a pair is not triangulated");
    visit("LocalMapping.triangulationRatio", self.triangulation_ratio,
          OptionBound::Between(0, true, 1, false), "ratio test of the triangulation matches");
    visit("LocalMapping.maxCosParallax", self.max_cos_parallax, OptionBound::Open(0, 1),
          "rays closer than this are not triangulated");
    visit("LocalMapping.scaleConsistency", self.scale_consistency, OptionBound::AtLeast(1),
          "allowed mismatch of distance ratio and level ratio (times `scaleFactor`)");
    visit("LocalMapping.minFoundRatio", self.min_found_ratio, OptionBound::Closed(0, 1),
          "recent points found in fewer of the frames that saw them are culled");
    visit("LocalMapping.fuseRadius", self.fuse_radius, OptionBound::Positive(),
          "pixels (times scale) for fusing duplicates");
    visit("LocalMapping.baIterations", self.local_ba_iterations, OptionBound::AtLeast(1),
          "local bundle adjustment: iterations of the robust (Huber) solve");
    visit("LocalMapping.baRefineIterations", self.local_ba_refine_iterations,
          OptionBound::NonNegative(),
          "then iterations without the observations judged outliers, squared loss (0: one "
          "robust solve only; with 20 robust iterations desk_static's ATE was 1.88 mm, with "
          "5 + 10 1.55 mm)");
    visit("LocalMapping.baRefineMinChi2Decrease", self.local_ba_refine_min_chi2_decrease,
          OptionBound::NonNegative(),
          "the refining solve also ends after an iteration that lowers the chi-square (sum of "
          "squared residuals over their level's variance) by less than this: the step moved "
          "the estimate by less than one standard deviation (Mahalanobis); 0: only Ceres' "
          "relative tolerance and the iteration count end it");
    visit("LocalMapping.redundantRatio", self.redundant_ratio,
          OptionBound::Between(0, true, 1, false),
          "keyframe culling: a keyframe whose points are this share seen elsewhere is culled");
    visit("LocalMapping.redundantObservers", self.redundant_observers, OptionBound::AtLeast(1),
          "keyframe culling: ... by at least this many other keyframes");
    visit("LocalMapping.queueCapacity", self.queue_capacity, OptionBound::AtLeast(1),
          "keyframes waiting for the local mapping thread (threaded mode)");
  }
  void Check() const;
};

void ReadSettings(const SettingsFile& file, LocalMappingOptions* options);

struct LocalMappingStats {
  int keyframes = 0;
  int points_created = 0;
  int points_culled = 0;
  int points_fused = 0;
  int keyframes_culled = 0;
  // Summaries, not one number an event: a long run keeps making (and culling) keyframes.
  DurationSummary ba_seconds;      // per local bundle adjustment
  DurationSummary ba_cpu_seconds;  // the same, CPU time of this thread (load-proof)
  // Per keyframe [s]: the whole of its local mapping, and the part of it that held the
  // map lock (what tracking may have waited for; the local BA's solve runs without it).
  DurationSummary keyframe_seconds;
  DurationSummary keyframe_cpu_seconds;  // CPU time of this thread per keyframe
  DurationSummary map_lock_held_seconds;
  // Solved while a loop correction or a global adjustment moved the map, and dropped.
  int local_adjustments_dropped = 0;
  // Threaded mode: not run because more keyframes waited (keyframe culling skipped too),
  // and stopped early because a keyframe arrived while solving (applied as far as done).
  int local_adjustments_skipped = 0;
  int local_adjustments_interrupted = 0;
  std::vector<int> ba_iterations;  // per local adjustment applied: of both solves
  // Threaded mode: times local mapping released the map lock between steps because
  // tracking waited for it.
  int map_lock_yields = 0;
};

class LocalMapping {
 public:
  LocalMapping(const PinholeCamera& camera, const ScalePyramid& pyramid,
               const MatcherOptions& matcher, const LocalMappingOptions& options, Map* map,
               BowDatabase* database);
  ~LocalMapping();
  LocalMapping(const LocalMapping&) = delete;
  LocalMapping& operator=(const LocalMapping&) = delete;

  // Sequential use (any single thread).
  void ProcessKeyFrame(const KeyFramePtr& keyframe);

  // Threaded use: Start once; Insert from tracking; Stop (or the destructor) drains the
  // queue and joins. An exception in the worker is rethrown by the next Insert or Stop.
  void Start();
  // Also stops a local adjustment being solved (after its current iteration).
  void Insert(const KeyFramePtr& keyframe);
  bool Idle() const;
  void Stop();
  // Forgets recent points (after a map reset). Call with the worker idle.
  void Reset();
  // Threaded mode: called on the worker with each keyframe once it is mapped (loop
  // closing). Set before Start().
  void SetKeyFrameMapped(std::function<void(const KeyFramePtr&)> callback) {
    keyframe_mapped_ = std::move(callback);
  }

  // Called on the mapping thread, without the map lock, right before each local
  // adjustment is solved: for tests and profiling. Set before Start().
  void SetBeforeLocalSolve(std::function<void()> callback) {
    before_local_solve_ = std::move(callback);
  }
  // The same, right before new points are matched and triangulated without the lock.
  void SetBeforeTriangulation(std::function<void()> callback) {
    before_triangulation_ = std::move(callback);
  }

  LocalMappingStats Stats() const;

 private:
  void LinkKeyFrame(const KeyFramePtr& keyframe);
  void CullRecentPoints(const KeyFramePtr& keyframe);
  // A keyframe as triangulation sees it: copied under the map lock, used without it.
  struct TriangulationView {
    KeyFramePtr keyframe;  // its features and vocabulary vector, fixed once it exists
    SE3 T_cw;
    double median_depth = 0.0;    // neighbours only
    std::vector<char> has_point;  // per feature: a map point is attached
  };
  struct NewPoint {
    std::size_t view;  // index into the views: the neighbour of the pair
    int i1, i2;        // feature in the new keyframe, in the neighbour
    Eigen::Vector3d position;
  };
  static TriangulationView ViewOf(const KeyFramePtr& keyframe);
  template <typename Work>
  auto WithoutMapLock(std::unique_lock<std::mutex>& map_lock, Work&& work);
  // Takes the map lock held and gives it back held; matches and triangulates without it.
  void TriangulateNewPoints(const KeyFramePtr& keyframe, std::unique_lock<std::mutex>& map_lock);
  // views: the new keyframe first, then its neighbours. Marks the new keyframe's features
  // that it gives points to. Needs no lock.
  std::vector<NewPoint> FindNewPoints(std::vector<TriangulationView>* views) const;
  // Takes the map lock held and gives it back held; lets tracking in between targets.
  void FuseDuplicates(const KeyFramePtr& keyframe, std::unique_lock<std::mutex>& map_lock);
  // Takes the map lock held and gives it back held; releases it while Ceres solves.
  void LocalBundleAdjustment(const KeyFramePtr& keyframe, std::unique_lock<std::mutex>& map_lock);
  // Threaded mode: whether to skip the local adjustment and keyframe culling because more
  // keyframes wait; also clears a stop request left from before.
  bool CatchingUp();
  void CullKeyFrames(const KeyFramePtr& keyframe, std::unique_lock<std::mutex>& map_lock);
  // Between two steps on a keyframe: a tracker waiting for the map lock goes first
  // (Map::LetWaitingTrackerIn), so that it waits for one step, not for all of them.
  void LetTrackingIn(std::unique_lock<std::mutex>& map_lock);

  PinholeCamera camera_;
  ScalePyramid pyramid_;
  MatcherOptions matcher_;
  LocalMappingOptions options_;
  Map* map_;
  BowDatabase* database_;
  std::list<MapPointPtr> recent_points_;
  LocalMappingStats stats_;
  double unlocked_seconds_ = 0.0;  // of the keyframe being processed: work without the lock

  std::function<void(const KeyFramePtr&)> keyframe_mapped_;
  std::function<void()> before_local_solve_;
  std::function<void()> before_triangulation_;
  // Set by Insert, cleared before each local adjustment starts: stops it when set meanwhile.
  std::atomic<bool> stop_adjustment_{false};
  KeyFrameWorker worker_;  // last: stopped before the members it uses go
};

}  // namespace ocg
