#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "ocg/app/settings.h"
#include "ocg/core/file_io.h"
#include "ocg/core/settings_file.h"
#include "ocg/io/sequence.h"
#include "ocg/ocg/change_detector.h"
#include "ocg/ocg/replay_format.h"
#include "ocg/sim/generator.h"
#include "ocg/sim/scene_io.h"
#include "test_support.h"

namespace ocg::sim {
namespace {

namespace fs = std::filesystem;

Scene ScheduledPreset(const std::string& name, std::uint64_t seed) {
  Scene scene = MakePreset(name, seed);
  SceneRenderer planner(scene);
  ScheduleMoves(scene, PresetMoves(name, scene, seed), planner);
  return scene;
}

std::map<std::string, std::string> ReadTree(const std::string& root) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (entry.is_regular_file())
      files[fs::relative(entry.path(), root).string()] = ReadTextFile(entry.path().string());
  }
  return files;
}

TEST(Generator, SameSeedSameFilesDifferentSeedDifferentFiles) {
  GeneratorOptions options;
  options.max_frames = 12;
  options.keyframe_interval = 4;
  const std::string dir = testing::MakeTempDir("synth");
  Generate(ScheduledPreset("smoke", 3), dir + "/a", options);
  Generate(ScheduledPreset("smoke", 3), dir + "/b", options);
  Generate(ScheduledPreset("smoke", 4), dir + "/c", options);
  const auto a = ReadTree(dir + "/a");
  const auto b = ReadTree(dir + "/b");
  const auto c = ReadTree(dir + "/c");
  ASSERT_EQ(a.size(), 12u * 2 + 6);  // rgb + detections per frame, 6 other files
  EXPECT_TRUE(a == b) << "same seed, different output";
  EXPECT_NE(a.at("rgb/1000.000000.png"), c.at("rgb/1000.000000.png"));
  EXPECT_NE(a.at("objects_gt.json"), c.at("objects_gt.json"));
  EXPECT_EQ(ReadTumImageList(dir + "/a/rgb.txt", dir + "/a").size(), 12u);
  // camera.yaml is a settings file for the rendered camera.
  const LoadedSettings camera = LoadSettings(dir + "/a/camera.yaml");
  EXPECT_TRUE(camera.warnings.empty());
  EXPECT_DOUBLE_EQ(camera.settings.camera.model.fx, 535.4);
  // An existing output is never overwritten by accident.
  EXPECT_THROW(Generate(ScheduledPreset("smoke", 3), dir + "/a", options), FileError);
}

// objects_gt.json counts, per placement, the frames that show the object at the
// detector's least visible size: with the perfect detector that is the number of its
// boxes, and an object behind the partition in every frame has none.
TEST(Generator, ObjectsGroundTruthCountsTheFramesInViewOfEachPlacement) {
  Scene scene = MakePreset("smoke", 1);
  scene.noise.perfect = true;
  const int hidden_id = scene.objects[0].id;
  scene.objects[0].history = {PlacedPose{0.0, true, Eigen::Vector3d(0.0, 0.2, 0.80), 0.0}};
  GeneratorOptions options;
  options.max_frames = 6;
  options.write_images = false;
  const std::string dir = testing::MakeTempDir("frames_in_view");
  Generate(scene, dir + "/out", options);

  std::map<int, int> boxes_of_class;
  for (const auto& [name, text] : ReadTree(dir + "/out/detections")) {
    std::istringstream lines(text);
    std::string line;
    while (std::getline(lines, line)) {
      if (line.empty() || line[0] == '#') continue;
      std::istringstream fields(line);
      int class_id = -1;
      fields >> class_id;
      ++boxes_of_class[class_id];
    }
  }
  const nlohmann::json gt = nlohmann::json::parse(ReadTextFile(dir + "/out/objects_gt.json"));
  std::map<int, int> in_view_of_class;
  int objects_in_view = 0;
  for (const nlohmann::json& object : gt.at("objects")) {
    ASSERT_EQ(object.at("history").size(), 1u);
    const int frames = object.at("history")[0].at("frames_in_view").get<int>();
    EXPECT_LE(frames, options.max_frames);
    if (object.at("id").get<int>() == hidden_id) {
      EXPECT_EQ(frames, 0);
    }
    if (frames == 0) continue;
    in_view_of_class[object.at("class_id").get<int>()] += frames;
    ++objects_in_view;
  }
  EXPECT_GT(objects_in_view, 1);
  EXPECT_EQ(in_view_of_class, boxes_of_class);
}

// With a move: each frame counts for the placement the object has then. The oracle
// observations name it (OracleMapId: object id and placement index), and with the
// perfect detector every object in view is observed. Rendered only up to before the move,
// the moved object has one placement: the move did not happen in those frames.
TEST(Generator, FramesInViewCountEachPlacementAndChangesAfterTheLastFrameAreLeftOut) {
  const Scene scene = ScheduledPreset("smoke", 1);
  Scene perfect = scene;
  perfect.noise.perfect = true;
  GeneratorOptions options;
  options.write_images = false;
  options.keyframe_interval = 1;
  const std::string dir = testing::MakeTempDir("frames_in_view_moves");
  Generate(perfect, dir + "/all", options);

  std::map<std::int64_t, int> observed;  // oracle map id -> keyframes observed in
  std::ifstream oracle(dir + "/all/oracle_observations.jsonl");
  std::string line;
  while (std::getline(oracle, line)) {
    const nlohmann::json observation = nlohmann::json::parse(line);
    for (const std::int64_t id : observation.at("observed")) ++observed[id];
  }
  const nlohmann::json gt = nlohmann::json::parse(ReadTextFile(dir + "/all/objects_gt.json"));
  int moved = 0;
  double first_change = 1e9;
  for (const nlohmann::json& object : gt.at("objects")) {
    const nlohmann::json& history = object.at("history");
    if (history.size() > 1) {
      ++moved;
      first_change = std::min(
          first_change, history[1].at("time").get<double>() - gt.at("time_origin").get<double>());
    }
    for (std::size_t i = 0; i < history.size(); ++i) {
      const std::int64_t id = OracleMapId(object.at("id").get<int>(), i);
      EXPECT_EQ(history[i].at("frames_in_view").get<int>(), observed[id])
          << "object " << object.at("id") << " placement " << i;
    }
  }
  ASSERT_GT(moved, 0);
  // Placements after the move saw frames too (else this test could not tell them apart).
  int seen_after_a_move = 0;
  for (const auto& [id, count] : observed) {
    if (id % kOracleIdStride > 0 && count > 0) ++seen_after_a_move;
  }
  EXPECT_GT(seen_after_a_move, 0);

  options.max_frames = static_cast<int>(first_change * scene.fps) - 1;
  ASSERT_GT(options.max_frames, 0);
  Generate(perfect, dir + "/before", options);
  const nlohmann::json before =
      nlohmann::json::parse(ReadTextFile(dir + "/before/objects_gt.json"));
  for (const nlohmann::json& object : before.at("objects")) {
    EXPECT_EQ(object.at("history").size(), 1u) << "object " << object.at("id");
    EXPECT_EQ(object.at("status"), "static");
  }
}

TEST(DetectionModel, UnoccludedObjectBoxEqualsItsProjectedBox) {
  Scene scene = MakePreset("smoke", 1);
  scene.objects.resize(1);
  scene.noise.perfect = true;
  SceneObject& object = scene.objects[0];
  object.shape = Shape::kBox;
  object.size = Eigen::Vector3d(0.3, 0.2, 0.25);
  object.history = {PlacedPose{0.0, true, Eigen::Vector3d(0.2, -0.25, 0.875), 0.4}};
  SceneRenderer renderer(scene);
  DetectionModel model(scene);
  const SE3 T_cw = LookAt({0.9, -1.4, 1.3}, {0.2, -0.25, 0.8});
  const DetectionModel::FrameResult result = model.Detect(renderer.Ids(0.0, T_cw), 0.0, T_cw, 0);
  ASSERT_EQ(result.detections.size(), 1u);
  const Detection& box = result.detections[0];
  double min_u = 1e9, min_v = 1e9, max_u = -1e9, max_v = -1e9;
  const SE3 T_wo(Eigen::Matrix3d(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ())),
                 {0.2, -0.25, 0.875});
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d local((corner & 1 ? 0.15 : -0.15), (corner & 2 ? 0.1 : -0.1),
                                (corner & 4 ? 0.125 : -0.125));
    const Eigen::Vector2d pixel = scene.camera.Project(T_cw * (T_wo * local));
    min_u = std::min(min_u, pixel.x());
    max_u = std::max(max_u, pixel.x());
    min_v = std::min(min_v, pixel.y());
    max_v = std::max(max_v, pixel.y());
  }
  EXPECT_NEAR(box.x, min_u, 1.5);
  EXPECT_NEAR(box.y, min_v, 1.5);
  EXPECT_NEAR(box.x + box.width - 1, max_u, 1.5);
  EXPECT_NEAR(box.y + box.height - 1, max_v, 1.5);
  EXPECT_EQ(box.class_id, object.class_id);
  EXPECT_EQ(box.confidence, 1.0);
}

TEST(SceneRenderer, ThePartitionHidesTheFarHalf) {
  Scene scene = MakePreset("smoke", 1);
  const SE3 T_cw = CameraPoseAt(scene, 0.0);  // the camera starts on the y < 0 side
  ASSERT_LT(T_cw.Inverse().translation().y(), -1.0);
  const int id = scene.objects[0].id;
  const PlacedPose far_side{0.0, true, Eigen::Vector3d(0.0, 0.2, 0.80), 0.0};
  const PlacedPose near_side{0.0, true, Eigen::Vector3d(0.0, -0.2, 0.80), 0.0};
  SceneRenderer with_partition(scene);
  EXPECT_EQ(with_partition.VisiblePixels(id, far_side, 0.0, T_cw), 0);
  EXPECT_GT(with_partition.VisiblePixels(id, near_side, 0.0, T_cw), 200);
  Scene open = scene;
  open.furniture.erase(std::remove_if(open.furniture.begin(), open.furniture.end(),
                                      [](const Furniture& f) { return f.name == "partition"; }),
                       open.furniture.end());
  SceneRenderer without_partition(open);
  EXPECT_GT(without_partition.VisiblePixels(id, far_side, 0.0, T_cw), 200)
      << "hidden by something else";
}

TEST(Changes, ScheduledChangesHappenUnseenAndVisibleOnesAreRefused) {
  Scene scene = ScheduledPreset("smoke", 1);
  SceneRenderer renderer(scene);
  EXPECT_NO_THROW(ValidateChanges(scene, renderer));
  int changes = 0;
  for (const SceneObject& object : scene.objects) {
    for (size_t i = 1; i < object.history.size(); ++i, ++changes) {
      const double t = object.history[i].time;
      for (double when : {t - 0.1, t + 0.1}) {
        const SE3 T_cw = CameraPoseAt(scene, when);
        EXPECT_EQ(renderer.VisiblePixels(object.id, object.history[i - 1], when, T_cw), 0);
        EXPECT_EQ(renderer.VisiblePixels(object.id, object.history[i], when, T_cw), 0);
      }
    }
  }
  EXPECT_EQ(changes, 1);
  // An object on the near half moved at 0.5 s, right in front of the camera: refused.
  Scene bad = MakePreset("smoke", 1);
  for (SceneObject& object : bad.objects) {
    if (object.history[0].centre.y() < 0) {
      PlacedPose moved = object.history[0];
      moved.time = 0.5;
      moved.centre.x() += 0.1;
      object.history.push_back(moved);
      break;
    }
  }
  SceneRenderer bad_renderer(bad);
  EXPECT_THROW(ValidateChanges(bad, bad_renderer), std::invalid_argument);
  // ocg_synth refuses such a scene and leaves nothing behind.
  const std::string dir = testing::MakeTempDir("refused");
  GeneratorOptions options;
  options.max_frames = 2;
  EXPECT_THROW(Generate(bad, dir + "/out", options), std::invalid_argument);
  EXPECT_TRUE(fs::is_empty(dir)) << "a refused scene left files";
}

// A scene at 160 x 120 (intrinsics scaled), so that the scheduler's renders are cheap.
void QuarterSize(Scene& scene) {
  scene.camera.fx /= 4;
  scene.camera.fy /= 4;
  scene.camera.cx = (scene.camera.cx + 0.5) / 4 - 0.5;
  scene.camera.cy = (scene.camera.cy + 0.5) / 4 - 0.5;
  scene.camera.width = 160;
  scene.camera.height = 120;
}

// smoke's room and camera path with two objects of our own, for the scheduler.
Scene TwoObjectScene(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  Scene scene = MakePreset("smoke", 1);
  QuarterSize(scene);
  scene.objects.resize(2);
  const Eigen::Vector3d sizes[] = {{0.085, 0.085, 0.10}, {0.40, 0.12, 0.30}};  // cup, a screen
  const Eigen::Vector3d places[] = {a, b};
  for (int i = 0; i < 2; ++i) {
    SceneObject& object = scene.objects[static_cast<size_t>(i)];
    object.id = i + 1;
    object.shape = Shape::kBox;
    object.size = sizes[i];
    object.history.resize(1);
    object.history[0] = PlacedPose{0.0, true, places[i], 0.0};
    object.history[0].centre.z() = 0.75 + sizes[i].z() / 2;
  }
  return scene;
}

TEST(Changes, AMoveWithNoUnseenMomentGivesWayToItsAlternative) {
  // round_2, seed 12: its fifth move takes object 10 across the partition (its own half
  // was full). On the round path the partition hides one half at a time and the table's
  // ends show both, so one of the two places is always in view. At 160 x 120 and 5 frames
  // a second, to keep the renders cheap.
  Scene scene = MakePreset("round_2", 12);
  std::vector<PlannedMove> moves = PresetMoves("round_2", scene, 12);
  QuarterSize(scene);
  scene.fps = 5;
  const auto crossing = std::find_if(moves.begin(), moves.end(),
                                     [&](const PlannedMove& move) { return move.object_id == 10; });
  ASSERT_NE(crossing, moves.end());
  const Eigen::Vector3d from = scene.FindObject(10)->history[0].centre;
  ASSERT_LT(from.y() * crossing->new_centre.y(), 0.0) << "not across the partition any more";
  ASSERT_FALSE(crossing->alternatives.empty());
  PlannedMove move = *crossing;
  move.earliest = 0.0;
  {
    Scene plain = scene;
    PlannedMove without = move;
    without.alternatives.clear();
    SceneRenderer renderer(plain);
    EXPECT_THROW(ScheduleMoves(plain, {without}, renderer), std::runtime_error);
  }
  SceneRenderer renderer(scene);
  ScheduleMoves(scene, {move}, renderer);
  int changed = 0;
  for (const SceneObject& object : scene.objects) {
    if (object.history.size() == 1) continue;
    ++changed;
    EXPECT_NE(object.id == 10 ? object.history[1].centre : Eigen::Vector3d::Zero(),
              crossing->new_centre);
    const auto stand_in = std::find_if(
        move.alternatives.begin(), move.alternatives.end(), [&](const PlannedMove& alternative) {
          return alternative.object_id == object.id &&
                 (alternative.removal || alternative.new_centre == object.history[1].centre);
        });
    EXPECT_NE(stand_in, move.alternatives.end()) << "object " << object.id;
  }
  EXPECT_EQ(changed, 1);
  SceneRenderer check(scene);
  EXPECT_NO_THROW(ValidateChanges(scene, check));
}

TEST(Changes, AChangeScheduledEarlierDoesNotRevealALaterOne) {
  // The cup (1) stands on the near half right behind the screen (2), which hides it from the
  // camera at the start of the second lap; the cup shifts then. The screen is removed,
  // listed after the cup but free to go earlier: at the first moment the camera is away
  // from both, in the first lap, which would leave the cup in view when it shifts.
  Scene scene = TwoObjectScene({0.0, -0.35, 0}, {0.0, -0.52, 0});
  const double lap = LapDuration(scene.path);
  PlannedMove shift;
  shift.object_id = 1;
  shift.new_centre = {0.06, -0.35, 0.80};
  shift.earliest = lap + 0.5;
  PlannedMove removal;
  removal.object_id = 2;
  removal.removal = true;
  {  // Each alone happens unseen, the cup while the screen stands.
    Scene alone = scene;
    SceneRenderer renderer(alone);
    ScheduleMoves(alone, {shift}, renderer);
    ASSERT_LT(alone.FindObject(1)->history[1].time, lap + 2.0);
    Scene open = scene;
    open.objects.pop_back();
    SceneRenderer open_renderer(open);
    EXPECT_GT(open_renderer.VisiblePixels(1, open.objects[0].history[0],
                                          alone.FindObject(1)->history[1].time,
                                          CameraPoseAt(open, alone.FindObject(1)->history[1].time)),
              0)
        << "the screen does not hide the cup";
  }
  SceneRenderer renderer(scene);
  ScheduleMoves(scene, {shift, removal}, renderer);
  const double shifted = scene.FindObject(1)->history.at(1).time;
  const double removed = scene.FindObject(2)->history.at(1).time;
  EXPECT_GT(removed, shifted) << "the removal would show the cup when it shifts";
  SceneRenderer check(scene);
  EXPECT_NO_THROW(ValidateChanges(scene, check));
}

TEST(Presets, FramesHaveManyWellSpreadFastCorners) {
  for (const std::string& name : PresetNames()) {
    const Scene scene = MakePreset(name, 1);
    SceneRenderer renderer(scene);
    constexpr int kSamples = 8;
    for (int k = 0; k < kSamples; ++k) {
      const double t = scene.duration * (k + 0.5) / kSamples;
      cv::Mat grey;
      cv::cvtColor(renderer.Colour(t, CameraPoseAt(scene, t), static_cast<std::uint64_t>(k)), grey,
                   cv::COLOR_BGR2GRAY);
      std::vector<cv::KeyPoint> corners;
      cv::FAST(grey, corners, 20, true);
      std::set<int> cells;  // 8 x 6 grid
      for (const cv::KeyPoint& corner : corners) {
        cells.insert(static_cast<int>(corner.pt.y / 80) * 8 + static_cast<int>(corner.pt.x / 80));
      }
      EXPECT_GE(corners.size(), 500u) << name << " at " << t << " s";
      EXPECT_GE(cells.size(), 36u) << name << " at " << t << " s: corners crowd into few cells";
    }
  }
}

TEST(Presets, ChangeCountsAndAnAdditionThatAppearsUnseen) {
  const Scene scene = ScheduledPreset("straight_2", 1);
  int moved = 0, removed = 0, added = 0, still = 0;
  for (const SceneObject& object : scene.objects) {
    if (!object.Moves()) {
      ++still;
      continue;
    }
    const bool starts = object.history.front().present, ends = object.history.back().present;
    moved += starts && ends;
    removed += starts && !ends;
    added += !starts && ends;
  }
  EXPECT_EQ(moved, 9);
  EXPECT_EQ(removed, 1);
  EXPECT_EQ(added, 1);
  EXPECT_GE(still, 21);
  SceneRenderer renderer(scene);
  EXPECT_NO_THROW(ValidateChanges(scene, renderer));
}

TEST(Presets, CameraMotionStaysHandHeld) {
  for (const std::string& name : PresetNames()) {
    const Scene scene = MakePreset(name, 2);
    const double dt = 1.0 / scene.fps;
    double fastest = 0.0, fastest_turn = 0.0;
    for (int frame = 1; frame < scene.FrameCount(); ++frame) {
      const SE3 a = CameraPoseAt(scene, (frame - 1) * dt).Inverse();
      const SE3 b = CameraPoseAt(scene, frame * dt).Inverse();
      fastest = std::max(fastest, (b.translation() - a.translation()).norm() / dt);
      fastest_turn =
          std::max(fastest_turn, LogSO3(a.rotation().transpose() * b.rotation()).norm() / dt);
    }
    EXPECT_LE(fastest, 0.45) << name;  // about 0.4 m/s
    EXPECT_LE(fastest_turn * 180 / M_PI, 40.0) << name;
  }
}

TEST(SceneFile, RoundTripAndErrorsNameTheField) {
  const Scene scene = ScheduledPreset("smoke", 5);
  const std::string text = SceneToYaml(scene);
  const SceneFile parsed = ParseSceneYaml(text, "scene.yaml");
  EXPECT_EQ(SceneToYaml(parsed.scene), text);
  EXPECT_EQ(parsed.scene.objects.size(), scene.objects.size());
  try {
    ParseSceneYaml(
        "objects:\n  - id: 1\n    class_id: 41\n    size: [1, 2]\n    history: [{time: 0, centre: "
        "[0, 0, 0]}]\n",
        "bad.yaml");
    FAIL();
  } catch (const SettingsError& error) {
    EXPECT_NE(std::string(error.what()).find("objects[0].size"), std::string::npos) << error.what();
  }
  EXPECT_THROW(ParseSceneYaml("path: {kind: zigzag}\n", "bad.yaml"), SettingsError);
}

TEST(Oracle, SmokeSequenceTheOcgRemovesTheMovedObjectAndNothingElse) {
  // The whole smoke sequence, keyframes only (every 10th frame), id pass and detector:
  // the oracle stream fed to the OCG in paper and improved modes.
  const Scene scene = ScheduledPreset("smoke", 1);
  SceneRenderer renderer(scene);
  for (const std::string mode : {"paper", "improved"}) {
    DetectionModel model(scene);
    OcgOptions options;
    options.mode = mode;
    ObjectChangeDetector detector(options);
    std::vector<ObjectId> removed;
    for (int frame = 0; frame < scene.FrameCount(); frame += 10) {
      const double t = scene.TimeOfFrame(frame);
      const SE3 T_cw = CameraPoseAt(scene, t);
      const auto detections = model.Detect(renderer.Ids(t, T_cw), t, T_cw, frame);
      const KeyframeObservation observation = ParseObservationJson(
          OracleObservation(scene, frame / 10, t, T_cw, detections.detected_objects));
      for (const RemovalEvent& event : detector.Process(observation).removed)
        removed.push_back(event.object_id);
    }
    int moved_id = 0;
    for (const SceneObject& object : scene.objects) {
      if (object.Moves()) moved_id = object.id;
    }
    ASSERT_NE(moved_id, 0);
    EXPECT_EQ(removed, std::vector<ObjectId>{OracleMapId(moved_id, 0)}) << mode;
  }
}

}  // namespace
}  // namespace ocg::sim
