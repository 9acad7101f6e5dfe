#pragma once
// Tracking: one call per image, on the caller's thread. Initializes the map from two
// views, then tracks with the constant-velocity motion model (falling back to BoW
// matching against the reference keyframe), refines with the local map, decides on new
// keyframes, and relocalizes through the keyframe database when lost.

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ocg/core/option_fields.h"
#include "ocg/features/bow_database.h"
#include "ocg/features/matcher.h"
#include "ocg/features/orb_extractor.h"
#include "ocg/features/vocabulary.h"
#include "ocg/optim/bundle_adjustment.h"
#include "ocg/slam/initialization_report.h"
#include "ocg/slam/initializer.h"
#include "ocg/slam/map.h"

namespace ocg {

class SettingsFile;

// Tracking.* settings (defaults: ORB-SLAM2's monocular values).
struct TrackingOptions {
  int min_initialization_features = 100;  // Tracking.minInitFeatures: per view
  int min_initialization_matches = 100;   // Tracking.minInitMatches
  // Tracking.initFeaturesFactor: until the map exists, extract this many times
  // ORBextractor.nFeatures (window matching uses level 0 only, so it needs more).
  double initialization_features_factor = 2.0;
  double motion_search_radius = 15.0;         // Tracking.motionSearchRadius: pixels at level 0
  int min_motion_matches = 20;                // Tracking.minMotionMatches: else widen the search
  int min_tracked_matches = 10;               // Tracking.minTrackedMatches: after pose optimization
  int min_bow_matches = 15;                   // Tracking.minBowMatches
  int min_local_map_inliers = 30;             // Tracking.minLocalMapInliers
  int min_inliers_after_relocalization = 50;  // Tracking.minRelocalizationInliers
  double keyframe_tracked_ratio = 0.9;        // Tracking.keyframeRatio: of the reference's points
  int max_frames_between_keyframes = 0;       // Tracking.maxFramesBetweenKeyFrames (0: fps)
  // Tracking.minFramesBetweenKeyFrames: while local mapping is idle, a weak frame becomes
  // a keyframe only this many frames after the last one. ORB-SLAM2 has 0 and counts on
  // its mapper still being busy during the frame after a keyframe (a local BA takes
  // longer than a frame period); in sequential mode the mapper finishes before the next
  // frame, and 0 made nearly every frame a keyframe under forward motion (KITTI 07: 130
  // keyframes for 155 frames). 2 stands for that busy frame in both modes.
  int min_frames_between_keyframes = 2;
  int min_keyframes_to_keep_map = 5;  // Tracking.minKeyFrames: reset when lost below
  // Tracking.newMapAfterLostSeconds: lost this long in a bigger map without relocalizing,
  // tracking starts a new map (the old one is kept, ORB-SLAM3's Atlas); 0: never, keep
  // trying to relocalize.
  double new_map_after_lost_seconds = 2.0;
  int local_keyframes = 80;  // Tracking.localKeyFrames: at most

  // The settings keys, once (ocg/core/option_fields.h).
  template <typename Self, typename Visitor>
  static void VisitFields(Self& self, Visitor&& visit) {
    visit("Tracking.minInitFeatures", self.min_initialization_features, OptionBound::AtLeast(8),
          "features per view needed to try initialization");
    visit("Tracking.minInitMatches", self.min_initialization_matches, OptionBound::AtLeast(8),
          "window matches needed to try initialization");
    visit("Tracking.initFeaturesFactor", self.initialization_features_factor,
          OptionBound::AtLeast(1), "until the map exists, extract this many times `nFeatures`");
    visit("Tracking.motionSearchRadius", self.motion_search_radius, OptionBound::Positive(),
          "pixels (times the level's scale) around the motion model's prediction");
    visit("Tracking.minMotionMatches", self.min_motion_matches, OptionBound::AtLeast(4),
          "fewer: search again with twice the radius, then fall back to BoW");
    visit("Tracking.minTrackedMatches", self.min_tracked_matches, OptionBound::AtLeast(4),
          "inliers after pose optimization for the motion model / BoW / PnP stage");
    visit("Tracking.minBowMatches", self.min_bow_matches, OptionBound::AtLeast(4),
          "BoW matches with the reference keyframe or a relocalization candidate");
    visit("Tracking.minLocalMapInliers", self.min_local_map_inliers, OptionBound::AtLeast(4),
          "inliers after tracking the local map (else lost)");
    visit("Tracking.minRelocalizationInliers", self.min_inliers_after_relocalization,
          OptionBound::AtLeast(4), "the same, during the second after a relocalization");
    visit("Tracking.keyframeRatio", self.keyframe_tracked_ratio,
          OptionBound::Between(0, true, 1, false),
          "new keyframe when tracked inliers fall below this share of the reference "
          "keyframe's points");
    visit("Tracking.maxFramesBetweenKeyFrames", self.max_frames_between_keyframes,
          OptionBound::NonNegative(), "0: one camera second (`Camera.fps`)");
    visit("Tracking.minFramesBetweenKeyFrames", self.min_frames_between_keyframes,
          OptionBound::NonNegative(),
          "while local mapping is idle, a keyframe at the earliest this many frames after the "
          "last (ORB-SLAM2's 0 relies on a mapper still busy with the last keyframe; "
          "sequential mode never is)");
    visit("Tracking.minKeyFrames", self.min_keyframes_to_keep_map, OptionBound::AtLeast(2),
          "lost with at most this many live keyframes (culled ones do not count): reset the "
          "map");
    visit("Tracking.localKeyFrames", self.local_keyframes, OptionBound::AtLeast(2),
          "local map size at most");
    visit("Tracking.newMapAfterLostSeconds", self.new_map_after_lost_seconds,
          OptionBound::NonNegative().Because("0: never start a new map"),
          "lost this long (camera time) in a map of more than `minKeyFrames` live keyframes "
          "without relocalizing: start a new map, keeping the old one's trajectory "
          "([slam.md](slam.md))");
  }
  // Throws OptionError naming the key.
  void Check() const;
};

void ReadSettings(const SettingsFile& file, TrackingOptions* options);

enum class TrackingState { kNoImages, kNotInitialized, kOk, kLost };
const char* ToString(TrackingState state);

// One image's features and what tracking found in it.
struct Frame {
  std::uint64_t id = 0;
  double timestamp = 0.0;
  std::string timestamp_text;
  ExtractedFeatures features;
  BowVector bow;
  FeatureVector feature_vector;
  bool has_bow = false;
  std::vector<MapPointPtr> points;  // per feature
  std::vector<bool> outlier;
  std::optional<SE3> T_cw;
  KeyFramePtr reference;
};

// A map point matched in the tracked frame: what the object layer reads of the map.
struct TrackedPoint {
  MapPointId id = 0;
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();     // undistorted keypoint
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // world, as tracked
};

struct TrackingResult {
  TrackingState state = TrackingState::kNoImages;
  std::optional<SE3> T_cw;
  std::vector<TrackedPoint> points;  // tracked frames: the map points matched (inliers)
  bool new_keyframe = false;
  bool relocalized = false;
  // Lost with too small a map: the owner must stop local mapping and call Reset().
  bool reset = false;
  // Lost too long in a bigger map: the owner keeps what it needs of the map (its
  // trajectory), stops local mapping and calls Reset(); tracking initializes a new map.
  // Poses before and after are in different frames (and scales).
  bool new_map = false;
  // Relocalized in another map of the atlas, which became current (poses before and
  // after are in different frames).
  bool switched_map = false;
  // Set by System: a merge moved the current map into another map's frame during this
  // frame (in threaded mode: since the last frame was recorded); this frame's pose and
  // points are in the merged frame, poses before are in the old frame.
  bool merged = false;
  int inliers = 0;
  // Time spent waiting for the map lock while tracking this frame [s]: in threaded mode,
  // while local mapping or loop closing held it.
  double map_lock_wait_seconds = 0.0;
};

struct TrackingDependencies {
  const Vocabulary* vocabulary = nullptr;
  BowDatabase* database = nullptr;
  Map* map = nullptr;
};

class Tracking {
 public:
  // keyframe_sink receives each new keyframe (local mapping's queue, or a synchronous
  // call in sequential mode); it is called without the map lock held, and returns true
  // when it closed a loop (the keyframe's pose was corrected: the frame takes it).
  Tracking(const PinholeCamera& camera, double fps, const OrbExtractorOptions& orb,
           const MatcherOptions& matcher, const InitialMapOptions& initializer,
           const TrackingOptions& options, TrackingDependencies dependencies,
           std::function<bool(const KeyFramePtr&)> keyframe_sink,
           std::function<bool()> local_mapping_idle);

  // features: the image's ORB features made by an extractor with this tracking's options
  // (System::MakeFeatureExtractor), e.g. on a reader thread while the previous frame was
  // tracked; null: extracted here. While not initialized tracking extracts its own even
  // when given some, with Tracking.initFeaturesFactor times more features.
  TrackingResult Track(const cv::Mat& image, double timestamp, const std::string& timestamp_text,
                       const ExtractedFeatures* features = nullptr);
  TrackingState state() const { return state_; }
  // Every frame given while not initialized, and why it did not initialize.
  const InitializationAttempts& initialization_attempts() const { return initialization_; }
  // Starts over in a new map: keep_map keeps the current one in the atlas (Map's maps;
  // its keyframes stay in the database, for relocalization and merges), else it is erased
  // with its database entries (a reset of a young map). Other maps are kept either way.
  // Call with local mapping stopped or idle.
  void Reset(bool keep_map = false);
  // The map was loaded from a map file, not made here: tracking starts lost, relocalizes
  // in it, and never resets it however long relocalization fails (no second map is
  // initialized beside it). Frame ids continue from first_frame_id, after the saved
  // keyframes'. Call before the first Track().
  void StartInLoadedMap(std::uint64_t first_frame_id);
  const ScalePyramid& pyramid() const { return extractor_.pyramid(); }
  // The features of the last frame tracked (null before one was), until the next Track().
  const ExtractedFeatures* LastFrameFeatures() const {
    return last_frame_ ? &last_frame_->features : nullptr;
  }
  // The last frame tracked, placed as the map now stands (call with Map::mutex() held): its
  // tracked pose, or, when the loop closing thread moved the map since Track() placed it,
  // where its keyframe took it (through a merge: into the other map's frame). None before
  // a frame was tracked or when its keyframe is gone.
  std::optional<SE3> LastFramePoseNow() const;
  // Whether the map was moved since the last frame was placed (Map::mutex() held).
  bool MapMovedSinceLastFrame() const;

 private:
  bool Initialize(Frame& frame);
  void RecordTooFewFeatures(const Frame& frame);
  bool TrackWithMotionModel(Frame& frame);
  bool TrackReferenceKeyFrame(Frame& frame);
  bool Relocalize(Frame& frame);
  int TrackLocalMap(Frame& frame);
  int OptimizeFramePose(Frame& frame);
  bool NeedKeyFrame(const Frame& frame, int inliers) const;
  // The map lock, its waiting time added to map_lock_wait_seconds_.
  std::unique_lock<std::mutex> LockMap() const;
  KeyFramePtr CreateKeyFrame(Frame& frame);
  void ComputeBow(Frame& frame) const;
  void UpdateLastFramePoints();
  // Remembers where the frame stands relative to keyframe (call under the map lock).
  void Anchor(const Frame& frame, const KeyFramePtr& keyframe);
  // A loop correction or global adjustment (another thread's, in threaded mode) moved the
  // map since the last frame was placed: the last frame moves with its keyframe, or the
  // motion model would predict from where the map no longer is. Under the map lock.
  void ReanchorLastFrame();
  // The same for the frame being tracked (anchored), at each step that uses its pose with
  // the map under a lock taken since it was placed (a new keyframe, the points it reports):
  // in threaded mode the loop closing thread may have moved the map in between.
  void FollowCorrections(Frame& frame);
  // The anchored frame's pose as the map stands now (PoseFromAnchor); none without an
  // anchor or when its keyframe is gone. Under the map lock.
  std::optional<SE3> AnchoredPoseNow() const;

  PinholeCamera camera_;
  double fps_;
  OrbExtractor extractor_;
  OrbExtractor initialization_extractor_;
  MatcherOptions matcher_;
  InitialMapOptions initializer_;
  TrackingOptions options_;
  TrackingDependencies dependencies_;
  std::function<bool(const KeyFramePtr&)> keyframe_sink_;
  std::function<bool()> local_mapping_idle_;
  PoseOptimizationOptions pose_options_;

  TrackingState state_ = TrackingState::kNoImages;
  std::uint64_t next_frame_id_ = 0;
  std::unique_ptr<Frame> initial_frame_;
  InitializationAttempts initialization_;
  mutable double map_lock_wait_seconds_ = 0.0;  // of the frame being tracked
  std::vector<Eigen::Vector2d>
      initial_predicted_;  // where the first view's features were last seen
  std::unique_ptr<Frame> last_frame_;
  std::optional<SE3> velocity_;  // T_current_last
  KeyFramePtr reference_;
  // The last frame's keyframe, its pose relative to it and Map::corrections() when it was
  // placed.
  ocg::Anchor anchor_;
  int anchored_merges_ = 0;  // Map::merges() then
  std::uint64_t last_keyframe_frame_id_ = 0;
  std::uint64_t last_relocalization_frame_id_ = 0;
  int frames_lost_ = 0;  // in a row, in this map
  bool map_loaded_ = false;
};

}  // namespace ocg
