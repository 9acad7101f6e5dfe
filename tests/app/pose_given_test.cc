// The pose-given runner (MapObjectsAlongTrajectory, `ocg_slam objects`) on a synthetic
// table scene: detection files and a trajectory in, the object map's files and the run's
// counts out. Frames without a pose are skipped whole, keyframes fall every
// Objects.keyframe_interval-th frame used, and a vanished object is removed.

#include "ocg/app/pose_given.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <opencv2/imgcodecs.hpp>

#include "ocg/core/file_io.h"
#include "ocg/viewer/run_scene.h"
#include "synthetic_scene.h"
#include "test_support.h"

namespace ocg {
namespace {

constexpr int kPerson = 0;  // COCO class of the boxes of the frames without a pose

struct PoseGivenRun {
  nlohmann::json report;
  std::string folder;
  nlohmann::json Read(const std::string& name) const {
    return nlohmann::json::parse(ReadTextFile(folder + "/" + name));
  }
};

// The scene's detections as EAO files, a pose for every frame but those in
// [no_pose_from, no_pose_until), whose files hold a person box in the middle of the image
// (in every one of them: were they used, the person would be mapped).
PoseGivenRun MapScene(const testing::SyntheticScene& scene, const Settings& settings,
                      const std::string& name, int no_pose_from = 0, int no_pose_until = 0,
                      const SnapshotPolicy& snapshots = {false, 0}) {
  const std::string folder = testing::MakeTempDir(name);
  const std::string detections = folder + "/detections";
  std::filesystem::create_directories(detections);
  std::vector<PoseGivenFrame> frames;
  std::vector<std::string> names;
  for (int frame = 0; frame < scene.options.frames; ++frame) {
    const auto f = static_cast<std::size_t>(frame);
    PoseGivenFrame given;
    given.timestamp = 100.0 + scene.timestamps[f];
    std::ostringstream text;
    text.precision(6);
    text << std::fixed << given.timestamp;
    given.timestamp_text = text.str();
    const bool without_pose = frame >= no_pose_from && frame < no_pose_until;
    if (!without_pose) given.T_cw = scene.T_cw[f];
    std::ofstream file(detections + "/" + given.timestamp_text + ".txt");
    for (const Detection& d : scene.detections[f])
      file << d.class_id << ' ' << d.x << ' ' << d.y << ' ' << d.width << ' ' << d.height << ' '
           << d.confidence << '\n';
    if (without_pose) file << kPerson << " 280 200 80 120 0.95\n";
    frames.push_back(given);
    names.push_back(given.timestamp_text);
  }
  FolderDetectionSource folder_of_detections(EaoDetectionFolder(detections, names), detections);
  PoseGivenRun run;
  run.folder = folder + "/out";
  std::filesystem::create_directories(run.folder);
  std::size_t progress_calls = 0;
  run.report = MapObjectsAlongTrajectory(
      settings, frames, folder_of_detections, run.folder, [&](std::size_t) { ++progress_calls; },
      nullptr, snapshots);
  EXPECT_EQ(progress_calls, frames.size() - static_cast<std::size_t>(no_pose_until - no_pose_from));
  return run;
}

Settings PaperSettings() {
  Settings settings;
  settings.ocg.mode = "paper";
  settings.objects.keyframe_interval = 5;
  return settings;
}

TEST(PoseGiven, WritesTheObjectMapAndCountsFramesAndKeyframes) {
  const testing::SyntheticScene scene = testing::SynthesizeScene(testing::TableWithObjects());
  // Frames 20-26 have no pose: skipped, their person boxes unused. Seven of them, so
  // that counting keyframes over every frame instead of those used gives another count.
  const PoseGivenRun run = MapScene(scene, PaperSettings(), "pose_given_counts", 20, 27);
  EXPECT_EQ(run.report["frames"], 120);
  EXPECT_EQ(run.report["frames_used"], 113);
  EXPECT_EQ(run.report["frames_without_pose"], 7);
  // Every 5th frame used is a keyframe: used frames 0, 5, ..., 110.
  EXPECT_EQ(run.report["keyframes"], 23);
  for (const char* file : {"objects.json", "changes.json", "ocg.json", "ocg_observations.jsonl"})
    EXPECT_TRUE(std::filesystem::is_regular_file(run.folder + "/" + file)) << file;
  std::ifstream observations(run.folder + "/ocg_observations.jsonl");
  int lines = 0;
  for (std::string line; std::getline(observations, line);) ++lines;
  EXPECT_EQ(lines, 23);

  const nlohmann::json objects = run.Read("objects.json")["objects"];
  ASSERT_EQ(objects.size(), 4u);
  for (const nlohmann::json& object : objects) {
    EXPECT_NE(object["class_id"], kPerson);
    bool near_truth = false;
    for (const testing::SyntheticObject& truth : scene.options.objects) {
      if (truth.class_id != object["class_id"]) continue;
      const auto& c = object["cuboid"]["centre"];
      near_truth =
          (Eigen::Vector3d(c[0], c[1], c[2]) - truth.centre).norm() < 0.15 * truth.size.maxCoeff();
    }
    EXPECT_TRUE(near_truth) << object.dump();
  }
  EXPECT_TRUE(run.Read("changes.json")["changes"].empty());
}

TEST(PoseGiven, TheCupTakenAwayIsRemovedAndLoggedWithItsSessionTime) {
  const testing::SyntheticScene scene = testing::SynthesizeScene(testing::TableWithObjects(60));
  const PoseGivenRun run = MapScene(scene, PaperSettings(), "pose_given_removal");
  const nlohmann::json objects = run.Read("objects.json")["objects"];
  EXPECT_EQ(objects.size(), 3u);
  const nlohmann::json changes = run.Read("changes.json")["changes"];
  ASSERT_EQ(changes.size(), 1u);
  EXPECT_EQ(changes[0]["type"], "removed");
  EXPECT_EQ(changes[0]["class_id"], 41);
  // Removed at the keyframe of frame 105 (the first since the camera left at frame 100
  // that saw no object), 105 frames after the run's first frame.
  EXPECT_NEAR(changes[0]["time"].get<double>(), 105.0 / 30.0, 1e-6);
  EXPECT_EQ(run.report["objects_live"], 3);
}

TEST(PoseGiven, TheOcgModeDecidesWhatIsRemovedNotWhatIsMapped) {
  // The same run in the "off" mode keeps the cup: nothing is removed, all four mapped.
  const testing::SyntheticScene scene = testing::SynthesizeScene(testing::TableWithObjects(60));
  Settings settings = PaperSettings();
  settings.ocg.mode = "off";
  const PoseGivenRun run = MapScene(scene, settings, "pose_given_off");
  EXPECT_EQ(run.Read("objects.json")["objects"].size(), 4u);
  EXPECT_TRUE(run.Read("changes.json")["changes"].empty());
}

int LineCount(const std::string& path) {
  std::ifstream file(path);
  int lines = 0;
  for (std::string line; std::getline(file, line);) ++lines;
  return lines;
}

// Issue 32, point 5: a pose-given run can be looked at like a SLAM run. Its folder holds
// the given trajectory and the OCG keyframes' poses, and snapshots (the map before the
// cup's removal, the final map, the last frame, and every N keyframes when asked), and
// ocg_render draws it again.
TEST(PoseGiven, WritesTrajectoriesAndSnapshotsThatOcgRenderDraws) {
  const testing::SyntheticScene scene = testing::SynthesizeScene(testing::TableWithObjects(60));
  Settings settings = PaperSettings();
  settings.viewer.snapshot_width = 320;
  settings.viewer.snapshot_height = 240;
  const PoseGivenRun run =
      MapScene(scene, settings, "pose_given_snapshots", 0, 0, ParseSnapshotPolicy("every:10"));
  ASSERT_EQ(run.report["frames_used"], 120);
  EXPECT_EQ(LineCount(run.folder + "/CameraTrajectory.txt"), 120);
  EXPECT_EQ(LineCount(run.folder + "/KeyFrameTrajectory.txt"), run.report["keyframes"]);
  const std::string snapshots = run.folder + "/snapshots/";
  for (const char* name : {"final_follow", "final_top", "final_three_quarter", "final_objects",
                           "before_first_removal_three_quarter", "before_first_removal_objects",
                           "keyframe_00010_three_quarter", "keyframe_00020_three_quarter"}) {
    const cv::Mat image = cv::imread(snapshots + name + ".png");
    EXPECT_EQ(image.size(), cv::Size(320, 240)) << name;
  }
  for (const char* name : {"final_frame", "keyframe_00010_frame"}) {
    const cv::Mat image = cv::imread(snapshots + name + ".png");
    EXPECT_EQ(image.size(), cv::Size(settings.camera.model.width, settings.camera.model.height))
        << name;
  }
  EXPECT_EQ(run.report["snapshots"]["files"].size(), 11u);

  // The folder read back as ocg_render reads it (with the run.json `ocg_slam objects` adds):
  // the given path, the keyframes, the three objects left and the cup's ghost.
  nlohmann::json report = run.report;
  report["command"] = "objects";
  WriteFileAtomically(run.folder + "/run.json", report.dump());
  const auto drawn = ReadRunScene(run.folder);
  EXPECT_EQ(drawn.trajectory.size(), 120u);
  EXPECT_EQ(drawn.keyframes.size(), run.report["keyframes"].get<std::size_t>());
  EXPECT_EQ(drawn.trajectory_name, "given camera path");
  ASSERT_EQ(drawn.objects.size(), 4u);
  EXPECT_TRUE(drawn.objects[3].removed);
  const std::string rendered = run.folder + "/rendered";
  const std::string command = std::string(OCG_RENDER_TOOL) + " --run " + run.folder + " --out " +
                              rendered + " --views top --log-level warn > /dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  EXPECT_EQ(cv::imread(rendered + "/map_top.png").size(), cv::Size(1280, 720));

  // --snapshots none: the trajectories all the same, no PNG.
  const PoseGivenRun plain = MapScene(scene, PaperSettings(), "pose_given_no_snapshots");
  EXPECT_EQ(LineCount(plain.folder + "/CameraTrajectory.txt"), 120);
  EXPECT_FALSE(std::filesystem::exists(plain.folder + "/snapshots"));
  EXPECT_TRUE(plain.report["snapshots"].is_null());
}

}  // namespace
}  // namespace ocg
