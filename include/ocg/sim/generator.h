#pragma once
// Renders a scene into a TUM-format sequence with YOLO-like detections and ground truth.
//
// Threading: everything here runs on the calling thread (one OSMesa context).

#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "ocg/io/detections.h"
#include "ocg/render/renderer.h"
#include "ocg/sim/detector.h"
#include "ocg/sim/look.h"
#include "ocg/sim/presets.h"
#include "ocg/sim/scene.h"

namespace ocg::sim {

// The scene's meshes and textures on a renderer; renders any time and pose.
class SceneRenderer {
 public:
  explicit SceneRenderer(const Scene& scene);

  // Colour image (deterministic in noise_seed). Procedural look: mild sensor noise.
  // Realistic look: what the camera records over its exposure around t, the camera
  // moving as the scene's path does around T_cw; the auto-exposure adapts from call to
  // call, so a sequence is rendered with calls in frame order.
  cv::Mat Colour(double t, const SE3& T_cw, std::uint64_t noise_seed);
  // Object ids per pixel (scene object ids; furniture and background are 0), through the
  // output camera's lens at time t (no blur).
  cv::Mat Ids(double t, const SE3& T_cw, cv::Mat* depth = nullptr);
  // The realistic camera (nullptr for the procedural look).
  const CameraSensor* sensor() const { return sensor_.get(); }
  // Pixels of object_id visible from T_cw if it stood at pose (the rest of the scene as
  // at time t, the object's other poses hidden).
  int VisiblePixels(int object_id, const PlacedPose& pose, double t, const SE3& T_cw);
  const Scene& scene() const { return scene_; }
  // Appends a pose to an object's history (a change just scheduled), so later renders
  // and visibility checks see it.
  void AppendPose(int object_id, const PlacedPose& pose);
  // Undoes the last AppendPose of an object (a change tried and given up).
  void PopPose(int object_id);
  // The pixels that show a walker at time t from T_cw (CV_8UC1, 255 there), through the
  // output camera's lens; all 0 without walkers.
  cv::Mat WalkerMask(double t, const SE3& T_cw);
  // Share of the output image's pixels that show a walker (WalkerMask's share).
  double WalkerCoverage(double t, const SE3& T_cw);

 private:
  // Every item standing at time t, object skip_object left out; the walkers' items are
  // made for t (valid until the next call), with id kWalkerPixelId when mark_walkers, else
  // 0 (background to the id pass).
  std::vector<const DrawItem*> ItemsAt(double t, int skip_object, bool mark_walkers = false);
  cv::Mat RealisticColour(double t, const SE3& T_cw, std::uint64_t noise_seed);
  DrawItem MakeObjectItem(const SceneObject& object, const PlacedPose& pose);

  Scene scene_;
  std::unique_ptr<CameraSensor> sensor_;
  PinholeCamera render_camera_;  // pinhole; wider than the output with a distorting lens
  Renderer renderer_;
  std::vector<DrawItem> furniture_;
  std::map<int, std::vector<DrawItem>> object_items_;  // per object, one per history entry
  std::map<int, int> object_textures_;
  std::map<int, int> walker_textures_;
  std::map<int, Mesh> walker_bodies_;   // per walker, in its own frame
  std::vector<DrawItem> walker_items_;  // ItemsAt's walkers at its last time
  cv::Mat noise_tile_;                  // sensor noise, twice the image size
};

// Turns planned moves into history entries, each at the first frame from its earliest
// time at which neither the old nor the new place is visible (checked by rendering, one
// frame before and after, with the changes scheduled before it in place). renderer must
// have been made from scene.
// When that first pass fails (a move with no unseen moment, or a change scheduled earlier
// in time than one before it that makes the earlier-listed one visible, e.g. by removing
// its occluder), a careful pass starts again: a moment is taken only if every change
// already scheduled after it stays unseen, and a move with no such moment gives way to its
// alternatives (PlannedMove::alternatives) in order. Scenes the first pass makes are kept
// byte for byte. Throws std::runtime_error when the careful pass fails too.
void ScheduleMoves(Scene& scene, const std::vector<PlannedMove>& moves, SceneRenderer& renderer);

// Refuses (std::invalid_argument naming object and time) a scene whose changes happen
// while the old or the new place is visible.
void ValidateChanges(const Scene& scene, SceneRenderer& renderer);

// The YOLO-like detector (SPEC 2 format); deterministic in the scene seed and frame.
// scene.noise.kind chooses the independent model or the realistic one (detector.h); the
// realistic one has memory, so frames are detected in order.
class DetectionModel {
 public:
  explicit DetectionModel(const Scene& scene);

  struct FrameResult {
    std::vector<Detection> detections;
    int visible = 0;                   // objects with enough visible pixels
    std::vector<int> visible_objects;  // their scene ids (boxed or not)
    int missed = 0;
    int false_positives = 0;
    int duplicates = 0;
    int confused = 0;
    std::vector<int> detected_objects;  // scene ids behind the true detections
  };
  FrameResult Detect(const cv::Mat& ids, double t, const SE3& T_cw, int frame);

 private:
  const Scene& scene_;
  std::map<int, bool> missed_last_frame_;
  std::optional<RealisticDetector> realistic_;
};

struct GeneratorOptions {
  int max_frames = 0;  // 0: the whole scene
  bool write_depth = false;
  // false: no rgb/, rgb.txt or depth (the id pass alone feeds the detections): a fast way
  // to measure a detector model over whole sequences.
  bool write_images = true;
  bool overwrite = false;  // replace an existing output folder
  // Every N-th frame is a keyframe of oracle_observations.jsonl (0: no file).
  int keyframe_interval = 10;
};

struct GenerationStats {
  int frames = 0;
  double seconds = 0.0;
  std::size_t detections = 0;
  std::size_t visible = 0;
  std::size_t missed = 0;
  std::size_t false_positives = 0;
  std::size_t duplicates = 0;
  // Seconds spent per stage, over all frames.
  double colour_seconds = 0.0, ids_seconds = 0.0, detect_seconds = 0.0, write_seconds = 0.0;
  // Walkers (scenes with any): frames showing one, frames where they cover at least a
  // quarter of the image, and the largest share they cover (walkers.txt has every frame's).
  int walker_frames = 0;
  int walker_quarter_frames = 0;
  double walker_coverage_max = 0.0;
};

// Writes the sequence into out_dir (built in a temporary folder beside it and renamed at
// the end, so a failure leaves nothing half-written). Throws on an existing non-empty
// out_dir unless overwrite.
GenerationStats Generate(const Scene& scene, const std::string& out_dir,
                         const GeneratorOptions& options);
// The same with a renderer already made for the scene (the one ScheduleMoves used), so the
// textures are not generated twice.
GenerationStats Generate(SceneRenderer& renderer, const std::string& out_dir,
                         const GeneratorOptions& options);

// Oracle map ids: object id * kOracleIdStride + index of its pose in the history, so an
// object seen at a new place is a new map object, as a real object map would make it.
constexpr std::int64_t kOracleIdStride = 100;
std::int64_t OracleMapId(int object_id, std::size_t pose_index);
// One ocg_replay input line: ground-truth pose, the objects truly detected in the frame.
std::string OracleObservation(const Scene& scene, std::int64_t keyframe, double t, const SE3& T_cw,
                              const std::vector<int>& detected_objects);

// Per object id, per entry of its history (this visit's, in order): the number of rendered
// frames in which the object, at that placement, showed at least noise.min_visible_pixels
// pixels (the least the detector boxes).
using FramesInView = std::map<int, std::vector<int>>;

// objects_gt.json text for the scene; for a later visit, each changed object's history
// starts with its pose when the previous visit ended, and "session" lists the changes
// between the visits (docs/sessions.md). With frames_in_view, each of this visit's history
// entries carries "frames_in_view" (an object never in view is in no list a person would
// make from the frames; `ocg_eval objects` leaves such places out). Changes after
// end_time (seconds from the start: the last rendered frame's time) did not happen in the
// rendered sequence and are left out.
std::string ObjectsGroundTruthJson(const Scene& scene, const FramesInView* frames_in_view = nullptr,
                                   double end_time = std::numeric_limits<double>::infinity());
// A settings file (our format) for the rendered camera.
std::string CameraSettingsYaml(const Scene& scene);
// Timestamp text of a frame ("1000.033333").
std::string FrameTimestamp(const Scene& scene, int frame);

}  // namespace ocg::sim
