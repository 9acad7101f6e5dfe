#include "ocg/slam/tracking.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <set>

#include "ocg/core/options.h"
#include "ocg/core/settings_file.h"
#include "ocg/slam/map_operations.h"

namespace ocg {
namespace {

constexpr int kRelocalizationCandidates = 10;
constexpr double kRelocalizationRatio = 0.75;

// Features of the frame that already have a map point: search must not match them again.
std::vector<bool> MatchedFeatures(const Frame& frame) {
  std::vector<bool> matched(frame.points.size());
  for (std::size_t i = 0; i < matched.size(); ++i) matched[i] = frame.points[i] != nullptr;
  return matched;
}

// Gives each matched feature the map point of the query that found it.
void AssignMatches(const std::vector<int>& matches, const std::vector<MapPointPtr>& sources,
                   Frame* frame) {
  for (std::size_t q = 0; q < matches.size(); ++q) {
    if (matches[q] != kNoMatch) frame->points[static_cast<std::size_t>(matches[q])] = sources[q];
  }
}

int CountMatches(const std::vector<int>& matches) {
  return static_cast<int>(
      std::count_if(matches.begin(), matches.end(), [](int m) { return m != kNoMatch; }));
}

}  // namespace

void TrackingOptions::Check() const { CheckOptionFields(*this); }

void ReadSettings(const SettingsFile& file, TrackingOptions* options) {
  ReadOptionFields(file, options);
}

const char* ToString(TrackingState state) {
  switch (state) {
    case TrackingState::kNoImages:
      return "no images yet";
    case TrackingState::kNotInitialized:
      return "not initialized";
    case TrackingState::kOk:
      return "tracking";
    case TrackingState::kLost:
      return "lost";
  }
  return "?";
}

Tracking::Tracking(const PinholeCamera& camera, double fps, const OrbExtractorOptions& orb,
                   const MatcherOptions& matcher, const InitialMapOptions& initializer,
                   const TrackingOptions& options, TrackingDependencies dependencies,
                   std::function<bool(const KeyFramePtr&)> keyframe_sink,
                   std::function<bool()> local_mapping_idle)
    : camera_(camera),
      fps_(fps),
      extractor_(orb),
      initialization_extractor_([&] {
        OrbExtractorOptions more = orb;
        more.features = static_cast<int>(orb.features * options.initialization_features_factor);
        return more;
      }()),
      matcher_(matcher),
      initializer_(initializer),
      options_(options),
      dependencies_(dependencies),
      keyframe_sink_(std::move(keyframe_sink)),
      local_mapping_idle_(std::move(local_mapping_idle)) {
  options_.Check();
  matcher_.Check();
  initializer_.Check();
}

void Tracking::ComputeBow(Frame& frame) const {
  if (frame.has_bow) return;
  dependencies_.vocabulary->Transform(frame.features.descriptors, &frame.bow,
                                      &frame.feature_vector);
  frame.has_bow = true;
}

TrackingResult Tracking::Track(const cv::Mat& image, double timestamp,
                               const std::string& timestamp_text,
                               const ExtractedFeatures* features) {
  map_lock_wait_seconds_ = 0.0;
  Frame frame;
  frame.id = next_frame_id_++;
  frame.timestamp = timestamp;
  frame.timestamp_text = timestamp_text;
  const bool initializing =
      state_ == TrackingState::kNoImages || state_ == TrackingState::kNotInitialized;
  if (initializing) {
    frame.features = initialization_extractor_.Extract(image, camera_);
  } else if (features != nullptr) {
    frame.features = *features;
  } else {
    frame.features = extractor_.Extract(image, camera_);
  }
  frame.points.assign(frame.features.size(), nullptr);
  frame.outlier.assign(frame.features.size(), false);
  TrackingResult result;
  const TrackingState previous = state_;
  if (state_ == TrackingState::kNoImages) state_ = TrackingState::kNotInitialized;
  if (state_ == TrackingState::kNotInitialized) {
    ++initialization_.frames;
    if (Initialize(frame)) {
      state_ = TrackingState::kOk;
      result.new_keyframe = true;
    }
  } else {
    bool ok = false;
    int inliers = 0;
    {
      const std::unique_lock<std::mutex> lock = LockMap();
      ReanchorLastFrame();
      UpdateLastFramePoints();
      if (state_ == TrackingState::kOk) {
        ok = TrackWithMotionModel(frame) || TrackReferenceKeyFrame(frame);
      } else {
        const int map_before = dependencies_.map->current_map();
        ok = Relocalize(frame);
        result.relocalized = ok;
        result.switched_map = dependencies_.map->current_map() != map_before;
        if (ok) last_relocalization_frame_id_ = frame.id;
      }
      if (ok) {
        inliers = TrackLocalMap(frame);
        const int needed =
            frame.id < last_relocalization_frame_id_ + static_cast<std::uint64_t>(fps_) &&
                    last_relocalization_frame_id_ > 0
                ? options_.min_inliers_after_relocalization
                : options_.min_local_map_inliers;
        ok = inliers >= needed;
        if (!ok)
          spdlog::debug("frame {}: local map: {} inliers, need {}", frame.id, inliers, needed);
      }
      if (ok) Anchor(frame, reference_);
    }
    result.inliers = inliers;
    spdlog::trace("frame {}: {} local map inliers", frame.id, inliers);
    if (ok) {
      state_ = TrackingState::kOk;
      frames_lost_ = 0;
      if (last_frame_ && last_frame_->T_cw) velocity_ = *frame.T_cw * last_frame_->T_cw->Inverse();
      if (NeedKeyFrame(frame, inliers)) {
        KeyFramePtr keyframe;
        {
          const std::unique_lock<std::mutex> lock = LockMap();
          FollowCorrections(frame);
          keyframe = CreateKeyFrame(frame);
          keyframe->anchor = anchor_;
          Anchor(frame, keyframe);
        }
        result.new_keyframe = true;
        spdlog::trace("frame {}: new keyframe {}", frame.id, keyframe->id);
        if (keyframe_sink_(keyframe)) {
          // A loop moved the map under this frame: it stands where its keyframe now does.
          const std::unique_lock<std::mutex> lock = LockMap();
          frame.T_cw = keyframe->T_cw;
          Anchor(frame, keyframe);
        }
      }
    } else {
      state_ = TrackingState::kLost;
      velocity_.reset();
      // The frame a relocalized one would take its velocity from must be the frame before
      // it, not the last one tracked before the loss (seconds earlier, elsewhere): that
      // velocity sent the motion model's search far from where the points were.
      last_frame_.reset();
      std::size_t keyframes = 0;
      {
        const std::unique_lock<std::mutex> lock = LockMap();
        // Culled keyframes stay in the map (bad) for the frames placed on them; counting
        // them kept a map culled down to four keyframes from ever being reset.
        keyframes = dependencies_.map->LiveKeyFrameCount(dependencies_.map->current_map());
      }
      ++frames_lost_;
      const int new_map_frames =
          static_cast<int>(std::ceil(options_.new_map_after_lost_seconds * fps_));
      if (!map_loaded_ &&
          keyframes <= static_cast<std::size_t>(options_.min_keyframes_to_keep_map)) {
        // The owner stops local mapping first, then calls Reset(): clearing the map under
        // a worker that still holds queued keyframes would let them into the new map.
        spdlog::warn("frame {}: lost with only {} keyframes: the map will be reset", frame.id,
                     keyframes);
        result.reset = true;
      } else if (!map_loaded_ && new_map_frames > 0 && frames_lost_ >= new_map_frames) {
        spdlog::warn(
            "frame {}: lost for {} frames in a map of {} keyframes without relocalizing: "
            "starting a new map",
            frame.id, frames_lost_, keyframes);
        result.new_map = true;
      }
    }
  }
  if (state_ != previous) {
    spdlog::info("frame {} ({}): {} -> {}", frame.id, timestamp_text, ToString(previous),
                 ToString(state_));
  }
  result.state = state_;
  if (state_ == TrackingState::kOk) {
    const std::unique_lock<std::mutex> lock = LockMap();  // positions move in BA
    FollowCorrections(frame);
    result.T_cw = frame.T_cw;
    for (std::size_t i = 0; i < frame.points.size(); ++i) {
      const MapPointPtr& point = frame.points[i];
      if (!point || point->bad || (i < frame.outlier.size() && frame.outlier[i])) continue;
      result.points.push_back({point->id, frame.features.undistorted[i], point->position});
    }
    last_frame_ = std::make_unique<Frame>(std::move(frame));
  }
  result.map_lock_wait_seconds = map_lock_wait_seconds_;
  return result;
}

void Tracking::RecordTooFewFeatures(const Frame& frame) {
  initialization_.Record(
      "too few features (" + std::to_string(frame.features.size()) +
      ", Tracking.minInitFeatures = " + std::to_string(options_.min_initialization_features) + ")");
}

bool Tracking::Initialize(Frame& frame) {
  if (!initial_frame_) {
    if (static_cast<int>(frame.features.size()) > options_.min_initialization_features) {
      initial_frame_ = std::make_unique<Frame>(frame);
      initial_predicted_ = frame.features.undistorted;
    } else {
      RecordTooFewFeatures(frame);
    }
    return false;
  }
  if (static_cast<int>(frame.features.size()) <= options_.min_initialization_features) {
    RecordTooFewFeatures(frame);
    initial_frame_.reset();
    return false;
  }
  const std::vector<int> matches =
      MatchInWindow(initial_frame_->features, frame.features, initial_predicted_, matcher_);
  if (CountMatches(matches) < options_.min_initialization_matches) {
    initialization_.Record(
        "too few matches with the first view (" + std::to_string(CountMatches(matches)) +
        ", Tracking.minInitMatches = " + std::to_string(options_.min_initialization_matches) + ")");
    spdlog::debug("frame {}: {} matches with the first view: choosing a new first view", frame.id,
                  CountMatches(matches));
    initial_frame_ = std::make_unique<Frame>(frame);
    initial_predicted_ = frame.features.undistorted;
    return false;
  }
  for (std::size_t i = 0; i < matches.size(); ++i) {
    if (matches[i] != kNoMatch) {
      initial_predicted_[i] = frame.features.undistorted[static_cast<std::size_t>(matches[i])];
    }
  }
  std::vector<Eigen::Vector2d> p1, p2;
  std::vector<int> index1, index2;
  std::vector<double> weights;
  for (std::size_t i = 0; i < matches.size(); ++i) {
    if (matches[i] == kNoMatch) continue;
    p1.push_back(initial_frame_->features.undistorted[i]);
    p2.push_back(frame.features.undistorted[static_cast<std::size_t>(matches[i])]);
    index1.push_back(static_cast<int>(i));
    index2.push_back(matches[i]);
    weights.push_back(pyramid().inverse_sigma2[static_cast<std::size_t>(
        frame.features.keypoints[static_cast<std::size_t>(matches[i])].octave)]);
  }
  const InitialMap initial = InitializeFromTwoViews(p1, p2, camera_, initializer_, &weights);
  if (!initial.success) {
    initialization_.Record(initial.failure);
    spdlog::debug("frame {}: initialization failed: {}", frame.id, initial.failure);
    if (initial.failure.rfind("weak initial map", 0) == 0) initial_frame_.reset();
    return false;
  }
  Map& map = *dependencies_.map;
  KeyFramePtr first, second;
  {
    const std::lock_guard<std::mutex> mapping(map.mapping_mutex());
    const std::lock_guard<std::mutex> lock(map.mutex());
    ComputeBow(*initial_frame_);
    ComputeBow(frame);
    initial_frame_->T_cw = SE3::Identity();
    frame.T_cw = initial.T_21;
    first = CreateKeyFrame(*initial_frame_);
    second = CreateKeyFrame(frame);
    for (std::size_t m = 0; m < p1.size(); ++m) {
      if (!initial.valid[m]) continue;
      auto point = std::make_shared<MapPoint>();
      point->id = map.NextMapPointId();
      point->position = initial.points[m];
      point->reference = second->id;
      point->first_keyframe = first->id;
      point->first_frame = first->frame_id;
      point->map = first->map;
      map.Add(point);
      point->observations[first->id] = index1[m];
      point->observations[second->id] = index2[m];
      first->points[static_cast<std::size_t>(index1[m])] = point;
      second->points[static_cast<std::size_t>(index2[m])] = point;
      frame.points[static_cast<std::size_t>(index2[m])] = point;
    }
    map.Add(first);
    map.Add(second);
    for (const auto& [id, point] : map.points()) {
      if (point->map != first->map) continue;  // an earlier map's
      map.UpdatePointDescriptor(point);
      map.UpdatePointGeometry(point, pyramid());
    }
  }
  spdlog::info("initialized from frames {} and {}: {} points ({}, median depth scaled from {:.3f})",
               initial_frame_->id, frame.id, initial.point_count,
               initial.two_view.model == TwoViewModel::kHomography ? "homography" : "fundamental",
               initial.median_depth_before_scaling);
  keyframe_sink_(first);
  keyframe_sink_(second);
  reference_ = second;
  {
    std::lock_guard<std::mutex> lock(dependencies_.map->mutex());
    Anchor(frame, second);
  }
  initial_frame_.reset();
  return true;
}

void Tracking::UpdateLastFramePoints() {
  if (!last_frame_) return;
  for (MapPointPtr& point : last_frame_->points) {
    if (point && point->bad) point.reset();
  }
}

int Tracking::OptimizeFramePose(Frame& frame) {
  std::vector<PoseObservation> observations;
  std::vector<int> feature_of;
  for (std::size_t i = 0; i < frame.points.size(); ++i) {
    if (!frame.points[i]) continue;
    PoseObservation o;
    o.point_world = frame.points[i]->position;
    o.pixel = frame.features.undistorted[i];
    o.inverse_sigma2 =
        pyramid().inverse_sigma2[static_cast<std::size_t>(frame.features.keypoints[i].octave)];
    observations.push_back(o);
    feature_of.push_back(static_cast<int>(i));
  }
  if (observations.size() < 4) return 0;
  const PoseOptimizationResult result =
      OptimizePose(camera_, *frame.T_cw, observations, pose_options_);
  frame.T_cw = result.T_cw;
  for (std::size_t k = 0; k < observations.size(); ++k) {
    if (!result.inlier[k]) frame.points[static_cast<std::size_t>(feature_of[k])].reset();
  }
  return result.inliers;
}

bool Tracking::TrackWithMotionModel(Frame& frame) {
  if (!velocity_ || !last_frame_ || !last_frame_->T_cw) return false;
  frame.T_cw = *velocity_ * *last_frame_->T_cw;
  std::vector<ProjectedPoint> points;
  std::vector<MapPointPtr> sources;
  for (std::size_t i = 0; i < last_frame_->points.size(); ++i) {
    const MapPointPtr& point = last_frame_->points[i];
    if (!point || point->bad) continue;
    const auto projection =
        ProjectPoint(camera_, frame.features.grid.bounds(), *frame.T_cw, *point, false);
    if (!projection) continue;
    const cv::KeyPoint& kp = last_frame_->features.keypoints[i];
    ProjectedPoint p;
    p.pixel = projection->pixel;
    p.min_level = std::max(0, kp.octave - 1);
    p.max_level = kp.octave + 1;
    p.descriptor = point->descriptor;
    p.source_angle = kp.angle;
    points.push_back(p);
    sources.push_back(point);
  }
  for (const double widen : {1.0, 2.0}) {
    for (std::size_t q = 0; q < points.size(); ++q) {
      const int level = std::max(0, points[q].max_level - 1);
      points[q].radius =
          widen * options_.motion_search_radius * pyramid().scale[static_cast<std::size_t>(level)];
    }
    const std::vector<int> matches =
        SearchByProjection(frame.features, points, nullptr, 0.0, matcher_.loose_distance, matcher_);
    std::fill(frame.points.begin(), frame.points.end(), nullptr);
    AssignMatches(matches, sources, &frame);
    if (CountMatches(matches) >= options_.min_motion_matches) break;
  }
  const int matched = static_cast<int>(std::count_if(
      frame.points.begin(), frame.points.end(), [](const MapPointPtr& p) { return p != nullptr; }));
  if (matched < options_.min_motion_matches) {
    spdlog::debug("frame {}: motion model: {} matches of {} points projected", frame.id, matched,
                  points.size());
    return false;
  }
  const int inliers = OptimizeFramePose(frame);
  if (inliers < options_.min_tracked_matches) {
    spdlog::debug("frame {}: motion model: {} inliers of {} matches", frame.id, inliers, matched);
  }
  return inliers >= options_.min_tracked_matches;
}

bool Tracking::TrackReferenceKeyFrame(Frame& frame) {
  if (!reference_ || !last_frame_ || !last_frame_->T_cw) return false;
  ComputeBow(frame);
  const std::vector<bool> usable = reference_->GoodPointMask();
  MatcherOptions options = matcher_;
  const BowFeatures a{&reference_->feature_vector, &reference_->features.descriptors,
                      &reference_->features.keypoints, &usable};
  const BowFeatures b{&frame.feature_vector, &frame.features.descriptors, &frame.features.keypoints,
                      nullptr};
  const std::vector<int> matches = SearchByBow(a, b, options);
  if (CountMatches(matches) < options_.min_bow_matches) {
    spdlog::debug("frame {}: reference keyframe {}: {} BoW matches", frame.id, reference_->id,
                  CountMatches(matches));
    return false;
  }
  std::fill(frame.points.begin(), frame.points.end(), nullptr);
  for (std::size_t i = 0; i < matches.size(); ++i) {
    if (matches[i] != kNoMatch)
      frame.points[static_cast<std::size_t>(matches[i])] = reference_->points[i];
  }
  frame.T_cw = last_frame_->T_cw;
  return OptimizeFramePose(frame) >= options_.min_tracked_matches;
}

int Tracking::TrackLocalMap(Frame& frame) {
  Map& map = *dependencies_.map;
  // Local keyframes: those that see the frame's points, and their best neighbours.
  std::map<KeyFrameId, int> seen_by;
  for (const MapPointPtr& point : frame.points) {
    if (!point || point->bad) continue;
    for (const auto& [keyframe_id, feature] : point->observations) ++seen_by[keyframe_id];
  }
  std::vector<KeyFramePtr> local;
  std::set<KeyFrameId> in_local;
  KeyFramePtr best;
  int best_count = 0;
  for (const auto& [keyframe_id, count] : seen_by) {
    const KeyFramePtr keyframe = map.GetKeyFrame(keyframe_id);
    if (!keyframe || keyframe->bad) continue;
    local.push_back(keyframe);
    in_local.insert(keyframe_id);
    if (count > best_count) {
      best_count = count;
      best = keyframe;
    }
  }
  const std::size_t direct = local.size();
  for (std::size_t i = 0;
       i < direct && local.size() < static_cast<std::size_t>(options_.local_keyframes); ++i) {
    for (const KeyFramePtr& neighbour : map.BestCovisible(local[i], 10)) {
      if (in_local.insert(neighbour->id).second) local.push_back(neighbour);
    }
  }
  if (best) {
    reference_ = best;
    frame.reference = best;
  }
  // Local points not matched yet, projected with the current pose; each once, however
  // many local keyframes see it (marked with the frame id instead of a set of ids).
  for (const MapPointPtr& point : frame.points) {
    if (point) point->searched_by_frame = frame.id;
  }
  std::vector<ProjectedPoint> projected;
  std::vector<MapPointPtr> sources;
  const double threshold =
      (last_relocalization_frame_id_ > 0 && frame.id < last_relocalization_frame_id_ + 2) ? 5.0
                                                                                          : 1.0;
  for (const KeyFramePtr& keyframe : local) {
    for (const MapPointPtr& point : keyframe->points) {
      if (!point || point->bad || point->searched_by_frame == frame.id) continue;
      point->searched_by_frame = frame.id;
      const auto projection =
          ProjectPoint(camera_, frame.features.grid.bounds(), *frame.T_cw, *point, true);
      if (!projection) continue;
      ++point->visible;
      const int level = pyramid().PredictLevel(projection->distance, point->max_distance);
      ProjectedPoint p;
      p.pixel = projection->pixel;
      p.radius = (projection->view_cos > 0.998 ? 2.5 : 4.0) * threshold *
                 pyramid().scale[static_cast<std::size_t>(level)];
      p.min_level = std::max(0, level - 1);
      p.max_level = level;
      p.descriptor = point->descriptor;
      projected.push_back(p);
      sources.push_back(point);
    }
  }
  const std::vector<bool> taken = MatchedFeatures(frame);
  MatcherOptions options = matcher_;
  options.check_orientation = false;
  const std::vector<int> matches =
      SearchByProjection(frame.features, projected, &taken, matcher_.projection_ratio,
                         matcher_.loose_distance, options);
  AssignMatches(matches, sources, &frame);
  const int inliers = OptimizeFramePose(frame);
  for (const MapPointPtr& point : frame.points) {
    if (point) ++point->found;
  }
  return inliers;
}

std::unique_lock<std::mutex> Tracking::LockMap() const {
  const auto start = std::chrono::steady_clock::now();
  std::unique_lock<std::mutex> lock = dependencies_.map->LockForTracking();
  map_lock_wait_seconds_ +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return lock;
}

bool Tracking::NeedKeyFrame(const Frame& frame, int inliers) const {
  const std::unique_lock<std::mutex> lock = LockMap();
  const std::size_t keyframes =
      dependencies_.map->LiveKeyFrameCount(dependencies_.map->current_map());
  const std::uint64_t max_frames =
      options_.max_frames_between_keyframes > 0
          ? static_cast<std::uint64_t>(options_.max_frames_between_keyframes)
          : static_cast<std::uint64_t>(std::max(1.0, fps_));
  if (last_relocalization_frame_id_ > 0 && frame.id < last_relocalization_frame_id_ + max_frames &&
      keyframes > max_frames) {
    return false;
  }
  if (!reference_) return false;
  const int reference_points = reference_->TrackedPoints(keyframes <= 2 ? 2 : 3);
  const bool waited_long = frame.id >= last_keyframe_frame_id_ + max_frames;
  // ORB-SLAM2 inserts whenever mapping is idle (its mMinFrames is 0) and relies on the
  // mapper being busy for the frames after a keyframe; in sequential mode it never is,
  // so the idle condition waits for min_frames_between_keyframes frames instead.
  const bool mapping_idle =
      local_mapping_idle_() &&
      frame.id >= last_keyframe_frame_id_ +
                      static_cast<std::uint64_t>(options_.min_frames_between_keyframes);
  const bool weak = inliers < options_.keyframe_tracked_ratio * reference_points && inliers > 15;
  return (waited_long || mapping_idle) && weak;
}

KeyFramePtr Tracking::CreateKeyFrame(Frame& frame) {
  ComputeBow(frame);
  auto keyframe = std::make_shared<KeyFrame>();
  keyframe->id = dependencies_.map->NextKeyFrameId();
  keyframe->frame_id = frame.id;
  keyframe->timestamp = frame.timestamp;
  keyframe->timestamp_text = frame.timestamp_text;
  keyframe->T_cw = *frame.T_cw;
  keyframe->features = frame.features;
  keyframe->bow = frame.bow;
  keyframe->feature_vector = frame.feature_vector;
  keyframe->points = frame.points;
  keyframe->map = dependencies_.map->current_map();
  last_keyframe_frame_id_ = frame.id;
  reference_ = keyframe;
  frame.reference = keyframe;
  return keyframe;
}

bool Tracking::Relocalize(Frame& frame) {
  ComputeBow(frame);
  const std::vector<BowQueryResult> candidates =
      dependencies_.database->Query(frame.bow, kRelocalizationCandidates, 1);
  const Eigen::Matrix3d K =
      (Eigen::Matrix3d() << camera_.fx, 0, camera_.cx, 0, camera_.fy, camera_.cy, 0, 0, 1)
          .finished();
  cv::Mat K_cv;
  cv::eigen2cv(K, K_cv);
  for (const BowQueryResult& candidate : candidates) {
    const KeyFramePtr keyframe =
        dependencies_.map->GetKeyFrame(static_cast<KeyFrameId>(candidate.id));
    if (!keyframe || keyframe->bad) continue;
    const std::vector<bool> usable = keyframe->GoodPointMask();
    MatcherOptions options = matcher_;
    options.bow_ratio = kRelocalizationRatio;
    const std::vector<int> matches = SearchByBow(
        {&keyframe->feature_vector, &keyframe->features.descriptors, &keyframe->features.keypoints,
         &usable},
        {&frame.feature_vector, &frame.features.descriptors, &frame.features.keypoints, nullptr},
        options);
    if (CountMatches(matches) < options_.min_bow_matches) continue;
    std::vector<cv::Point3f> object;
    std::vector<cv::Point2f> image;
    std::vector<std::pair<int, MapPointPtr>> pairs;
    for (std::size_t i = 0; i < matches.size(); ++i) {
      if (matches[i] == kNoMatch) continue;
      const Eigen::Vector3d& X = keyframe->points[i]->position;
      const Eigen::Vector2d& x = frame.features.undistorted[static_cast<std::size_t>(matches[i])];
      object.emplace_back(static_cast<float>(X.x()), static_cast<float>(X.y()),
                          static_cast<float>(X.z()));
      image.emplace_back(static_cast<float>(x.x()), static_cast<float>(x.y()));
      pairs.emplace_back(matches[i], keyframe->points[i]);
    }
    // OpenCV's RANSAC draws from cv::theRNG(): seed it so that relocalization repeats.
    cv::theRNG().state = 0x9E3779B97F4A7C15ull ^ frame.id;
    cv::Mat rvec, tvec;
    std::vector<int> inliers;
    if (!cv::solvePnPRansac(object, image, K_cv, cv::noArray(), rvec, tvec, false, 300, 4.0, 0.99,
                            inliers, cv::SOLVEPNP_EPNP) ||
        static_cast<int>(inliers.size()) < options_.min_tracked_matches) {
      continue;
    }
    cv::Mat R_cv;
    cv::Rodrigues(rvec, R_cv);
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    cv::cv2eigen(R_cv, R);
    cv::cv2eigen(tvec, t);
    frame.T_cw = SE3(R, t);
    std::fill(frame.points.begin(), frame.points.end(), nullptr);
    for (const int index : inliers) {
      frame.points[static_cast<std::size_t>(pairs[static_cast<std::size_t>(index)].first)] =
          pairs[static_cast<std::size_t>(index)].second;
    }
    int good = OptimizeFramePose(frame);
    if (good < options_.min_tracked_matches) continue;
    if (good < options_.min_inliers_after_relocalization) {
      // Guided search: the candidate's other points, projected with the new pose.
      std::vector<ProjectedPoint> projected;
      std::vector<MapPointPtr> sources;
      for (const MapPointPtr& point : keyframe->points) {
        if (!point || point->bad) continue;
        if (std::find(frame.points.begin(), frame.points.end(), point) != frame.points.end())
          continue;
        const auto projection =
            ProjectPoint(camera_, frame.features.grid.bounds(), *frame.T_cw, *point, true);
        if (!projection) continue;
        projected.push_back(SearchWindow(*projection, *point, pyramid(), 10.0));
        sources.push_back(point);
      }
      const std::vector<bool> taken = MatchedFeatures(frame);
      const std::vector<int> extra = SearchByProjection(frame.features, projected, &taken, 0.9,
                                                        matcher_.loose_distance, matcher_);
      AssignMatches(extra, sources, &frame);
      good = OptimizeFramePose(frame);
    }
    if (good >= options_.min_inliers_after_relocalization) {
      reference_ = keyframe;
      if (keyframe->map != dependencies_.map->current_map()) {
        // The place is in another map of the atlas: tracking goes on in that one.
        spdlog::info("frame {}: relocalized in map {}, which becomes current (was map {})",
                     frame.id, keyframe->map, dependencies_.map->current_map());
        dependencies_.map->SetCurrentMap(keyframe->map);
      }
      spdlog::info("frame {}: relocalized against keyframe {} with {} inliers", frame.id,
                   keyframe->id, good);
      return true;
    }
  }
  frame.T_cw.reset();
  return false;
}

void Tracking::Anchor(const Frame& frame, const KeyFramePtr& keyframe) {
  if (!frame.T_cw || !keyframe) return;
  anchor_.keyframe = keyframe;
  anchor_.T_c_keyframe = *frame.T_cw * keyframe->T_cw.Inverse();
  anchor_.map = keyframe->map;
  anchor_.corrections = dependencies_.map->corrections();
}

void Tracking::FollowCorrections(Frame& frame) {
  const std::uint64_t corrections = dependencies_.map->corrections();
  if (corrections == anchor_.corrections) return;
  // Placed again on the same keyframe: the relative pose, its map and units stay.
  anchor_.corrections = corrections;
  if (!frame.T_cw) return;
  if (const std::optional<SE3> T_cw = AnchoredPoseNow()) {
    frame.T_cw = *T_cw;
    spdlog::debug("frame {}: the map was corrected; re-anchored on keyframe {}", frame.id,
                  anchor_.keyframe->id);
  }
}

std::optional<SE3> Tracking::AnchoredPoseNow() const {
  if (!anchor_.keyframe) return std::nullopt;
  const std::optional<AnchoredPose> pose = PoseFromAnchor(*dependencies_.map, anchor_);
  if (!pose) return std::nullopt;
  return pose->T_cw;
}

bool Tracking::MapMovedSinceLastFrame() const {
  return dependencies_.map->corrections() != anchor_.corrections;
}

std::optional<SE3> Tracking::LastFramePoseNow() const {
  if (!last_frame_ || !last_frame_->T_cw) return std::nullopt;
  if (!MapMovedSinceLastFrame() || !anchor_.keyframe) return last_frame_->T_cw;
  return AnchoredPoseNow();
}

void Tracking::ReanchorLastFrame() {
  if (dependencies_.map->merges() != anchored_merges_) {
    // The map was merged into another, of other units: the motion model's step too.
    anchored_merges_ = dependencies_.map->merges();
    if (velocity_) {
      velocity_ = SE3(velocity_->rotation(),
                      velocity_->translation() * dependencies_.map->last_merge_scale());
    }
  }
  if (last_frame_) {
    FollowCorrections(*last_frame_);
  } else {
    anchor_.corrections = dependencies_.map->corrections();
  }
}

void Tracking::StartInLoadedMap(std::uint64_t first_frame_id) {
  state_ = TrackingState::kLost;
  map_loaded_ = true;
  next_frame_id_ = first_frame_id;
}

void Tracking::Reset(bool keep_map) {
  {
    std::lock_guard<std::mutex> lock(dependencies_.map->mutex());
    Map& map = *dependencies_.map;
    if (keep_map) {
      map.StartNewMap();
    } else if (map.map_count() == 1) {
      map.Clear();  // the only map: ids start over too
      dependencies_.database->Clear();
    } else {
      for (const KeyFrameId id : map.EraseMap(map.current_map()))
        dependencies_.database->Erase(static_cast<int>(id));
    }
  }
  state_ = TrackingState::kNotInitialized;
  frames_lost_ = 0;
  initial_frame_.reset();
  last_frame_.reset();
  velocity_.reset();
  reference_.reset();
  anchor_ = ocg::Anchor();
}

}  // namespace ocg
