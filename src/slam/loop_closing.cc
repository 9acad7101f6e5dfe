#include "ocg/slam/loop_closing.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <map>

#include "ocg/core/options.h"
#include "ocg/core/settings_file.h"
#include "ocg/core/thread_name.h"
#include "ocg/optim/pose_graph.h"
#include "ocg/slam/map_operations.h"

namespace ocg {
namespace {

SE3 ToSE3(const Sim3& S) { return SE3(S.rotation(), S.translation() / S.scale()); }

// Keyframes of another map matched against a keyframe that may show their place: the
// candidate and its best covisible ones (ORB-SLAM3 matches merges in such a window).
constexpr std::size_t kMergeWindow = 6;

}  // namespace

void LoopClosingOptions::Check() const {
  CheckOptionFields(*this);
  RequireOption(min_loop_matches >= sim3.min_inliers, "LoopClosing.minLoopMatches",
                "must be at least LoopClosing.sim3MinInliers");
}

void ReadSettings(const SettingsFile& file, LoopClosingOptions* options) {
  ReadOptionFields(file, options);
}

// The map lock of a loop correction, taken and given back between its steps, with how
// long it was held: what tracking may have waited for.
class LoopClosing::MapLock {
 public:
  explicit MapLock(std::mutex& mutex) : lock_(mutex, std::defer_lock) {}
  void Lock() {
    lock_.lock();
    locked_at_ = std::chrono::steady_clock::now();
  }
  void Unlock() {
    CountHold();
    lock_.unlock();
  }
  // Between two steps of the correction, each of which leaves the map whole.
  void LetWaitingTrackerIn(const Map& map) {
    if (!map.TrackerWaiting()) return;
    CountHold();
    map.LetWaitingTrackerIn(lock_);
    locked_at_ = std::chrono::steady_clock::now();
  }
  double held_seconds = 0.0;
  double longest_hold_seconds = 0.0;

 private:
  void CountHold() {
    const double held =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - locked_at_).count();
    held_seconds += held;
    longest_hold_seconds = std::max(longest_hold_seconds, held);
  }
  std::unique_lock<std::mutex> lock_;
  std::chrono::steady_clock::time_point locked_at_;
};

// A recognized place: the matched keyframe, the current keyframe's pose in the matched
// place's frame, and the loop points it sees.
struct LoopClosing::Loop {
  KeyFramePtr matched;
  Sim3 S_cw;
  std::vector<MapPointPtr> matched_points;  // per feature of the current keyframe
  std::vector<MapPointPtr> loop_points;     // of the matched keyframe and its neighbours
  int sim3_inliers = 0;
  int loop_matches = 0;
};

LoopClosing::LoopClosing(const PinholeCamera& camera, const ScalePyramid& pyramid,
                         const MatcherOptions& matcher, const LoopClosingOptions& options, Map* map,
                         BowDatabase* database, std::uint64_t seed)
    : camera_(camera),
      pyramid_(pyramid),
      matcher_(matcher),
      options_(options),
      map_(map),
      database_(database),
      seed_(seed),
      worker_(
          options.queue_capacity,
          [this](const KeyFramePtr& keyframe) { ProcessKeyFrame(keyframe); }, "loop_closing") {
  options_.Check();
}

LoopClosing::~LoopClosing() {
  try {
    worker_.Stop();
  } catch (...) {
    // Reported by an explicit Stop(); a destructor must not throw.
  }
  JoinGlobalAdjustment();
}

void LoopClosing::Start() {
  threaded_ = true;
  worker_.Start();
}

void LoopClosing::Stop() {
  worker_.Stop();
  JoinGlobalAdjustment();
}

void LoopClosing::JoinGlobalAdjustment() {
  if (global_adjustment_thread_.joinable()) global_adjustment_thread_.join();
}

void LoopClosing::Reset() {
  groups_.clear();
  last_loop_keyframe_ = 0;
}

bool LoopClosing::ProcessKeyFrame(const KeyFramePtr& keyframe) {
  if (!options_.enabled || global_adjustment_running_) return false;
  JoinGlobalAdjustment();  // a finished one
  const auto start = std::chrono::steady_clock::now();
  // Recognition only reads the map: with local mapping kept out, tracking (a reader too)
  // goes on meanwhile.
  const std::lock_guard<std::mutex> mapping(map_->mapping_mutex());
  if (keyframe->bad) return false;
  const std::vector<KeyFramePtr> candidates = DetectCandidates(keyframe);
  if (candidates.empty()) return false;
  Loop loop;
  if (!ComputeSim3(keyframe, candidates, &loop)) return false;
  LoopEvent event = Describe(keyframe, loop);
  MapLock map_lock(map_->mutex());
  const bool merge = loop.matched->map != keyframe->map;
  if (merge) {
    // Another map holds this place: the current map (all its keyframes and points) moves
    // into that map's frame by the similarity between them, and becomes part of it. The
    // correction below is then a loop closure of the merged map with nothing left to
    // move at the current keyframe: it fuses the points seen twice, welds the
    // covisibility graph across the seam, and optimizes the merged map's pose graph.
    event.merged_map = keyframe->map;
    event.into_map = loop.matched->map;
    event.frame = keyframe->frame_id;
    map_lock.Lock();
    const Sim3 S_into_from = loop.S_cw.Inverse() * Sim3(keyframe->T_cw);
    event.scale = S_into_from.scale();
    map_->MoveMap(keyframe->map, loop.matched->map, S_into_from);
    map_->CountCorrection();
    loop.S_cw = Sim3(keyframe->T_cw);
    map_lock.Unlock();
  }
  event.points_fused = Correct(keyframe, loop, map_lock);
  event.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  event.map_lock_held_seconds = map_lock.held_seconds;
  event.map_lock_longest_hold_seconds = map_lock.longest_hold_seconds;
  spdlog::info(
      "{}: keyframe {} sees keyframe {} again ({} Sim(3) inliers, {} matches, "
      "scale {:.3f}, moved {:.3f}) in {:.2f} s, the map locked {:.1f} ms of it (at most {:.1f} "
      "ms at once)",
      merge ? "maps merged" : "loop closed", event.keyframe, event.matched, event.sim3_inliers,
      event.loop_matches, event.scale, event.correction, event.seconds,
      1e3 * event.map_lock_held_seconds, 1e3 * event.map_lock_longest_hold_seconds);
  if (merge) {
    spdlog::info("maps merged: map {} moved into map {} (scale {:.3f}) at frame {}",
                 event.merged_map, event.into_map, event.scale, event.frame);
    stats_.merges.push_back(event);
  } else {
    stats_.loops.push_back(event);
  }
  return true;
}

std::optional<LoopEvent> LoopClosing::Recognize(const KeyFramePtr& keyframe,
                                                const std::vector<KeyFramePtr>& candidates) {
  std::lock_guard<std::mutex> lock(map_->mutex());
  Loop loop;
  if (!ComputeSim3(keyframe, candidates, &loop)) return std::nullopt;
  return Describe(keyframe, loop);
}

LoopEvent LoopClosing::Describe(const KeyFramePtr& keyframe, const Loop& loop) {
  LoopEvent event;
  event.keyframe = keyframe->id;
  event.matched = loop.matched->id;
  event.timestamp = keyframe->timestamp;
  event.sim3_inliers = loop.sim3_inliers;
  event.loop_matches = loop.loop_matches;
  event.scale = loop.S_cw.scale();
  event.correction = (ToSE3(loop.S_cw).Inverse().translation() - keyframe->Centre()).norm();
  return event;
}

std::vector<KeyFramePtr> LoopClosing::DetectCandidates(const KeyFramePtr& keyframe) {
  const bool loops_allowed =
      map_->KeyFrameCount(keyframe->map) >
          static_cast<std::size_t>(options_.min_keyframes_between) &&
      !(last_loop_keyframe_ > 0 &&
        keyframe->id <
            last_loop_keyframe_ + static_cast<KeyFrameId>(options_.min_keyframes_between));
  // Another map's place is recognized as a loop is (the same candidates, consistency and
  // verification), from a map's first keyframes on: the sooner two maps merge, the less
  // is tracked in a frame of its own.
  const bool merges_allowed = options_.merge_maps && map_->map_count() > 1;
  if (!loops_allowed && !merges_allowed) return {};
  // The least similarity to a neighbour is what "looks like this place" means here.
  double min_score = 1.0;
  bool any = false;
  for (const KeyFrameId id : keyframe->ordered_covisible) {
    const KeyFramePtr neighbour = map_->GetKeyFrame(id);
    if (!neighbour || neighbour->bad) continue;
    min_score = std::min(min_score, ScoreL1(keyframe->bow, neighbour->bow));
    any = true;
  }
  if (!any) return {};
  std::vector<int> exclude = {static_cast<int>(keyframe->id)};
  for (const auto& [id, weight] : keyframe->covisible) exclude.push_back(static_cast<int>(id));
  std::vector<KeyFramePtr> raw;
  for (const BowQueryResult& result : database_->Query(keyframe->bow, 0, 1, exclude)) {
    if (result.score < min_score) break;  // best first
    const KeyFramePtr candidate = map_->GetKeyFrame(static_cast<KeyFrameId>(result.id));
    if (!candidate || candidate->bad) continue;
    if (candidate->map == keyframe->map) {
      if (!loops_allowed) continue;
      // A place seen a moment ago is not a loop.
      if (candidate->id + static_cast<KeyFrameId>(options_.min_loop_age) > keyframe->id) continue;
    } else if (!merges_allowed) {
      continue;
    }
    raw.push_back(candidate);
    if (static_cast<int>(raw.size()) >= options_.max_candidates) break;
  }
  // Consistency: a candidate's group (it and its neighbours) must overlap a group that
  // was a candidate's for the previous keyframes, options_.consistency times in a row.
  std::vector<ConsistentGroup> current;
  std::vector<bool> continued(groups_.size(), false);
  std::vector<KeyFramePtr> accepted;
  for (const KeyFramePtr& candidate : raw) {
    ConsistentGroup group;
    group.keyframes.insert(candidate->id);
    for (const auto& [id, weight] : candidate->covisible) group.keyframes.insert(id);
    bool consistent = false, enough = false;
    for (std::size_t g = 0; g < groups_.size(); ++g) {
      const bool overlaps =
          std::any_of(group.keyframes.begin(), group.keyframes.end(),
                      [&](KeyFrameId id) { return groups_[g].keyframes.count(id) > 0; });
      if (!overlaps) continue;
      consistent = true;
      const int consistency = groups_[g].consistency + 1;
      if (!continued[g]) {
        current.push_back({group.keyframes, consistency});
        continued[g] = true;
      }
      if (consistency >= options_.consistency && !enough) {
        accepted.push_back(candidate);
        enough = true;
      }
    }
    if (!consistent) current.push_back({group.keyframes, 0});
  }
  groups_ = std::move(current);
  return accepted;
}

bool LoopClosing::ComputeSim3(const KeyFramePtr& keyframe,
                              const std::vector<KeyFramePtr>& candidates, Loop* loop) {
  const std::vector<bool> keyframe_usable = keyframe->GoodPointMask();
  for (const KeyFramePtr& candidate : candidates) {
    if (candidate->bad) continue;
    ++stats_.candidates_checked;
    std::vector<Sim3Match> matches;
    std::vector<std::pair<std::size_t, MapPointPtr>> features;  // current feature, point
    // Another map's place: its points are matched in the candidate and its best covisible
    // keyframes (ORB-SLAM3's window for merges), as a map seen once from a new angle
    // shares few points with any single keyframe of it. Points of the window's other
    // keyframes enter as the candidate's camera sees them (their pixel there projected).
    std::vector<KeyFramePtr> window = {candidate};
    if (candidate->map != keyframe->map) {
      for (const KeyFramePtr& k : map_->BestCovisible(candidate, kMergeWindow - 1))
        window.push_back(k);
    }
    std::vector<bool> current_usable = keyframe_usable;
    std::set<MapPointId> used;
    for (const KeyFramePtr& source : window) {
      const std::vector<bool> source_usable = source->GoodPointMask();
      const std::vector<int> bow_matches =
          SearchByBow({&keyframe->feature_vector, &keyframe->features.descriptors,
                       &keyframe->features.keypoints, &current_usable},
                      {&source->feature_vector, &source->features.descriptors,
                       &source->features.keypoints, &source_usable},
                      matcher_);
      for (std::size_t i = 0; i < bow_matches.size(); ++i) {
        if (bow_matches[i] == kNoMatch) continue;
        const auto j = static_cast<std::size_t>(bow_matches[i]);
        const MapPointPtr& point1 = keyframe->points[i];
        const MapPointPtr& point2 = source->points[j];
        if (point1 == point2) continue;  // already one point: no loop evidence
        if (source != candidate && !used.insert(point2->id).second) continue;
        Sim3Match match;
        match.point1 = keyframe->T_cw * point1->position;
        match.point2 = candidate->T_cw * point2->position;
        if (source != candidate && match.point2.z() <= 0.0) continue;
        match.pixel1 = keyframe->features.undistorted[i];
        match.pixel2 = source == candidate ? candidate->features.undistorted[j]
                                           : camera_.ProjectUndistorted(match.point2);
        match.sigma2_1 =
            pyramid_.sigma2[static_cast<std::size_t>(keyframe->features.keypoints[i].octave)];
        match.sigma2_2 =
            pyramid_.sigma2[static_cast<std::size_t>(source->features.keypoints[j].octave)];
        matches.push_back(match);
        features.emplace_back(i, point2);
        current_usable[i] = false;
      }
      if (source == candidate) {
        for (const auto& [i, point] : features) used.insert(point->id);
      }
    }
    if (static_cast<int>(matches.size()) < options_.min_bow_matches) continue;
    Sim3EstimationOptions sim3_options = options_.sim3;
    sim3_options.seed = seed_ ^ (0x9E3779B97F4A7C15ull * (keyframe->id + 1)) ^ candidate->id;
    const Sim3Estimate estimate = EstimateSim3(matches, camera_, sim3_options);
    if (!estimate.found) continue;

    // Guided matching: the points around the place seen before, projected into the
    // current keyframe through the similarity.
    const Sim3 S_cw = estimate.S12 * Sim3(candidate->T_cw);
    std::vector<MapPointPtr> matched(keyframe->points.size());
    std::vector<bool> taken(keyframe->points.size(), false);
    std::set<MapPointId> already;
    for (std::size_t m = 0; m < matches.size(); ++m) {
      if (!estimate.inliers[m]) continue;
      matched[features[m].first] = features[m].second;
      taken[features[m].first] = true;
      already.insert(features[m].second->id);
    }
    std::vector<MapPointPtr> loop_points;
    std::set<MapPointId> seen;
    std::vector<KeyFramePtr> region = {candidate};
    for (const KeyFramePtr& k : map_->BestCovisible(candidate, candidate->ordered_covisible.size()))
      region.push_back(k);
    for (const KeyFramePtr& k : region) {
      for (const MapPointPtr& point : k->points) {
        if (point && !point->bad && seen.insert(point->id).second) loop_points.push_back(point);
      }
    }
    // The rigid pose with the similarity's scale divided out projects to the same pixels
    // from the same centre, and measures distances in the loop region's units, as the
    // points' scale-invariance distances are.
    const SE3 T_cw = ToSE3(S_cw);
    std::vector<ProjectedPoint> projected;
    std::vector<MapPointPtr> sources;
    for (const MapPointPtr& point : loop_points) {
      if (already.count(point->id) > 0) continue;
      const auto projection =
          ProjectPoint(camera_, keyframe->features.grid.bounds(), T_cw, *point, true);
      if (!projection) continue;
      projected.push_back(SearchWindow(*projection, *point, pyramid_, options_.loop_search_radius));
      sources.push_back(point);
    }
    const std::vector<int> guided = SearchByProjection(keyframe->features, projected, &taken, 0.0,
                                                       matcher_.strict_distance, matcher_);
    for (std::size_t q = 0; q < guided.size(); ++q) {
      if (guided[q] != kNoMatch) matched[static_cast<std::size_t>(guided[q])] = sources[q];
    }
    const int total = static_cast<int>(std::count_if(
        matched.begin(), matched.end(), [](const MapPointPtr& p) { return p != nullptr; }));
    if (total < options_.min_loop_matches) continue;
    loop->matched = candidate;
    loop->S_cw = S_cw;
    loop->matched_points = std::move(matched);
    loop->loop_points = std::move(loop_points);
    loop->sim3_inliers = estimate.inlier_count;
    loop->loop_matches = total;
    return true;
  }
  return false;
}

int LoopClosing::Correct(const KeyFramePtr& keyframe, Loop& loop, MapLock& map_lock) {
  // 1. The current keyframe and its neighbours move with the similarity. Tracking, let in
  // between the steps below, follows them: it tracks where the camera is, among them.
  map_lock.Lock();
  std::vector<KeyFramePtr> group = {keyframe};
  for (const KeyFramePtr& k : map_->BestCovisible(keyframe, keyframe->ordered_covisible.size()))
    group.push_back(k);
  std::map<KeyFrameId, Sim3> corrected, uncorrected;
  const SE3 T_wc = keyframe->T_cw.Inverse();
  for (const KeyFramePtr& k : group) {
    uncorrected[k->id] = Sim3(k->T_cw);
    corrected[k->id] = k == keyframe ? loop.S_cw : Sim3(k->T_cw * T_wc) * loop.S_cw;
  }
  std::map<MapPointId, KeyFrameId> corrected_by;
  for (const KeyFramePtr& k : group) {
    for (const MapPointPtr& point : k->points) {
      if (!point || point->bad || !corrected_by.emplace(point->id, k->id).second) continue;
      point->position = corrected[k->id].Inverse() * (uncorrected[k->id] * point->position);
    }
  }
  for (const KeyFramePtr& k : group) k->T_cw = ToSE3(corrected[k->id]);
  for (const auto& [id, keyframe_id] : corrected_by) {
    const auto found = map_->points().find(id);
    if (found != map_->points().end()) map_->UpdatePointGeometry(found->second, pyramid_);
  }
  map_->CountCorrection();
  map_lock.LetWaitingTrackerIn(*map_);

  // 2. One point per place: the loop's points replace their duplicates.
  int fused = 0;
  for (std::size_t i = 0; i < loop.matched_points.size(); ++i) {
    const MapPointPtr& loop_point = loop.matched_points[i];
    if (!loop_point || loop_point->bad) continue;
    const MapPointPtr existing = keyframe->points[i];
    if (existing && !existing->bad) {
      map_->ReplacePoint(existing, loop_point);
    } else if (loop_point->observations.count(keyframe->id) == 0) {
      map_->AddObservation(keyframe, static_cast<int>(i), loop_point);
    }
    ++fused;
  }
  std::map<KeyFrameId, std::set<KeyFrameId>> before;
  for (const KeyFramePtr& k : group) {
    for (const auto& [id, weight] : k->covisible) before[k->id].insert(id);
  }
  for (const KeyFramePtr& k : group) {
    map_lock.LetWaitingTrackerIn(*map_);
    if (k->bad) continue;
    fused += FusePoints(*map_, camera_, pyramid_, matcher_, 4.0, k, loop.loop_points);
  }

  // 3. The links the loop made: new covisibility between the two regions.
  std::set<KeyFrameId> group_ids;
  for (const KeyFramePtr& k : group) group_ids.insert(k->id);
  std::map<KeyFrameId, std::set<KeyFrameId>> loop_links;
  for (const KeyFramePtr& k : group) {
    map_->UpdateConnections(k);
    for (const auto& [id, weight] : k->covisible) {
      if (before[k->id].count(id) == 0 && group_ids.count(id) == 0) loop_links[k->id].insert(id);
    }
  }
  keyframe->loop_edges.insert(loop.matched->id);
  loop.matched->loop_edges.insert(keyframe->id);
  map_lock.Unlock();

  // 4. The essential graph as a Sim(3) pose graph, the matched keyframe fixed: built and
  // solved without the map lock (only this thread changes the map), written under it.
  std::vector<KeyFramePtr> all;
  std::map<KeyFrameId, int> index;
  PoseGraphProblem problem;
  for (const auto& [id, k] : map_->keyframes()) {
    if (k->bad || k->map != keyframe->map) continue;  // other maps are not moved
    index[id] = static_cast<int>(all.size());
    all.push_back(k);
    const auto found = corrected.find(id);
    problem.poses.push_back(found != corrected.end() ? found->second : Sim3(k->T_cw));
    problem.fixed.push_back(k == loop.matched);
  }
  const auto old_pose = [&](const KeyFramePtr& k) {
    const auto found = uncorrected.find(k->id);
    return found != uncorrected.end() ? found->second : Sim3(k->T_cw);
  };
  std::set<std::pair<int, int>> linked;
  const auto add_edge = [&](const KeyFramePtr& a, const KeyFramePtr& b, const Sim3& S_ab) {
    const auto i = index.find(a->id), j = index.find(b->id);
    if (i == index.end() || j == index.end() || i->second == j->second) return;
    if (!linked.insert({std::min(i->second, j->second), std::max(i->second, j->second)}).second)
      return;
    problem.edges.push_back({i->second, j->second, S_ab, 1.0});
  };
  // The loop's own links, measured after the correction.
  for (const auto& [id, links] : loop_links) {
    const KeyFramePtr a = map_->GetKeyFrame(id);
    for (const KeyFrameId other : links) {
      const KeyFramePtr b = map_->GetKeyFrame(other);
      if (!a || !b || a->bad || b->bad) continue;
      const bool the_loop = a == keyframe && b == loop.matched;
      const auto weight = a->covisible.find(other);
      if (!the_loop &&
          (weight == a->covisible.end() || weight->second < options_.strong_covisibility))
        continue;
      add_edge(a, b,
               problem.poses[static_cast<std::size_t>(index[a->id])] *
                   problem.poses[static_cast<std::size_t>(index[b->id])].Inverse());
    }
  }
  add_edge(keyframe, loop.matched,
           problem.poses[static_cast<std::size_t>(index[keyframe->id])] *
               problem.poses[static_cast<std::size_t>(index[loop.matched->id])].Inverse());
  // The rest as the map measured it before the correction: spanning tree, earlier loops,
  // strong covisibility.
  for (const KeyFramePtr& k : all) {
    const auto related = [&](KeyFrameId other_id) {
      const KeyFramePtr other = map_->GetKeyFrame(other_id);
      if (other && !other->bad) add_edge(k, other, old_pose(k) * old_pose(other).Inverse());
    };
    if (k->has_parent) related(k->parent);
    for (const KeyFrameId other : k->loop_edges) related(other);
    for (const auto& [other, weight] : k->covisible) {
      if (weight >= options_.strong_covisibility) related(other);
    }
  }
  PoseGraphOptions graph_options;
  graph_options.max_iterations = options_.pose_graph_iterations;
  const std::vector<Sim3> initial = problem.poses;
  const PoseGraphReport report = OptimizePoseGraph(&problem, graph_options);
  map_lock.Lock();
  if (report.solved) {
    for (std::size_t n = 0; n < all.size(); ++n) all[n]->T_cw = ToSE3(problem.poses[n]);
    // Points follow the keyframe that corrected them, or their reference.
    for (const auto& [id, point] : map_->points()) {
      if (point->bad || point->map != keyframe->map) continue;
      KeyFrameId reference = point->reference;
      const auto by = corrected_by.find(id);
      if (by != corrected_by.end()) reference = by->second;
      auto found = index.find(reference);
      if (found == index.end()) {
        for (const auto& [observer, feature] : point->observations) {
          found = index.find(observer);
          if (found != index.end()) break;
        }
      }
      if (found == index.end()) continue;
      const auto n = static_cast<std::size_t>(found->second);
      point->position = problem.poses[n].Inverse() * (initial[n] * point->position);
      map_->UpdatePointGeometry(point, pyramid_);
    }
  } else {
    spdlog::warn("loop closing: the pose graph found no usable solution: {}", report.message);
  }

  map_->CountCorrection();
  map_lock.Unlock();
  AdjustGlobally(keyframe->map, map_lock);
  last_loop_keyframe_ = keyframe->id;
  return fused;
}

void LoopClosing::AdjustGlobally(int map, MapLock& map_lock) {
  if (options_.global_ba_iterations <= 0) return;
  std::vector<KeyFramePtr> keyframes;
  for (const auto& [id, k] : map_->keyframes()) {
    if (!k->bad && k->map == map) keyframes.push_back(k);
  }
  // Copying the whole map takes a while: done without the map lock (only this thread
  // changes the map).
  KeyFrameAdjustment adjustment = PrepareAdjustment(*map_, camera_, pyramid_, keyframes);
  if (!threaded_) {
    const auto start = std::chrono::steady_clock::now();
    if (SolveGlobally(adjustment)) {
      map_lock.Lock();
      MergeGlobalAdjustment(adjustment, start);
      map_lock.Unlock();
    }
    return;
  }
  global_adjustment_running_ = true;
  global_adjustment_thread_ = std::thread([this, adjustment = std::move(adjustment)]() mutable {
    NameThisThread("global_ba");
    try {
      const auto start = std::chrono::steady_clock::now();
      if (SolveGlobally(adjustment)) {
        const std::lock_guard<std::mutex> mapping(map_->mapping_mutex());
        const std::lock_guard<std::mutex> lock(map_->mutex());
        MergeGlobalAdjustment(adjustment, start);
      }
    } catch (const std::exception& error) {
      spdlog::error("loop closing: the global bundle adjustment failed: {}", error.what());
    }
    global_adjustment_running_ = false;
  });
}

bool LoopClosing::SolveGlobally(KeyFrameAdjustment& adjustment) const {
  if (SolveAdjustment(&adjustment, options_.global_ba_iterations)) return true;
  spdlog::warn("loop closing: the global bundle adjustment found no usable solution: {}",
               adjustment.report.message);
  return false;
}

void LoopClosing::MergeGlobalAdjustment(const KeyFrameAdjustment& adjustment,
                                        std::chrono::steady_clock::time_point start) {
  const int followed = ApplyAdjustment(*map_, pyramid_, adjustment);
  map_->CountCorrection();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ++stats_.global_adjustments;
  stats_.followed_global_adjustment += followed;
  stats_.global_adjustment_seconds += seconds;
  if (threaded_) {
    spdlog::info(
        "global bundle adjustment of {} keyframes merged after {:.2f} s; {} keyframes and "
        "points added meanwhile followed it",
        adjustment.keyframes.size(), seconds, followed);
  }
}

}  // namespace ocg
