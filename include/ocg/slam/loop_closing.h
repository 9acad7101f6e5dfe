#pragma once
// Loop closing: recognizes a place seen long ago (BoW database, candidates consistent
// over consecutive keyframes), estimates the similarity between now and then (Sim(3):
// scale drifts in monocular maps), corrects the current keyframe's neighbourhood, fuses
// the duplicated points, optimizes the essential graph as a Sim(3) pose graph and runs a
// global bundle adjustment.
//
// Threading: in sequential mode the caller runs ProcessKeyFrame on each keyframe local
// mapping has finished, and the global bundle adjustment runs inside it. In threaded mode
// Start() runs a worker fed by Insert() (called by the local mapping thread; a bounded
// queue), Stop() drains it and joins it and the global adjustment, and Stats() is for
// after Stop(). ProcessKeyFrame takes Map::mapping_mutex() (local mapping waits for
// recognition and correction) and reads the map without Map::mutex(); it takes
// Map::mutex() only for the steps of a correction that change the map, and lets a
// waiting tracker in between them, so tracking waits milliseconds, not the correction.
// The global adjustment then runs on a thread of its own without the locks, on a copy of
// the map's keyframes and points, and is merged back under both: what was added
// meanwhile follows the correction of what it hangs from (ApplyAdjustment). No loop is
// looked for while a global adjustment runs.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <optional>
#include <set>
#include <thread>
#include <vector>

#include "ocg/core/option_fields.h"
#include "ocg/features/bow_database.h"
#include "ocg/features/matcher.h"
#include "ocg/features/scale_pyramid.h"
#include "ocg/optim/sim3_estimation.h"
#include "ocg/slam/keyframe_worker.h"
#include "ocg/slam/map.h"

namespace ocg {

class SettingsFile;
struct KeyFrameAdjustment;

// LoopClosing.* settings.
struct LoopClosingOptions {
  bool enabled = true;               // LoopClosing.enabled (merges of maps too)
  bool merge_maps = true;            // LoopClosing.mergeMaps: another map's place merges it
  int min_keyframes_between = 10;    // LoopClosing.minKeyFramesBetween: after the map's start
                                     // and after the last loop
  int min_loop_age = 30;             // LoopClosing.minLoopAge: keyframes between a place
                                     // and its recognition (a moment ago is no loop)
  int consistency = 3;               // LoopClosing.consistency: consecutive keyframes
  int max_candidates = 8;            // LoopClosing.maxCandidates: per keyframe
  int min_bow_matches = 20;          // LoopClosing.minBowMatches
  int min_loop_matches = 40;         // LoopClosing.minLoopMatches: after guided matching
  double loop_search_radius = 10.0;  // LoopClosing.searchRadius: pixels at level 0
  int strong_covisibility = 100;     // LoopClosing.strongCovisibility: essential-graph edges
  int pose_graph_iterations = 20;    // LoopClosing.poseGraphIterations
  int global_ba_iterations = 10;     // LoopClosing.globalBAIterations (0: none)
  std::size_t queue_capacity = 8;    // LoopClosing.queueCapacity (threaded mode)
  Sim3EstimationOptions sim3;        // LoopClosing.sim3* keys

  // The settings keys, once (ocg/core/option_fields.h).
  template <typename Self, typename Visitor>
  static void VisitFields(Self& self, Visitor&& visit) {
    visit("LoopClosing.enabled", self.enabled, OptionBound::Any(),
          "recognize revisited places and correct the map");
    visit("LoopClosing.mergeMaps", self.merge_maps, OptionBound::Any(),
          "a keyframe that recognizes another map's place (as a loop is recognized) merges its "
          "map into that one by the Sim(3) between them ([slam.md](slam.md) \"the atlas\"); "
          "false: maps stay apart (relocalization still tries every map)");
    visit("LoopClosing.minKeyFramesBetween", self.min_keyframes_between, OptionBound::NonNegative(),
          "no loop in the map's first keyframes nor within this many keyframes of the last "
          "loop");
    visit("LoopClosing.minLoopAge", self.min_loop_age, OptionBound::AtLeast(1),
          "keyframes between a place and its recognition (a moment ago is no loop)");
    visit("LoopClosing.consistency", self.consistency, OptionBound::NonNegative(),
          "consecutive keyframes whose candidates must overlap (a candidate and its covisible "
          "keyframes)");
    visit("LoopClosing.maxCandidates", self.max_candidates, OptionBound::AtLeast(1),
          "database candidates per keyframe at most");
    visit("LoopClosing.minBowMatches", self.min_bow_matches, OptionBound::AtLeast(3),
          "BoW matches of distinct points before Sim(3) estimation");
    visit("LoopClosing.minLoopMatches", self.min_loop_matches, OptionBound::AtLeast(3),
          "matches after guided search through the similarity: fewer, no loop (at least "
          "`sim3MinInliers`)");
    visit("LoopClosing.searchRadius", self.loop_search_radius, OptionBound::Positive(),
          "pixels (times scale) of the guided search");
    visit("LoopClosing.strongCovisibility", self.strong_covisibility, OptionBound::AtLeast(1),
          "shared points that make a covisibility edge part of the essential graph");
    visit("LoopClosing.poseGraphIterations", self.pose_graph_iterations, OptionBound::AtLeast(1),
          "Sim(3) pose graph iterations");
    visit("LoopClosing.globalBAIterations", self.global_ba_iterations, OptionBound::NonNegative(),
          "global bundle adjustment after a loop (0: none)");
    visit("LoopClosing.queueCapacity", self.queue_capacity, OptionBound::AtLeast(1),
          "keyframes waiting for the loop closing thread (threaded mode)");
    Sim3EstimationOptions::VisitFields(self.sim3, visit);
  }
  void Check() const;
};

void ReadSettings(const SettingsFile& file, LoopClosingOptions* options);

struct LoopEvent {
  KeyFrameId keyframe = 0;  // the current keyframe
  KeyFrameId matched = 0;   // the keyframe of the place seen before
  double timestamp = 0.0;
  int sim3_inliers = 0;
  int loop_matches = 0;     // after guided matching
  double scale = 1.0;       // the correction's scale (1: no scale drift)
  double correction = 0.0;  // how far the current keyframe moved, map units
  int points_fused = 0;
  double seconds = 0.0;  // from recognition to the correction's end (global BA not included)
  // Of seconds, the time the correction held Map::mutex() (tracking may wait for it), in
  // total and the longest stretch at once.
  double map_lock_held_seconds = 0.0;
  double map_lock_longest_hold_seconds = 0.0;
  // A merge of maps (LoopClosingStats::merges): the map the current keyframe was in,
  // moved into into_map when the keyframe of frame `frame` (Tracking's frame id)
  // recognized into_map's place; `scale` is then the similarity's scale, into_map's units
  // per unit of the moved map. -1 for a loop.
  int merged_map = -1;
  int into_map = -1;
  std::uint64_t frame = 0;
};

struct LoopClosingStats {
  int candidates_checked = 0;  // consistent candidates that reached Sim(3) estimation
  std::vector<LoopEvent> loops;
  std::vector<LoopEvent> merges;  // a map recognized the place of another and merged into it
  int global_adjustments = 0;     // merged into the map
  double global_adjustment_seconds = 0.0;
  // Keyframes and points added while a global adjustment ran, that followed it.
  int followed_global_adjustment = 0;
};

class LoopClosing {
 public:
  // seed: the Sim(3) RANSAC's seed (from System.seed).
  LoopClosing(const PinholeCamera& camera, const ScalePyramid& pyramid,
              const MatcherOptions& matcher, const LoopClosingOptions& options, Map* map,
              BowDatabase* database, std::uint64_t seed);

  ~LoopClosing();
  LoopClosing(const LoopClosing&) = delete;
  LoopClosing& operator=(const LoopClosing&) = delete;

  // True when this keyframe closed a loop (the map has been corrected).
  bool ProcessKeyFrame(const KeyFramePtr& keyframe);
  // Threaded use (see above).
  void Start();
  void Insert(const KeyFramePtr& keyframe) { worker_.Insert(keyframe); }
  bool Idle() const { return worker_.Idle() && !global_adjustment_running_; }
  void Stop();
  // Forgets the consistency history (after a map reset).
  void Reset();
  // Recognition alone: whether keyframe (of this map or any other) shows the place of one
  // of candidates (this map's), verified as a loop is (BoW matches, Sim(3) RANSAC, guided
  // matching, the thresholds of LoopClosingOptions), without the consistency check and
  // without changing the map. For tests and diagnostics; takes Map::mutex().
  std::optional<LoopEvent> Recognize(const KeyFramePtr& keyframe,
                                     const std::vector<KeyFramePtr>& candidates);
  const LoopClosingStats& Stats() const { return stats_; }

 private:
  struct Loop;
  class MapLock;
  struct ConsistentGroup {
    std::set<KeyFrameId> keyframes;
    int consistency = 0;
  };
  std::vector<KeyFramePtr> DetectCandidates(const KeyFramePtr& keyframe);
  bool ComputeSim3(const KeyFramePtr& keyframe, const std::vector<KeyFramePtr>& candidates,
                   Loop* loop);
  // The event's fields known before the correction.
  static LoopEvent Describe(const KeyFramePtr& keyframe, const Loop& loop);
  // Returns the number of points fused. Holds Map::mapping_mutex(); takes map_lock (not
  // held on entry nor on return) only for the steps that change the map.
  int Correct(const KeyFramePtr& keyframe, Loop& loop, MapLock& map_lock);
  // Global bundle adjustment after a correction (Map::mapping_mutex() held, map_lock not):
  // in place in sequential mode, else started on global_adjustment_thread_.
  void AdjustGlobally(int map, MapLock& map_lock);
  // Solves without the map lock; false (warned) when Ceres found no usable solution.
  bool SolveGlobally(KeyFrameAdjustment& adjustment) const;
  // Writes a solved global adjustment into the map (lock held) and counts it.
  void MergeGlobalAdjustment(const KeyFrameAdjustment& adjustment,
                             std::chrono::steady_clock::time_point start);
  void JoinGlobalAdjustment();

  PinholeCamera camera_;
  ScalePyramid pyramid_;
  MatcherOptions matcher_;
  LoopClosingOptions options_;
  Map* map_;
  BowDatabase* database_;
  std::uint64_t seed_;
  std::vector<ConsistentGroup> groups_;
  KeyFrameId last_loop_keyframe_ = 0;
  LoopClosingStats stats_;
  bool threaded_ = false;
  std::thread global_adjustment_thread_;
  std::atomic<bool> global_adjustment_running_{false};
  KeyFrameWorker worker_;  // last: stopped before the members it uses go
};

}  // namespace ocg
