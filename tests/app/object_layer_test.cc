// The object layer of a SLAM run (ObjectLayer, src/app), driven as ObjectSlam::Track drives
// it: every frame's tracking result (pose, tracked points, new SLAM keyframes) with its
// detections and its colour image, then Finish() and the outputs. SLAM itself is not run:
// the system is idle (no keyframes, no map points), so the objects keep the sightings'
// poses, and the world is turned as a SLAM world is (the first camera's: up is -y).

#include "object_layer.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <filesystem>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "ocg/app/pose_given.h"
#include "ocg/core/file_io.h"
#include "ocg/io/detection_source.h"
#include "ocg/objects/object_change.h"
#include "synthetic_scene.h"
#include "test_support.h"

namespace ocg {
namespace {

// The synthetic world (z up) turned so that up is -y, as in a SLAM map started upright.
const Eigen::Matrix3d kSlamFromScene =
    Eigen::AngleAxisd(0.5 * 3.14159265358979323846, Eigen::Vector3d::UnitX()).toRotationMatrix();

Settings LayerSettings(const testing::SyntheticScene& scene) {
  Settings settings;
  settings.camera.model = scene.options.camera;
  settings.system.sequential = true;
  settings.ocg.mode = "paper";
  settings.objects.keyframe_interval = 5;
  return settings;
}

enum class Images { kNone, kFiles, kPixels };

// The keyframe images as files, as `ocg_slam run` names them (the frame's index).
std::vector<std::string> WriteImages(const testing::CarriedCups& cups,
                                     const testing::SyntheticScene& scene,
                                     const std::string& folder) {
  std::vector<std::string> paths;
  for (int frame = 0; frame < scene.options.frames; ++frame) {
    paths.push_back(folder + "/" + std::to_string(frame) + ".png");
    cv::imwrite(paths.back(), cups.ColourImage(scene, static_cast<std::size_t>(frame)));
  }
  return paths;
}

struct LayerRun {
  nlohmann::json section;  // run.json's "objects"
  std::vector<ChangeEntry> changes;
};

// Every frame into an ObjectLayer as ObjectSlam::Track gives it (a SLAM keyframe every
// third frame); images: none, files (grey pixels given, the file named: ocg_slam run) or
// BGR pixels without a file (the library with colour frames).
LayerRun RunLayer(const testing::CarriedCups& cups, const testing::SyntheticScene& scene,
                  Images images, const std::vector<std::string>& paths) {
  const Settings settings = LayerSettings(scene);
  const Vocabulary vocabulary;
  const System system(MakeSystemConfig(settings), vocabulary);
  app_detail::ObjectLayer layer(settings, true, false);
  const SE3 scene_from_slam(Eigen::Matrix3d(kSlamFromScene.transpose()), Eigen::Vector3d::Zero());
  for (int frame = 0; frame < scene.options.frames; ++frame) {
    const auto f = static_cast<std::size_t>(frame);
    TrackingResult result;
    result.state = TrackingState::kOk;
    result.T_cw = scene.T_cw[f] * scene_from_slam;
    result.new_keyframe = frame % 3 == 0;
    for (const testing::SyntheticProjection& seen : scene.projections[f]) {
      result.points.push_back(
          {static_cast<MapPointId>(seen.point), seen.pixel,
           kSlamFromScene * scene.points[static_cast<std::size_t>(seen.point)]});
    }
    cv::Mat pixels;
    std::string path;
    if (images == Images::kPixels) pixels = cups.ColourImage(scene, f);
    if (images == Images::kFiles) {
      cv::cvtColor(cups.ColourImage(scene, f), pixels, cv::COLOR_BGR2GRAY);
      path = paths[f];
    }
    app_detail::FrameColourImage colour(path, pixels);
    layer.AddFrame(system, result, frame, scene.timestamps[f], scene.detections[f], colour);
  }
  layer.Finish(system);
  return {layer.Write(testing::MakeTempDir("object_layer_out")),
          ParseChangeLog(layer.Changes(), "the layer's change log")};
}

// Each move from the cup place of its removal to that of its newcomer (scene coordinates).
std::map<std::size_t, std::size_t> Moves(const testing::CarriedCups& cups,
                                         const std::vector<ChangeEntry>& changes,
                                         const Eigen::Matrix3d& scene_from_run) {
  std::map<std::size_t, std::size_t> moves;
  for (const ChangeEntry& entry : changes) {
    if (entry.type != "moved") continue;
    EXPECT_TRUE(entry.to.has_value());
    if (!entry.to) continue;
    moves[cups.PlaceOf(scene_from_run * entry.cuboid.centre)] =
        cups.PlaceOf(scene_from_run * entry.to->cuboid.centre);
  }
  return moves;
}

// Two cups of one class and size, red and blue, carried past each other in the first
// session of a SLAM run: each keyframe's sightings take their colours as they are made,
// the cups removed keep theirs, and the first session's change log pairs the moves by
// colour; without images the nearer newcomers are taken (crossed). The colours come alike
// from the files (grey pixels given) and from BGR pixels.
// A keyframe moved when a point one map unit in front of it moved more than the
// tolerance: its centre's shift plus its turn (radians) times the unit, whichever way.
TEST(ObjectLayer, AKeyframeMovedWhenItsShiftPlusTurnExceedsTheTolerance) {
  KeyFrameState before;
  before.live = true;
  before.R_wc = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitY()).toRotationMatrix();
  before.t_wc = Eigen::Vector3d(1.0, -2.0, 0.5);
  const auto moved_by = [&](const Eigen::Vector3d& shift, double turn) {
    KeyFrameState now = before;
    now.t_wc += shift;
    now.R_wc = before.R_wc * Eigen::AngleAxisd(turn, Eigen::Vector3d(1, 1, 0).normalized());
    return now;
  };
  EXPECT_FALSE(app_detail::KeyframeMoved(before, before, 0.0));
  EXPECT_FALSE(app_detail::KeyframeMoved(before, moved_by({0.0004, 0, 0}, 0.0), 0.001));
  EXPECT_FALSE(app_detail::KeyframeMoved(before, moved_by({0, 0.0004, 0}, 0.0004), 0.001));
  EXPECT_TRUE(app_detail::KeyframeMoved(before, moved_by({0, 0, 0.0012}, 0.0), 0.001));
  EXPECT_TRUE(app_detail::KeyframeMoved(before, moved_by({0, 0, 0}, 0.0012), 0.001));
  EXPECT_TRUE(
      app_detail::KeyframeMoved(before, moved_by({0.0006, 0, 0}, 0.0006), 0.001));   // the sum
  EXPECT_TRUE(app_detail::KeyframeMoved(before, moved_by({1e-9, 0, 0}, 0.0), 0.0));  // 0: any move
}

TEST(ObjectLayer, MovesInTheFirstSessionOfASlamRunFollowTheObjectsColours) {
  const testing::CarriedCups cups = testing::CupsCarriedPastEachOther();
  const testing::SyntheticScene scene = testing::SynthesizeScene(cups.options);
  const std::vector<std::string> paths =
      WriteImages(cups, scene, testing::MakeTempDir("object_layer_images"));
  const Eigen::Matrix3d scene_from_slam = kSlamFromScene.transpose();
  const std::map<std::size_t, std::size_t> right = {{cups.red, cups.red_moved},
                                                    {cups.blue, cups.blue_moved}};
  const std::map<std::size_t, std::size_t> crossed = {{cups.red, cups.blue_moved},
                                                      {cups.blue, cups.red_moved}};
  const LayerRun files = RunLayer(cups, scene, Images::kFiles, paths);
  const nlohmann::json& colours = files.section["colour_signatures"];
  EXPECT_GT(colours["keyframe_images"].get<int>(), 0);
  EXPECT_GT(colours["sightings"].get<int>(), colours["keyframe_images"].get<int>());
  EXPECT_EQ(colours["unreadable_images"].get<int>(), 0);
  EXPECT_EQ(Moves(cups, files.changes, scene_from_slam), right);

  const LayerRun pixels = RunLayer(cups, scene, Images::kPixels, paths);
  EXPECT_EQ(pixels.section["colour_signatures"]["sightings"], colours["sightings"]);
  EXPECT_EQ(Moves(cups, pixels.changes, scene_from_slam), right);

  const LayerRun blind = RunLayer(cups, scene, Images::kNone, paths);
  EXPECT_EQ(blind.section["colour_signatures"]["keyframe_images"].get<int>(), 0);
  EXPECT_EQ(Moves(cups, blind.changes, scene_from_slam), crossed);
}

// The pose-given runner (`ocg_slam objects --frames`) and a SLAM run's layer colour the
// same keyframes' sightings from the same images: the same counts, the same moves.
TEST(ObjectLayer, ColoursTheKeyframesThePoseGivenRunnerColours) {
  const testing::CarriedCups cups = testing::CupsCarriedPastEachOther();
  const testing::SyntheticScene scene = testing::SynthesizeScene(cups.options);
  const std::vector<std::string> paths =
      WriteImages(cups, scene, testing::MakeTempDir("object_layer_images"));
  const LayerRun slam = RunLayer(cups, scene, Images::kFiles, paths);

  std::vector<PoseGivenFrame> frames;
  std::unordered_map<std::string, std::vector<Detection>> boxes;
  for (int frame = 0; frame < scene.options.frames; ++frame) {
    const auto f = static_cast<std::size_t>(frame);
    frames.push_back({std::to_string(frame), scene.timestamps[f], scene.T_cw[f], paths[f]});
    boxes[frames.back().timestamp_text] = scene.detections[f];
  }
  InMemoryDetectionSource detections(std::move(boxes));
  const std::string folder = testing::MakeTempDir("object_layer_pose_given");
  const nlohmann::json report = MapObjectsAlongTrajectory(LayerSettings(scene), frames, detections,
                                                          folder, nullptr, nullptr, {false, 0});
  const nlohmann::json& colours = report["colour_signatures"];
  EXPECT_GT(colours["sightings"].get<int>(), 0);
  EXPECT_EQ(colours["keyframe_images"], slam.section["colour_signatures"]["keyframe_images"]);
  EXPECT_EQ(colours["sightings"], slam.section["colour_signatures"]["sightings"]);
  const std::vector<ChangeEntry> pose_given =
      ParseChangeLog(ReadTextFile(folder + "/changes.json"), "changes.json");
  EXPECT_EQ(Moves(cups, pose_given, Eigen::Matrix3d::Identity()),
            Moves(cups, slam.changes, kSlamFromScene.transpose()));
  EXPECT_EQ(Moves(cups, pose_given, Eigen::Matrix3d::Identity()).size(), 2u);
}

}  // namespace
}  // namespace ocg
