#include "ocg/slam/local_mapping.h"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <set>

#include "ocg/core/cpu_time.h"
#include "ocg/core/options.h"
#include "ocg/core/settings_file.h"
#include "ocg/core/statistics.h"
#include "ocg/slam/map_operations.h"
#include "ocg/slam/two_view.h"

namespace ocg {
namespace {

constexpr double kChi2OneDof = 3.841;
constexpr double kChi2TwoDof = 5.991;

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

Eigen::Matrix3d Intrinsics(const PinholeCamera& c) {
  Eigen::Matrix3d K;
  K << c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1;
  return K;
}

// F with x2^T F x1 = 0 between the pixels of two cameras (poses T_cw).
Eigen::Matrix3d FundamentalBetween(const SE3& a_T_cw, const SE3& b_T_cw, const Eigen::Matrix3d& K) {
  const SE3 T_ba = b_T_cw * a_T_cw.Inverse();
  const Eigen::Matrix3d K_inverse = K.inverse();
  return K_inverse.transpose() * Skew(T_ba.translation()) * T_ba.rotation() * K_inverse;
}

double MedianDepth(const KeyFrame& keyframe) {
  std::vector<double> depths;
  for (const MapPointPtr& point : keyframe.points) {
    if (point && !point->bad) depths.push_back((keyframe.T_cw * point->position).z());
  }
  return Median(std::move(depths));
}

Eigen::Matrix<double, 3, 4> Projection(const Eigen::Matrix3d& K, const SE3& T_cw) {
  Eigen::Matrix<double, 3, 4> P;
  P.leftCols<3>() = K * T_cw.rotation();
  P.col(3) = K * T_cw.translation();
  return P;
}

}  // namespace

void LocalMappingOptions::Check() const { CheckOptionFields(*this); }

void ReadSettings(const SettingsFile& file, LocalMappingOptions* options) {
  ReadOptionFields(file, options);
}

LocalMapping::LocalMapping(const PinholeCamera& camera, const ScalePyramid& pyramid,
                           const MatcherOptions& matcher, const LocalMappingOptions& options,
                           Map* map, BowDatabase* database)
    : camera_(camera),
      pyramid_(pyramid),
      matcher_(matcher),
      options_(options),
      map_(map),
      database_(database),
      worker_(
          options.queue_capacity,
          [this](const KeyFramePtr& keyframe) {
            ProcessKeyFrame(keyframe);
            if (keyframe_mapped_) keyframe_mapped_(keyframe);
          },
          "local_mapping") {
  options_.Check();
}

LocalMapping::~LocalMapping() {
  try {
    Stop();
  } catch (...) {
    // A worker failure was already reported, or the owner is unwinding from one.
  }
}

// Runs work with the map lock released (taken held, given back held). Its time, waiting
// to lock again included, counts as not holding the lock (run.json's
// local_mapping_map_lock_held_per_keyframe).
template <typename Work>
auto LocalMapping::WithoutMapLock(std::unique_lock<std::mutex>& map_lock, Work&& work) {
  map_lock.unlock();
  const auto unlocked = std::chrono::steady_clock::now();
  auto result = work();
  map_lock.lock();
  unlocked_seconds_ +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - unlocked).count();
  return result;
}

// Tracking only reads the map (and counts its points' sightings), so what it does between
// two steps changes nothing they rely on; a loop correction that takes the lock meanwhile
// moves the map as it could before a keyframe's steps. Sequentially no tracker ever waits.
void LocalMapping::LetTrackingIn(std::unique_lock<std::mutex>& map_lock) {
  if (!map_->TrackerWaiting()) return;
  const auto unlocked = std::chrono::steady_clock::now();
  if (map_->LetWaitingTrackerIn(map_lock)) ++stats_.map_lock_yields;
  unlocked_seconds_ +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - unlocked).count();
}

void LocalMapping::ProcessKeyFrame(const KeyFramePtr& keyframe) {
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = ThreadCpuSeconds();
  const std::lock_guard<std::mutex> mapping(map_->mapping_mutex());
  std::unique_lock<std::mutex> lock(map_->mutex());
  unlocked_seconds_ = 0.0;
  const auto locked = std::chrono::steady_clock::now();
  LinkKeyFrame(keyframe);
  CullRecentPoints(keyframe);
  LetTrackingIn(lock);
  TriangulateNewPoints(keyframe, lock);
  LetTrackingIn(lock);
  FuseDuplicates(keyframe, lock);
  LetTrackingIn(lock);
  if (CatchingUp()) {
    ++stats_.local_adjustments_skipped;
  } else {
    if (map_->KeyFrameCount(keyframe->map) > 2) LocalBundleAdjustment(keyframe, lock);
    LetTrackingIn(lock);
    CullKeyFrames(keyframe, lock);
  }
  ++stats_.keyframes;
  const auto end = std::chrono::steady_clock::now();
  stats_.keyframe_seconds.Add(std::chrono::duration<double>(end - start).count());
  stats_.keyframe_cpu_seconds.Add(ThreadCpuSeconds() - cpu_start);
  stats_.map_lock_held_seconds.Add(std::chrono::duration<double>(end - locked).count() -
                                   unlocked_seconds_);
}

void LocalMapping::LinkKeyFrame(const KeyFramePtr& keyframe) {
  map_->Add(keyframe);
  for (std::size_t i = 0; i < keyframe->points.size(); ++i) {
    const MapPointPtr point = keyframe->points[i];
    if (!point) continue;
    if (point->bad) {
      keyframe->points[i].reset();
      continue;
    }
    if (point->observations.count(keyframe->id) == 0) {
      map_->AddObservation(keyframe, static_cast<int>(i), point);
      map_->UpdatePointGeometry(point, pyramid_);
      map_->UpdatePointDescriptor(point);
    } else {
      recent_points_.push_back(point);  // created with this keyframe (initialization)
    }
  }
  map_->UpdateConnections(keyframe);
  database_->Add(static_cast<int>(keyframe->id), keyframe->bow);
}

void LocalMapping::CullRecentPoints(const KeyFramePtr& keyframe) {
  for (auto it = recent_points_.begin(); it != recent_points_.end();) {
    const MapPointPtr& point = *it;
    const KeyFrameId age = keyframe->id - point->first_keyframe;
    if (point->bad) {
      it = recent_points_.erase(it);
    } else if (point->FoundRatio() < options_.min_found_ratio ||
               (age >= 2 && point->observations.size() <= 2)) {
      map_->ErasePoint(point);
      ++stats_.points_culled;
      it = recent_points_.erase(it);
    } else if (age >= 3) {
      it = recent_points_.erase(it);  // old enough: it stays
    } else {
      ++it;
    }
  }
}

LocalMapping::TriangulationView LocalMapping::ViewOf(const KeyFramePtr& keyframe) {
  TriangulationView view;
  view.keyframe = keyframe;
  view.T_cw = keyframe->T_cw;
  view.has_point.resize(keyframe->points.size());
  for (std::size_t i = 0; i < keyframe->points.size(); ++i)
    view.has_point[i] = keyframe->points[i] ? 1 : 0;
  return view;
}

// Matching and triangulating, most of this step's time, need only the keyframes' poses,
// which features have points (both copied under the lock) and their features (fixed once
// a keyframe exists): they run without the map lock, so that tracking does not wait for
// them. Only this thread adds points to keyframes; a loop correction or a global
// adjustment merged meanwhile moved the poses, and the pairs are then found again on the
// moved map. Sequentially nothing runs meanwhile: the same points, in the same order, as
// triangulating under the lock.
void LocalMapping::TriangulateNewPoints(const KeyFramePtr& keyframe,
                                        std::unique_lock<std::mutex>& map_lock) {
  const std::vector<KeyFramePtr> neighbours =
      map_->BestCovisible(keyframe, static_cast<std::size_t>(options_.triangulation_neighbours));
  const auto views_of_the_map = [&] {
    std::vector<TriangulationView> views;
    views.push_back(ViewOf(keyframe));
    for (const KeyFramePtr& neighbour : neighbours) {
      views.push_back(ViewOf(neighbour));
      views.back().median_depth = MedianDepth(*neighbour);  // the new keyframe's is not used
    }
    return views;
  };
  std::vector<TriangulationView> views = views_of_the_map();
  const std::uint64_t corrections = map_->corrections();
  std::vector<NewPoint> found = WithoutMapLock(map_lock, [&] {
    if (before_triangulation_) before_triangulation_();
    return FindNewPoints(&views);
  });
  if (map_->corrections() != corrections) {
    views = views_of_the_map();
    found = FindNewPoints(&views);
  }
  for (const NewPoint& candidate : found) {
    const KeyFramePtr& neighbour = views[candidate.view].keyframe;
    if (neighbour->bad || keyframe->points[static_cast<std::size_t>(candidate.i1)] ||
        neighbour->points[static_cast<std::size_t>(candidate.i2)]) {
      continue;  // taken meanwhile
    }
    auto point = std::make_shared<MapPoint>();
    point->id = map_->NextMapPointId();
    point->position = candidate.position;
    point->reference = keyframe->id;
    point->first_keyframe = keyframe->id;
    point->first_frame = keyframe->frame_id;
    point->map = keyframe->map;
    map_->Add(point);
    map_->AddObservation(keyframe, candidate.i1, point);
    map_->AddObservation(neighbour, candidate.i2, point);
    map_->UpdatePointDescriptor(point);
    map_->UpdatePointGeometry(point, pyramid_);
    recent_points_.push_back(point);
    ++stats_.points_created;
  }
}

std::vector<LocalMapping::NewPoint> LocalMapping::FindNewPoints(
    std::vector<TriangulationView>* views) const {
  std::vector<NewPoint> found;
  TriangulationView& self = views->front();
  const KeyFrame& keyframe = *self.keyframe;
  const Eigen::Matrix3d K = Intrinsics(camera_);
  const Eigen::Vector3d centre1 = self.T_cw.Inverse().translation();
  const Eigen::Matrix<double, 3, 4> P1 = Projection(K, self.T_cw);
  const double ratio_factor = options_.scale_consistency * pyramid_.scale_factor;
  for (std::size_t v = 1; v < views->size(); ++v) {
    const TriangulationView& other = (*views)[v];
    const KeyFrame& neighbour = *other.keyframe;
    const Eigen::Vector3d centre2 = other.T_cw.Inverse().translation();
    const double baseline = (centre2 - centre1).norm();
    if (other.median_depth <= 0.0 || baseline / other.median_depth < options_.min_baseline_ratio)
      continue;
    const Eigen::Matrix3d F12 = FundamentalBetween(other.T_cw, self.T_cw, K);  // x1^T F x2 = 0
    const Eigen::Matrix<double, 3, 4> P2 = Projection(K, other.T_cw);
    // Candidate pairs: features without points under the same vocabulary node, close in
    // descriptor space and near each other's epipolar line.
    std::vector<std::pair<int, int>> pairs;
    std::vector<char> taken(neighbour.features.size(), 0);
    ForEachSharedNode(
        keyframe.feature_vector, neighbour.feature_vector,
        [&](NodeId, const std::vector<int>& in_keyframe, const std::vector<int>& in_neighbour) {
          for (const int i1 : in_keyframe) {
            if (self.has_point[static_cast<std::size_t>(i1)]) continue;
            const Eigen::Vector2d& x1 = keyframe.features.undistorted[static_cast<std::size_t>(i1)];
            const Eigen::Vector3d line = F12.transpose() * x1.homogeneous();  // in the neighbour
            int best = INT_MAX, second = INT_MAX, best_index = -1;
            for (const int i2 : in_neighbour) {
              if (other.has_point[static_cast<std::size_t>(i2)] ||
                  taken[static_cast<std::size_t>(i2)]) {
                continue;
              }
              const int distance =
                  HammingDistance(keyframe.features.descriptors[static_cast<std::size_t>(i1)],
                                  neighbour.features.descriptors[static_cast<std::size_t>(i2)]);
              if (distance > matcher_.strict_distance || distance >= second) continue;
              const Eigen::Vector2d& x2 =
                  neighbour.features.undistorted[static_cast<std::size_t>(i2)];
              const double d = line.dot(x2.homogeneous());
              const int level2 = neighbour.features.keypoints[static_cast<std::size_t>(i2)].octave;
              if (d * d / line.head<2>().squaredNorm() >
                  kChi2OneDof * pyramid_.sigma2[static_cast<std::size_t>(level2)]) {
                continue;
              }
              if (distance < best) {
                second = best;
                best = distance;
                best_index = i2;
              } else {
                second = distance;
              }
            }
            if (best_index >= 0 &&
                (second == INT_MAX || best < options_.triangulation_ratio * second)) {
              pairs.emplace_back(i1, best_index);
              taken[static_cast<std::size_t>(best_index)] = 1;
            }
          }
        });
    for (const auto& [i1, i2] : pairs) {
      const Eigen::Vector2d& x1 = keyframe.features.undistorted[static_cast<std::size_t>(i1)];
      const Eigen::Vector2d& x2 = neighbour.features.undistorted[static_cast<std::size_t>(i2)];
      const Eigen::Vector3d X = TriangulateLinear(x1, x2, P1, P2);
      if (!X.allFinite()) continue;
      const Eigen::Vector3d ray1 = X - centre1;
      const Eigen::Vector3d ray2 = X - centre2;
      if (ray1.dot(ray2) / (ray1.norm() * ray2.norm()) > options_.max_cos_parallax) continue;
      const Eigen::Vector3d X1 = self.T_cw * X;
      const Eigen::Vector3d X2 = other.T_cw * X;
      if (X1.z() <= 0.0 || X2.z() <= 0.0) continue;
      const int level1 = keyframe.features.keypoints[static_cast<std::size_t>(i1)].octave;
      const int level2 = neighbour.features.keypoints[static_cast<std::size_t>(i2)].octave;
      if ((camera_.ProjectUndistorted(X1) - x1).squaredNorm() >
              kChi2TwoDof * pyramid_.sigma2[static_cast<std::size_t>(level1)] ||
          (camera_.ProjectUndistorted(X2) - x2).squaredNorm() >
              kChi2TwoDof * pyramid_.sigma2[static_cast<std::size_t>(level2)]) {
        continue;
      }
      // The distances' ratio must agree with the pyramid levels' ratio.
      const double distance_ratio = ray2.norm() / ray1.norm();
      const double level_ratio = pyramid_.scale[static_cast<std::size_t>(level1)] /
                                 pyramid_.scale[static_cast<std::size_t>(level2)];
      if (distance_ratio * ratio_factor < level_ratio ||
          distance_ratio > level_ratio * ratio_factor) {
        continue;
      }
      found.push_back({v, i1, i2, X});
      // Later neighbours see this feature as having its point, as they would in the map.
      self.has_point[static_cast<std::size_t>(i1)] = 1;
    }
  }
  return found;
}

void LocalMapping::FuseDuplicates(const KeyFramePtr& keyframe,
                                  std::unique_lock<std::mutex>& map_lock) {
  std::vector<KeyFramePtr> targets =
      map_->BestCovisible(keyframe, static_cast<std::size_t>(options_.triangulation_neighbours));
  std::set<KeyFrameId> seen;
  for (const KeyFramePtr& k : targets) seen.insert(k->id);
  const std::size_t first_ring = targets.size();
  for (std::size_t i = 0; i < first_ring; ++i) {
    for (const KeyFramePtr& second : map_->BestCovisible(targets[i], 5)) {
      if (second->id != keyframe->id && seen.insert(second->id).second) targets.push_back(second);
    }
  }
  for (const KeyFramePtr& target : targets) {
    stats_.points_fused += FusePoints(*map_, camera_, pyramid_, matcher_, options_.fuse_radius,
                                      target, keyframe->points);
    LetTrackingIn(map_lock);
  }
  std::vector<MapPointPtr> candidates;
  std::set<MapPointId> added;
  for (const KeyFramePtr& target : targets) {
    for (const MapPointPtr& point : target->points) {
      if (point && !point->bad && added.insert(point->id).second) candidates.push_back(point);
    }
  }
  stats_.points_fused +=
      FusePoints(*map_, camera_, pyramid_, matcher_, options_.fuse_radius, keyframe, candidates);
  for (const MapPointPtr& point : keyframe->points) {
    if (point && !point->bad) {
      map_->UpdatePointDescriptor(point);
      map_->UpdatePointGeometry(point, pyramid_);
    }
  }
  map_->UpdateConnections(keyframe);
}

// A keyframe inserted between here and the end of the solve stops the solve: the request
// is cleared before the queue is looked at, and Insert queues before it requests, so a
// keyframe is either seen waiting here or stops the solve.
bool LocalMapping::CatchingUp() {
  stop_adjustment_.store(false);
  return worker_.Waiting() > 0;
}

// The solve, most of local mapping's time, runs without the map lock, on the copy that
// PrepareAdjustment made: tracking goes on meanwhile instead of waiting a whole adjustment
// for the lock. Only this thread adds keyframes and points to the map, so nothing that the
// adjustment should carry along appears meanwhile; but a loop correction or a global
// adjustment merged meanwhile moved the whole map, and writing the local solution over it
// would undo that: it is dropped then. Sequentially nothing runs meanwhile, so the result
// is the same as an adjustment under the lock.
void LocalMapping::LocalBundleAdjustment(const KeyFramePtr& keyframe,
                                         std::unique_lock<std::mutex>& map_lock) {
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = ThreadCpuSeconds();
  std::vector<KeyFramePtr> local = {keyframe};
  for (const KeyFramePtr& k : map_->BestCovisible(keyframe, keyframe->ordered_covisible.size())) {
    local.push_back(k);
  }
  KeyFrameAdjustment adjustment = PrepareAdjustment(*map_, camera_, pyramid_, local);
  const std::uint64_t corrections = map_->corrections();
  BundleAdjustmentOptions solve;
  solve.max_iterations = options_.local_ba_iterations;
  solve.refine_iterations = options_.local_ba_refine_iterations;
  solve.refine_min_chi2_decrease = options_.local_ba_refine_min_chi2_decrease;
  solve.stop = [this](int) { return stop_adjustment_.load(); };
  const bool solved = WithoutMapLock(map_lock, [&] {
    if (before_local_solve_) before_local_solve_();
    return SolveAdjustment(&adjustment, solve);
  });
  if (adjustment.report.stopped) ++stats_.local_adjustments_interrupted;
  if (!solved) return;
  if (map_->corrections() != corrections) {
    ++stats_.local_adjustments_dropped;
    return;
  }
  ApplyAdjustment(*map_, pyramid_, adjustment);
  stats_.ba_iterations.push_back(adjustment.report.iterations);
  stats_.ba_seconds.Add(
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  stats_.ba_cpu_seconds.Add(ThreadCpuSeconds() - cpu_start);
}

void LocalMapping::CullKeyFrames(const KeyFramePtr& keyframe,
                                 std::unique_lock<std::mutex>& map_lock) {
  const std::optional<KeyFrameId> first_id = map_->FirstKeyFrame(keyframe->map);
  for (const KeyFramePtr& candidate :
       map_->BestCovisible(keyframe, keyframe->ordered_covisible.size())) {
    LetTrackingIn(map_lock);
    if (candidate->id == first_id || candidate->bad || !candidate->loop_edges.empty()) continue;
    int valid = 0;
    int redundant = 0;
    for (std::size_t i = 0; i < candidate->points.size(); ++i) {
      const MapPointPtr& point = candidate->points[i];
      if (!point || point->bad) continue;
      ++valid;
      if (static_cast<int>(point->observations.size()) <= options_.redundant_observers) continue;
      const int level = candidate->features.keypoints[i].octave;
      int observers = 0;
      for (const auto& [other_id, feature] : point->observations) {
        if (other_id == candidate->id) continue;
        const KeyFramePtr other = map_->GetKeyFrame(other_id);
        if (!other || other->bad) continue;
        // Seen at the same or a finer scale.
        if (other->features.keypoints[static_cast<std::size_t>(feature)].octave <= level + 1) {
          ++observers;
        }
        if (observers >= options_.redundant_observers) break;
      }
      if (observers >= options_.redundant_observers) ++redundant;
    }
    if (valid > 0 && redundant > options_.redundant_ratio * valid) {
      map_->EraseKeyFrame(candidate);
      database_->Erase(static_cast<int>(candidate->id));
      ++stats_.keyframes_culled;
    }
  }
}

void LocalMapping::Start() { worker_.Start(); }

void LocalMapping::Insert(const KeyFramePtr& keyframe) {
  worker_.Insert(keyframe);
  stop_adjustment_.store(true);  // after queueing it: see CatchingUp
}

bool LocalMapping::Idle() const { return worker_.Idle(); }

void LocalMapping::Stop() { worker_.Stop(); }

void LocalMapping::Reset() { recent_points_.clear(); }

LocalMappingStats LocalMapping::Stats() const {
  std::lock_guard<std::mutex> lock(map_->mutex());
  return stats_;
}

}  // namespace ocg
