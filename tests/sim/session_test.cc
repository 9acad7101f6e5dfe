#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "ocg/core/file_io.h"
#include "ocg/eval/object_metrics.h"
#include "ocg/sim/generator.h"
#include "ocg/sim/scene_io.h"
#include "test_support.h"

namespace ocg::sim {
namespace {

// The first visit as ocg_synth saves it: its changes scheduled into the histories.
Scene FirstVisit(const std::string& name, std::uint64_t seed) {
  Scene scene = MakePreset(name, seed);
  SceneRenderer planner(scene);
  ScheduleMoves(scene, PresetMoves(name, scene, seed), planner);
  return scene;
}

TEST(LaterVisit, SharesRoomAndStaticObjectsAndDiffersExactlyAsObjectsGtSays) {
  const Scene first = FirstVisit("smoke", 2);  // one in-session move
  const Scene second = MakeLaterVisit(first, PresetVisitChanges("session_b"), 7);
  EXPECT_EQ(second.session.index, 1);
  EXPECT_EQ(second.session.previous, first.name);
  EXPECT_GT(second.time_origin, first.time_origin + first.duration);
  // The room: every piece of furniture, the camera and the look are the same.
  ASSERT_EQ(second.furniture.size(), first.furniture.size());
  for (std::size_t i = 0; i < first.furniture.size(); ++i) {
    EXPECT_EQ(second.furniture[i].centre, first.furniture[i].centre);
    EXPECT_EQ(second.furniture[i].texture_seed, first.furniture[i].texture_seed);
  }
  EXPECT_EQ(second.room_size, first.room_size);
  // No changes while the camera watches.
  for (const SceneObject& object : second.objects) EXPECT_FALSE(object.Moves()) << object.id;

  // objects_gt.json's between-visit changes against the two scenes.
  const nlohmann::json gt = nlohmann::json::parse(ObjectsGroundTruthJson(second));
  ASSERT_TRUE(gt.contains("session"));
  std::map<int, std::string> listed;
  for (const nlohmann::json& change : gt["session"]["changes"])
    listed[change["id"].get<int>()] = change["type"].get<std::string>();
  int moved = 0, removed = 0, added = 0, unchanged = 0;
  for (const SceneObject& object : second.objects) {
    const SceneObject* before = first.FindObject(object.id);
    const PlacedPose now = object.history[0];
    if (before == nullptr) {
      ++added;
      EXPECT_EQ(listed[object.id], "added");
      EXPECT_TRUE(now.present);
      continue;
    }
    const PlacedPose then = before->history.back();
    ASSERT_TRUE(then.present) << "an object gone in the first visit came back: " << object.id;
    if (!now.present) {
      ++removed;
      EXPECT_EQ(listed[object.id], "removed");
    } else if ((now.centre - then.centre).norm() > 1e-9) {
      ++moved;
      EXPECT_EQ(listed[object.id], "moved");
      EXPECT_GE((now.centre - then.centre).head<2>().norm(), 0.25) << object.id;
    } else {
      ++unchanged;
      EXPECT_EQ(listed.count(object.id), 0u) << "an unchanged object listed: " << object.id;
      EXPECT_EQ(now.yaw, then.yaw);
      EXPECT_FALSE(object.before_session.has_value());
    }
  }
  EXPECT_EQ(moved, 4);
  EXPECT_EQ(removed, 1);
  EXPECT_EQ(added, 1);
  EXPECT_EQ(static_cast<int>(listed.size()), moved + removed + added);

  // Frames in view count this visit's frames: the previous visit's pose, first in a changed
  // object's history, has no count; this visit's placements have theirs, in order.
  FramesInView frames_in_view;
  for (const SceneObject& object : second.objects) {
    for (std::size_t i = 0; i < object.history.size(); ++i) {
      frames_in_view[object.id].push_back(object.id * 10 + static_cast<int>(i));
    }
  }
  const nlohmann::json counted =
      nlohmann::json::parse(ObjectsGroundTruthJson(second, &frames_in_view));
  for (const nlohmann::json& entry : counted.at("objects")) {
    const int id = entry.at("id").get<int>();
    const SceneObject* object = second.FindObject(id);
    ASSERT_NE(object, nullptr);
    const nlohmann::json& history = entry.at("history");
    const std::size_t first_of_visit = object->before_session ? 1 : 0;
    ASSERT_EQ(history.size(), first_of_visit + object->history.size()) << id;
    if (object->before_session) {
      EXPECT_FALSE(history[0].contains("frames_in_view")) << id;
    }
    for (std::size_t i = 0; i < object->history.size(); ++i) {
      EXPECT_EQ(history[first_of_visit + i].at("frames_in_view").get<int>(),
                id * 10 + static_cast<int>(i))
          << id;
    }
  }
  EXPECT_GE(unchanged, 2);

  // ocg_eval reads it: the places left between the visits are outdated places.
  const std::string dir = testing::MakeTempDir("visit_gt");
  WriteFile(dir + "/objects_gt.json", gt.dump());
  const ObjectGroundTruth truth = ReadObjectGroundTruth(dir + "/objects_gt.json");
  EXPECT_EQ(static_cast<int>(truth.outdated_places.size()), moved + removed);
  EXPECT_EQ(static_cast<int>(truth.static_places.size()), moved + added + unchanged);
}

TEST(LaterVisit, StartsElsewhereOnGroundTheFirstVisitSaw) {
  const Scene first = MakePreset("session_a", 1);
  const Scene second = MakeLaterVisit(first, PresetVisitChanges("session_b"), 1);
  const Eigen::Vector3d start_first = CameraPoseAt(first, 0).Inverse().translation();
  const Eigen::Vector3d start_second = CameraPoseAt(second, 0).Inverse().translation();
  EXPECT_GT((start_second - start_first).norm(), 1.0);
  // The first visit's camera passed where the second one starts, looking the same way.
  double nearest = 1e9, angle = 0;
  for (int frame = 0; frame < first.FrameCount(); ++frame) {
    const SE3 T_wc = CameraPoseAt(first, first.TimeOfFrame(frame)).Inverse();
    const double distance = (T_wc.translation() - start_second).norm();
    if (distance < nearest) {
      nearest = distance;
      angle =
          LogSO3(T_wc.rotation().transpose() * CameraPoseAt(second, 0).Inverse().rotation()).norm();
    }
  }
  EXPECT_LT(nearest, 0.05);
  EXPECT_LT(angle * 180 / M_PI, 5.0);
}

TEST(LaterVisit, DeterministicInTheSeedAndSavedWithTheScene) {
  const Scene first = MakePreset("session_a", 1);
  const VisitChanges changes = PresetVisitChanges("session_b");
  const std::string a = SceneToYaml(MakeLaterVisit(first, changes, 3));
  EXPECT_EQ(SceneToYaml(MakeLaterVisit(first, changes, 3)), a);
  EXPECT_NE(SceneToYaml(MakeLaterVisit(first, changes, 4)), a);
  // scene.yaml of a later visit reads back to the same scene (a visit of a visit works).
  const SceneFile parsed = ParseSceneYaml(a, "scene.yaml");
  EXPECT_EQ(SceneToYaml(parsed.scene), a);
  EXPECT_EQ(parsed.scene.session.index, 1);
  EXPECT_EQ(MakeLaterVisit(parsed.scene, changes, 5).session.index, 2);
  // A room preset gives its own change counts; an unknown name is refused.
  EXPECT_EQ(PresetVisitChanges("round_2").moves, 9);
  EXPECT_THROW(PresetVisitChanges("nowhere"), std::invalid_argument);
  VisitChanges too_many = changes;
  too_many.removals = 1000;
  EXPECT_THROW(MakeLaterVisit(first, too_many, 3), std::invalid_argument);
  Scene short_visit = first;
  short_visit.duration = 0.5 * LapDuration(first.path);
  EXPECT_THROW(MakeLaterVisit(short_visit, changes, 3), std::invalid_argument);
}

TEST(LaterVisit, KeepsTheRealisticLookAndDetector) {
  Scene first = MakePreset("session_a", 1);
  first.look.kind = LookKind::kRealistic;
  first.noise.kind = DetectorKind::kRealistic;
  const Scene second = MakeLaterVisit(first, PresetVisitChanges("session_b"), 2);
  EXPECT_TRUE(second.look.realistic());
  EXPECT_EQ(second.noise.kind, DetectorKind::kRealistic);
  // Rendered through the realistic camera: the first frame is a picture, not black.
  SceneRenderer renderer(second);
  const cv::Mat frame = renderer.Colour(0.0, CameraPoseAt(second, 0.0), 1);
  EXPECT_GT(cv::mean(frame)[0], 20.0);
}

}  // namespace
}  // namespace ocg::sim
