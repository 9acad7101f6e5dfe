// ObjectMapper, the object layer as one unit (detections in, an object map kept up to date
// by the OCG out), on a synthetic table scene with known objects: what it maps, what it
// removes and when, what it records for the OCG, and how it follows a SLAM map.

#include "ocg/objects/object_mapper.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/core/mat.hpp>
#include <sstream>

#include "ocg/objects/change_log.h"

#include "growing_slam_map.h"
#include "synthetic_scene.h"
#include "test_support.h"

namespace ocg {
namespace {

constexpr int kKeyframeInterval = 5;

OcgOptions Paper() { return testing::PaperOptions(); }

// Every frame of the scene into the mapper (a keyframe every kKeyframeInterval frames);
// returns the ids of the keyframes.
int Feed(const testing::SyntheticScene& scene, ObjectMapper* mapper, int first = 0, int last = -1) {
  if (last < 0) last = scene.options.frames;
  int keyframes = 0;
  for (int frame = first; frame < last; ++frame) {
    const auto f = static_cast<std::size_t>(frame);
    mapper->AddFrame(frame, scene.timestamps[f], scene.T_cw[f], scene.detections[f]);
    if (frame % kKeyframeInterval == 0) {
      mapper->AddKeyframe(frame / kKeyframeInterval, scene.timestamps[f], scene.T_cw[f]);
      ++keyframes;
    }
  }
  return keyframes;
}

// The live objects of objects.json by class.
std::map<int, nlohmann::json> LiveByClass(const ObjectMapper& mapper) {
  std::map<int, nlohmann::json> by_class;
  const nlohmann::json objects = nlohmann::json::parse(mapper.ObjectsJson());
  for (const nlohmann::json& object : objects["objects"])
    by_class[object["class_id"].get<int>()] = object;
  return by_class;
}

Eigen::Vector3d Centre(const nlohmann::json& cuboid) {
  const auto& c = cuboid["centre"];
  return {c[0].get<double>(), c[1].get<double>(), c[2].get<double>()};
}

TEST(ObjectMapper, MapsEachObjectOnceAtItsPlaceAndKeepsAStaticSceneWhole) {
  const testing::SyntheticScene scene = testing::SynthesizeScene(testing::TableWithObjects());
  ObjectMapper mapper(ObjectsOptions{}, Paper(), scene.options.camera, true);
  Feed(scene, &mapper);
  mapper.Finish();
  const auto live = LiveByClass(mapper);
  ASSERT_EQ(live.size(), scene.options.objects.size());
  EXPECT_EQ(mapper.LiveObjectCount(), scene.options.objects.size());
  for (const testing::SyntheticObject& truth : scene.options.objects) {
    ASSERT_EQ(live.count(truth.class_id), 1u) << truth.class_id;
    EXPECT_LT((Centre(live.at(truth.class_id)["cuboid"]) - truth.centre).norm(),
              0.15 * truth.size.maxCoeff())
        << truth.class_id;
  }
  EXPECT_TRUE(mapper.Changes().empty());
  const ObjectLayerStats stats = mapper.Stats();
  EXPECT_EQ(stats.frames, scene.options.frames);
  EXPECT_EQ(stats.keyframes, scene.options.frames / kKeyframeInterval);
  EXPECT_EQ(stats.objects_created, 4);
  EXPECT_EQ(stats.objects_removed, 0);
}

// The cup is taken away while the camera looks away (frames 60-69). Back at the table,
// its neighbours are seen and it is not: suspicious, its doubt grows; when the camera
// leaves again (frames 100-109) the OCG removes it, and the map follows. A keyframe
// reports what was detected since the previous one: the first without any object is the
// one at frame 105.
TEST(ObjectMapper, AnObjectTakenAwayIsRemovedWhenTheCameraLeavesItsNeighbours) {
  const testing::SyntheticScene scene = testing::SynthesizeScene(testing::TableWithObjects(60));
  for (const bool sequential : {true, false}) {
    SCOPED_TRACE(sequential ? "sequential" : "threaded");
    ObjectMapper mapper(ObjectsOptions{}, Paper(), scene.options.camera, sequential);
    Feed(scene, &mapper, 0, 100);
    mapper.Finish();  // lets the threaded OCG finish; nothing is removed before leaving
    EXPECT_EQ(mapper.LiveObjectCount(), 4u);
    ObjectMapper again(ObjectsOptions{}, Paper(), scene.options.camera, sequential);
    Feed(scene, &again);
    again.Finish();
    const auto live = LiveByClass(again);
    EXPECT_EQ(live.size(), 3u);
    EXPECT_EQ(live.count(41), 0u);
    const nlohmann::json changes =
        nlohmann::json::parse(ChangeLogJson(EntriesOf(again.Changes())))["changes"];
    ASSERT_EQ(changes.size(), 1u);
    EXPECT_EQ(changes[0]["type"], "removed");
    EXPECT_EQ(changes[0]["class_id"], 41);
    EXPECT_EQ(changes[0]["keyframe"], 105 / kKeyframeInterval);  // on leaving
    EXPECT_LT(
        (Centre(changes[0]["cuboid"]) - scene.options.objects[testing::kTableCup].centre).norm(),
        0.02);
    EXPECT_EQ(again.Stats().objects_removed, 1);
    // Viewers see the removal as a removed object at its last place.
    int removed_views = 0;
    for (const ObjectView& view : again.Views()) removed_views += view.removed ? 1 : 0;
    EXPECT_EQ(removed_views, 1);
  }
}

// Two cups, one red and one blue, carried past each other while the camera looks away
// (CupsCarriedPastEachOther): by distance alone the pairing takes each removal to the
// nearer newcomer, the other cup; the keyframe images show their colours, given with the
// keyframes' detections, and a removed cup keeps its coloured sightings, so the moves
// follow the colours.
TEST(ObjectMapper, MovesWithinASessionFollowTheObjectsColours) {
  const testing::CarriedCups cups = testing::CupsCarriedPastEachOther();
  const testing::SyntheticScene scene = testing::SynthesizeScene(cups.options);
  ObjectMapper mapper(ObjectsOptions{}, Paper(), scene.options.camera, true);
  for (int frame = 0; frame < scene.options.frames; ++frame) {
    const auto f = static_cast<std::size_t>(frame);
    const bool keyframe = frame % kKeyframeInterval == 0;
    mapper.AddFrame(frame, scene.timestamps[f], scene.T_cw[f], scene.detections[f], nullptr,
                    keyframe ? cups.ColourImage(scene, f) : cv::Mat());
    if (keyframe) mapper.AddKeyframe(frame / kKeyframeInterval, scene.timestamps[f], scene.T_cw[f]);
  }
  mapper.Finish();
  ASSERT_EQ(mapper.Stats().objects_removed, 2);
  EXPECT_GT(mapper.Stats().colour_images, 0);
  EXPECT_GT(mapper.Stats().colour_sightings, mapper.Stats().colour_images);
  ChangeLogContext context;
  context.seen_as_class = mapper.SeenAsClassThisSession();
  context.colour = mapper.ColourAppearances(context.appearance_options.min_colour_signatures);
  // Each move from a cup's old place to the other place of its colour.
  const auto moves_of = [&](const ChangeLogContext& with) {
    std::map<std::size_t, std::size_t> moves;
    for (const ChangeEntry& entry : ReviseChangeLog(mapper.Changes(), mapper.LiveObjects(), with)) {
      if (entry.type != "moved") continue;
      EXPECT_TRUE(entry.to.has_value());
      if (entry.to)
        moves[cups.PlaceOf(entry.cuboid.centre)] = cups.PlaceOf(entry.to->cuboid.centre);
    }
    return moves;
  };
  EXPECT_EQ(moves_of(context), (std::map<std::size_t, std::size_t>{{cups.red, cups.red_moved},
                                                                   {cups.blue, cups.blue_moved}}));
  // Without the colours the nearer newcomers are taken: the case needs them.
  ChangeLogContext blind = context;
  blind.colour.clear();
  EXPECT_EQ(moves_of(blind), (std::map<std::size_t, std::size_t>{{cups.red, cups.blue_moved},
                                                                 {cups.blue, cups.red_moved}}));
}

// The red cup is taken away while the camera looks away (frames 60-69), and a cup appears
// elsewhere on the table; the run ends at frame 100, before the camera leaves the table
// again, with the red cup's place suspicious above tau_doubt. OCG.mode "successor" removes
// it at the end when the newcomer may be it carried: a red newcomer may, and so may any
// without images; a blue one, in images that show it blue, is another cup.
TEST(ObjectMapper, AtTheEndANewcomerOfAnotherColourIsNoSuccessor) {
  const auto red_removed_at_end = [](bool newcomer_red, bool images) {
    testing::CarriedCups cups = testing::CupsCarriedPastEachOther();
    // The blue cup stays; only the newcomer of the chosen colour appears.
    cups.options.objects[cups.blue].present_until = std::numeric_limits<int>::max();
    cups.options.objects[newcomer_red ? cups.blue_moved : cups.red_moved].present_from =
        std::numeric_limits<int>::max();
    const testing::SyntheticScene scene = testing::SynthesizeScene(cups.options);
    OcgOptions ocg;
    ocg.mode = "successor";
    ObjectMapper mapper(ObjectsOptions{}, ocg, scene.options.camera, true);
    for (int frame = 0; frame < 100; ++frame) {
      const auto f = static_cast<std::size_t>(frame);
      const bool keyframe = frame % kKeyframeInterval == 0;
      mapper.AddFrame(frame, scene.timestamps[f], scene.T_cw[f], scene.detections[f], nullptr,
                      keyframe && images ? cups.ColourImage(scene, f) : cv::Mat());
      if (keyframe)
        mapper.AddKeyframe(frame / kKeyframeInterval, scene.timestamps[f], scene.T_cw[f]);
    }
    mapper.Finish();
    int removed_red = 0;
    for (const ObjectChange& change : mapper.Changes()) {
      if (change.type == "removed" && cups.PlaceOf(change.cuboid.centre) == cups.red) {
        EXPECT_NE(change.reason.find("session ended: suspicious"), std::string::npos)
            << change.reason;
        ++removed_red;
      }
    }
    return removed_red;
  };
  EXPECT_EQ(red_removed_at_end(/*newcomer_red=*/true, /*images=*/true), 1);
  EXPECT_EQ(red_removed_at_end(/*newcomer_red=*/false, /*images=*/false), 1);
  EXPECT_EQ(red_removed_at_end(/*newcomer_red=*/false, /*images=*/true), 0);
}

TEST(ObjectMapper, RecordsTheOcgInputOfEveryKeyframe) {
  const testing::SyntheticScene scene = testing::SynthesizeScene(testing::TableWithObjects(60));
  ObjectMapper mapper(ObjectsOptions{}, Paper(), scene.options.camera, true);
  mapper.RecordObservations();
  const int keyframes = Feed(scene, &mapper);
  mapper.Finish();
  std::istringstream lines(mapper.ObservationsJsonl());
  std::string line;
  int count = 0;
  while (std::getline(lines, line)) {
    const nlohmann::json observation = nlohmann::json::parse(line);
    const int frame = count * kKeyframeInterval;
    const auto observed = observation["observed"].get<std::vector<ObjectId>>();
    if (frame == 65 || frame == 105) {
      EXPECT_TRUE(observed.empty()) << "keyframe at frame " << frame;
    }
    // The last keyframe before the cup went sees every object, those after it on the
    // table the three left.
    if (frame == 55) {
      EXPECT_EQ(observed.size(), 4u);
    }
    if (frame >= 70 && frame <= 100) {
      EXPECT_EQ(observed.size(), 3u) << "keyframe at frame " << frame;
    }
    ++count;
  }
  EXPECT_EQ(count, keyframes);
}

// The first 60 frames' objects, then the SLAM map moved by a similarity (new world from
// old world: a turn about up, a shift and, for a merge of maps, a scale) as the SLAM
// system reports it: frames' rigid poses in the new frame, points moved. The objects must
// follow their sightings' cameras to the same place, and size, in the new frame.
void ExpectObjectsFollowASimilarity(double scale) {
  const testing::SyntheticScene scene = testing::SynthesizeScene(testing::TableWithObjects());
  ObjectMapper mapper(ObjectsOptions{}, Paper(), scene.options.camera, true);
  Feed(scene, &mapper, 0, 60);
  const auto before = LiveByClass(mapper);
  ASSERT_EQ(before.size(), 4u);
  const double yaw = 0.4;
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
  const Sim3 moved(scale, turn, Eigen::Vector3d(0.5, -0.3, 0.1));
  SlamMapChanges view;
  view.everything = true;
  for (int frame = 0; frame < 60; ++frame) {
    const Sim3 S_cw = Sim3(scene.T_cw[static_cast<std::size_t>(frame)]) * moved.Inverse();
    view.frame_poses[frame] = SE3(S_cw.rotation(), S_cw.translation() / S_cw.scale());
  }
  // The map points of the table (points far off it would sway the supporting plane).
  for (int i = 0; i < scene.options.points_on_table; ++i) {
    view.points.push_back(
        {static_cast<std::uint64_t>(i), moved * scene.points[static_cast<std::size_t>(i)], {}});
  }
  for (const auto& [frame, T_cw] : view.frame_poses)
    view.camera_rotations.emplace_back(frame, T_cw.Inverse().rotation());
  mapper.FollowSlamMap(view, 1);
  EXPECT_LT((mapper.Up() - Eigen::Vector3d::UnitZ()).norm(), 0.02);
  const auto after = LiveByClass(mapper);
  ASSERT_EQ(after.size(), 4u);
  for (const auto& [class_id, object] : before) {
    const nlohmann::json& cuboid = after.at(class_id)["cuboid"];
    EXPECT_LT((Centre(cuboid) - moved * Centre(object["cuboid"])).norm(), 0.01 * scale) << class_id;
    const double size_before = object["cuboid"]["size"][2].get<double>();
    EXPECT_NEAR(cuboid["size"][2].get<double>(), scale * size_before, 0.05 * scale * size_before)
        << class_id << ": height";
  }
}

// Bundle adjustment moved the whole map (a turn about up and a shift).
TEST(ObjectMapper, FollowsTheSlamMapWhenItsFrameMoves) { ExpectObjectsFollowASimilarity(1.0); }

// A merge of SLAM maps moves the current map into another's frame and units (docs/slam.md
// "the atlas"): the object layer follows it as it follows any correction.
TEST(ObjectMapper, FollowsAMergeOfTheSlamMap) { ExpectObjectsFollowASimilarity(0.6); }

// Frames whose poses did not change need not be given: following a map in which the last
// 20 of 60 frames moved (a local adjustment's window) with those 20 poses alone gives the
// objects every byte of what following it with all 60 gives, and they did move.
TEST(ObjectMapper, FollowingTheFramesThatMovedEqualsFollowingEveryFrame) {
  const testing::SyntheticScene scene = testing::SynthesizeScene(testing::TableWithObjects());
  SlamMapChanges every;
  every.everything = true;
  for (int i = 0; i < scene.options.points_on_table; ++i)
    every.points.push_back(
        {static_cast<std::uint64_t>(i), scene.points[static_cast<std::size_t>(i)], {}});
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(0.03, Eigen::Vector3d::UnitX()));
  SlamMapChanges moved_only = every;
  for (int frame = 0; frame < 60; ++frame) {
    SE3 T_cw = scene.T_cw[static_cast<std::size_t>(frame)];
    if (frame >= 40) {
      T_cw = SE3(turn, Eigen::Vector3d(0.02, 0.0, 0.01)) * T_cw;
      moved_only.frame_poses[frame] = T_cw;
    }
    every.frame_poses[frame] = T_cw;
    every.camera_rotations.emplace_back(frame, T_cw.Inverse().rotation());
  }
  moved_only.camera_rotations = every.camera_rotations;
  std::vector<std::string> objects;
  for (const SlamMapChanges* changes : {&every, &moved_only}) {
    ObjectMapper mapper(ObjectsOptions{}, Paper(), scene.options.camera, true);
    Feed(scene, &mapper, 0, 60);
    const std::string before = mapper.ObjectsJson();
    mapper.FollowSlamMap(*changes, 1);
    objects.push_back(mapper.ObjectsJson());
    EXPECT_NE(objects.back(), before);
  }
  EXPECT_EQ(objects[0], objects[1]);
}

// Following the SLAM map costs what changed, not what the map holds: with the same changes
// per keyframe (points added, the adjustment's window moved, points culled), a map of
// 50,000 points costs a keyframe about as many points touched as one of 5,000 (a full
// read would touch ten times more), the supporting plane (Objects.plane_refit_share 0.1)
// fitted again only once a share of the map has changed and still the floor's; and the
// copy holds every live point.
TEST(ObjectMapper, FollowingTheSlamMapTouchesWhatChangedNotTheWholeMap) {
  const testing::SyntheticScene scene = testing::SynthesizeScene(testing::TableWithObjects());
  std::vector<double> touched;
  ObjectsOptions options;
  options.plane_refit_share = 0.1;
  for (const std::size_t size : {5000u, 50000u}) {
    ObjectMapper mapper(options, Paper(), scene.options.camera, true);
    testing::GrowingSlamMap growing;
    std::uint64_t seed = 0;
    while (growing.points() < size) mapper.FollowSlamMap(growing.NextKeyframe(), ++seed);
    constexpr int kKeyframes = 40;
    std::size_t points = 0;
    int refits = 0;
    for (int k = 0; k < kKeyframes; ++k) {
      mapper.FollowSlamMap(growing.NextKeyframe(), ++seed);
      const SlamFollowWork work = mapper.LastFollowWork();
      points += work.points_changed + work.plane_points;
      refits += work.plane_refit ? 1 : 0;
      EXPECT_LT((mapper.Up() - Eigen::Vector3d::UnitZ()).norm(), 0.02) << size << ", " << k;
    }
    EXPECT_EQ(mapper.SlamMap().points().size(), growing.points());
    EXPECT_LT(refits, kKeyframes / 2) << size;
    touched.push_back(static_cast<double>(points) / kKeyframes);
    EXPECT_LT(touched.back(), 0.5 * static_cast<double>(size)) << size;
  }
  EXPECT_LT(touched[1], 1.5 * touched[0]);
}

}  // namespace
}  // namespace ocg
