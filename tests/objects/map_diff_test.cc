// Moves linked from removals and appearances, and the diff of two object maps, on
// constructed maps with known answers.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "ocg/core/file_io.h"
#include "ocg/io/text_lines.h"
#include "ocg/objects/map_diff.h"
#include "ocg/objects/map_frames.h"
#include "test_support.h"

namespace ocg {
namespace {

constexpr int kCup = 41, kBowl = 45, kBook = 73, kLaptop = 63, kMouse = 64;

ObjectRecord Record(ObjectId id, int class_id, double x, double y, double extent,
                    double first_seen = 0, double last_seen = 0) {
  ObjectRecord record;
  record.id = id;
  record.class_id = class_id;
  record.cuboid.centre = Eigen::Vector3d(x, y, 0.8);
  record.cuboid.size = Eigen::Vector3d(extent, 0.6 * extent, 0.5 * extent);
  record.first_seen = first_seen;
  record.last_seen = last_seen;
  return record;
}

std::vector<std::pair<ObjectId, ObjectId>> Pairs(const std::vector<MoveLink>& links) {
  std::vector<std::pair<ObjectId, ObjectId>> pairs;
  for (const MoveLink& link : links) pairs.emplace_back(link.from.id, link.to.id);
  return pairs;
}

TEST(LinkMoves, SameClassWithinReachAndBeyondTheSamePlaceIsAMove) {
  const MoveLinkOptions options;  // within 10 extents, beyond one
  const std::vector<ObjectRecord> removed = {Record(1, kCup, 0, 0, 0.1, 0, 10)};
  // Appeared 0.5 m away after the cup was last seen: a move, with both cuboids.
  std::vector<MoveLink> links = LinkMoves(removed, {Record(7, kCup, 0.5, 0, 0.1, 20, 30)}, options);
  ASSERT_EQ(links.size(), 1u);
  EXPECT_EQ(links[0].from.id, 1);
  EXPECT_EQ(links[0].to.id, 7);
  EXPECT_NEAR(links[0].distance, 0.5, 1e-12);
  EXPECT_NEAR(links[0].to.cuboid.centre.x(), 0.5, 1e-12);
  // Two maps hold no times: one first seen while the cup was still seen links all the
  // same (within a session the change log orders by time, ChangeLog.SeenTogetherIsNoMove).
  EXPECT_EQ(LinkMoves(removed, {Record(7, kCup, 0.5, 0, 0.1, 5, 30)}, options).size(), 1u);
  // Another class, too far for its size (1.5 m > 10 x 0.1 m), or overlapping its old
  // place (0.08 m < one extent: the same cup re-created): none.
  EXPECT_TRUE(LinkMoves(removed, {Record(7, kBowl, 0.5, 0, 0.1, 20)}, options).empty());
  EXPECT_TRUE(LinkMoves(removed, {Record(7, kCup, 1.5, 0, 0.1, 20)}, options).empty());
  EXPECT_TRUE(LinkMoves(removed, {Record(7, kCup, 0.08, 0, 0.1, 20)}, options).empty());
  // The same 1.5 m is within reach of a laptop (0.33 m: 3.3 m).
  EXPECT_EQ(LinkMoves({Record(2, kLaptop, 0, 0, 0.33, 0, 10)},
                      {Record(8, kLaptop, 1.5, 0, 0.33, 20)}, options)
                .size(),
            1u);
}

TEST(LinkMoves, NearestPairsFirstEachObjectOnceAndScaleFree) {
  const std::vector<ObjectRecord> removed = {Record(1, kCup, 0, 0, 0.1, 0, 10),
                                             Record(2, kCup, 0.6, 0, 0.1, 0, 10)};
  const std::vector<ObjectRecord> appeared = {Record(11, kCup, 0.85, 0, 0.1, 20),
                                              Record(12, kCup, -0.3, 0, 0.1, 20),
                                              Record(13, kCup, 0.85, 0.35, 0.1, 20)};
  const auto pairs = Pairs(LinkMoves(removed, appeared, {}));
  // 2 -> 11 (0.25 m) first; then 1 -> 12 (0.3 m) and 13 is left over (2 is taken).
  ASSERT_EQ(pairs.size(), 2u);
  EXPECT_EQ(pairs[0], std::make_pair(ObjectId{2}, ObjectId{11}));
  EXPECT_EQ(pairs[1], std::make_pair(ObjectId{1}, ObjectId{12}));
  // The same scene in another map scale (monocular) links the same objects.
  auto scaled = [](std::vector<ObjectRecord> records) {
    for (ObjectRecord& record : records) {
      record.cuboid.centre *= 3.7;
      record.cuboid.size *= 3.7;
    }
    return records;
  };
  EXPECT_EQ(Pairs(LinkMoves(scaled(removed), scaled(appeared), {})), pairs);
  MoveLinkOptions bad;
  bad.same_place_factor = 20;
  EXPECT_THROW(LinkMoves(removed, appeared, bad), std::invalid_argument);
}

TEST(MapDiff, ListsUnchangedMovedRemovedAndAdded) {
  const std::vector<ObjectRecord> before = {
      Record(1, kCup, 0, 0, 0.1), Record(2, kBook, 1, 0, 0.23), Record(3, kLaptop, 2, 0, 0.33),
      Record(4, kCup, 0, 1.5, 0.1), Record(5, kMouse, -1, 0, 0.11)};
  const std::vector<ObjectRecord> after = {
      Record(1, kCup, 0.01, 0, 0.1),       // the same object, same id
      Record(12, kBook, 1.02, 0, 0.23),    // the same book, numbered by another run
      Record(13, kLaptop, 2, 1.5, 0.33),   // the laptop moved 1.5 m
      Record(20, kMouse, -1, -2.5, 0.11),  // a mouse too far from the old one: added
  };
  const MapDiff diff = DiffObjectMaps(before, after, {});
  ASSERT_EQ(diff.unchanged.size(), 2u);
  EXPECT_EQ(Pairs(diff.unchanged), (std::vector<std::pair<ObjectId, ObjectId>>{{1, 1}, {2, 12}}));
  ASSERT_EQ(diff.moved.size(), 1u);
  EXPECT_EQ(diff.moved[0].from.id, 3);
  EXPECT_EQ(diff.moved[0].to.id, 13);
  EXPECT_NEAR(diff.moved[0].distance, 1.5, 1e-12);
  ASSERT_EQ(diff.removed.size(), 2u);  // the far cup has no cup to have moved to
  EXPECT_EQ(diff.removed[0].id, 4);
  EXPECT_EQ(diff.removed[1].id, 5);
  ASSERT_EQ(diff.added.size(), 1u);
  EXPECT_EQ(diff.added[0].id, 20);
  // Equal ids win over a nearer object of another id at the same place.
  const MapDiff ids =
      DiffObjectMaps({Record(1, kCup, 0, 0, 0.1), Record(2, kCup, 0.02, 0, 0.1)},
                     {Record(2, kCup, 0.0, 0, 0.1), Record(1, kCup, 0.02, 0, 0.1)}, {});
  EXPECT_EQ(Pairs(ids.unchanged), (std::vector<std::pair<ObjectId, ObjectId>>{{1, 1}, {2, 2}}));
  // The JSON lists the same counts.
  const nlohmann::json json = nlohmann::json::parse(MapDiffJson(diff));
  EXPECT_EQ(json["format"], "ocg-map-diff");
  EXPECT_EQ(json["counts"]["moved"], 1);
  EXPECT_EQ(json["counts"]["removed"], 2);
  EXPECT_EQ(json["moved"][0]["from"]["id"], 3);
  EXPECT_EQ(json["moved"][0]["to"]["cuboid"]["centre"][1], 1.5);
}

// A later session's run paired vase 11 with vase 32 (its change log); nearest first, the
// diff alone would take vase 36.
TEST(MapDiff, TheMovesTheLaterRunRecordedComeFirst) {
  const int kVase = 75;
  const std::vector<ObjectRecord> before = {Record(11, kVase, 0, 0, 0.1),
                                            Record(12, kCup, 1, 0, 0.1)};
  const std::vector<ObjectRecord> after = {
      Record(32, kVase, 0.6, 0, 0.1), Record(36, kVase, 0.3, 0, 0.1), Record(12, kCup, 1, 0, 0.1)};
  const MapDiff alone = DiffObjectMaps(before, after, {});
  EXPECT_EQ(Pairs(alone.moved), (std::vector<std::pair<ObjectId, ObjectId>>{{11, 36}}));
  const MapDiff recorded = DiffObjectMaps(before, after, {}, {{11, 32, 1}, {99, 12, 1}});
  EXPECT_EQ(Pairs(recorded.moved), (std::vector<std::pair<ObjectId, ObjectId>>{{11, 32}}));
  EXPECT_TRUE(recorded.moved[0].recorded);
  ASSERT_EQ(recorded.added.size(), 1u);  // a move naming an object not in before: ignored
  EXPECT_EQ(recorded.added[0].id, 36);
  EXPECT_EQ(Pairs(recorded.unchanged), (std::vector<std::pair<ObjectId, ObjectId>>{{12, 12}}));
  const nlohmann::json json = nlohmann::json::parse(MapDiffJson(recorded, "m", "why"));
  EXPECT_EQ(json["moved"][0]["recorded"], true);
  EXPECT_EQ(json["distance_unit"], "m");
  EXPECT_EQ(json["frame"], "why");
}

SavedObjectMap RunMap(std::vector<ObjectRecord> objects, int session, std::string loaded,
                      std::string saved, std::vector<RecordedMove> moves = {}) {
  SavedObjectMap map;
  map.objects = std::move(objects);
  map.run = RunRecord{"run" + std::to_string(session),
                      session,
                      std::move(loaded),
                      std::move(saved),
                      false,
                      std::move(moves)};
  return map;
}

TEST(MapDiff, MovesSinceAreTheLaterSessionsOfARunThatContinuedTheMap) {
  const SavedObjectMap before = RunMap({}, 0, "", "maps/a.ocgmap");
  const std::vector<RecordedMove> log = {{3, 4, 0}, {11, 32, 1}};
  const SavedObjectMap after = RunMap({}, 1, "maps/a.ocgmap", "", log);
  const std::vector<RecordedMove> since = MovesSince(before, after);
  ASSERT_EQ(since.size(), 1u);  // session 0's move was already in before's map
  EXPECT_EQ(since[0].from, 11);
  EXPECT_EQ(since[0].to, 32);
  // Another run's log names other objects; a bare objects.json has none.
  EXPECT_TRUE(MovesSince(before, RunMap({}, 1, "maps/b.ocgmap", "", log)).empty());
  SavedObjectMap bare;
  EXPECT_TRUE(MovesSince(bare, after).empty());
}

TEST(MapDiff, DistancesAreMetresOnlyWhenBothMapsWereMadeOnGivenPoses) {
  SavedObjectMap posed = RunMap({}, 0, "", ""), slam = posed, bare;
  posed.run->poses_given = true;
  EXPECT_EQ(DistanceUnit(posed, posed), "m");
  EXPECT_EQ(DistanceUnit(posed, slam), "map units");
  EXPECT_EQ(DistanceUnit(bare, bare), "map units");
}

// Eight objects of five classes on a table, and the same seen in another frame.
std::vector<ObjectRecord> Table() {
  return {Record(1, kCup, 0, 0, 0.1),         Record(2, kCup, 0.7, 0.2, 0.1),
          Record(3, kBook, 1, -0.4, 0.23),    Record(4, kLaptop, -0.8, 0.5, 0.33),
          Record(5, kMouse, -0.3, -0.6, 0.1), Record(6, kBowl, 0.4, 0.9, 0.15),
          Record(7, kBook, -1.2, -0.2, 0.23), Record(8, kLaptop, 1.3, 0.8, 0.33)};
}

std::vector<ObjectRecord> Transformed(std::vector<ObjectRecord> records, double scale, double turn,
                                      const Eigen::Vector3d& shift) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (ObjectRecord& record : records) {
    record.id += 100;
    record.cuboid.centre = scale * (R * record.cuboid.centre) + shift;
    record.cuboid.size *= scale;
    record.cuboid.yaw += turn;
  }
  return records;
}

TEST(CheckOneFrame, AMapInAnotherFrameIsToldFromOneWithMoves) {
  SavedObjectMap before, after;
  before.objects = Table();
  // One frame, two objects moved and one gone.
  after.objects = Table();
  after.objects[0].cuboid.centre.x() += 0.5;
  after.objects[3].cuboid.centre.y() -= 1.0;
  after.objects.pop_back();
  const FrameCheck same = CheckOneFrame(before, after, {});
  EXPECT_TRUE(same.one_frame) << same.evidence;
  EXPECT_EQ(same.same_place_as_given, 5);
  // The same table in a SLAM map's frame: scaled, turned and shifted; one object moved.
  after.objects = Transformed(Table(), 1.5, 0.7, Eigen::Vector3d(0.4, -0.3, 0.2));
  after.objects[1].cuboid.centre.x() += 0.6;
  const FrameCheck other = CheckOneFrame(before, after, {});
  EXPECT_FALSE(other.one_frame) << other.evidence;
  EXPECT_EQ(other.same_place_aligned, 7);
  EXPECT_LE(other.same_place_as_given, 2);
  EXPECT_NEAR(other.scale, 1 / 1.5, 1e-6);  // the later map onto the earlier
  EXPECT_NEAR(other.turn, 0.7, 1e-6);
  EXPECT_NE(other.evidence.find("scaled by 0.667"), std::string::npos) << other.evidence;
  // Different up directions: the turn about up is found in each map's gravity frame.
  after.up = Eigen::Vector3d(0, -1, 0);
  const Eigen::Matrix3d tilt = GravityFrame(after.up);
  for (ObjectRecord& record : after.objects) record.cuboid.centre = tilt * record.cuboid.centre;
  EXPECT_FALSE(CheckOneFrame(before, after, {}).one_frame);
  // A session record says one map whatever the objects say.
  before.run = RunRecord{"a", 0, "", "m.ocgmap", false, {}};
  after.run = RunRecord{"b", 1, "m.ocgmap", "", false, {}};
  const FrameCheck recorded = CheckOneFrame(before, after, {});
  EXPECT_TRUE(recorded.one_frame);
  EXPECT_NE(recorded.evidence.find("continued the map file 'm.ocgmap'"), std::string::npos);
}

TEST(CheckOneFrame, TooFewObjectsToTellAreTakenAsOneFrame) {
  SavedObjectMap before, after;
  before.objects = {Record(1, kCup, 0, 0, 0.1), Record(2, kLaptop, 1, 0, 0.33)};
  after.objects = Transformed(before.objects, 2.0, 1.0, Eigen::Vector3d(1, 1, 0));
  EXPECT_TRUE(CheckOneFrame(before, after, {}).one_frame);
}

TEST(ObjectMapReader, ReadsObjectsJsonAndRefusesOtherFilesNamingThem) {
  const std::string dir = testing::MakeTempDir("map_reader");
  WriteFile(dir + "/objects.json",
            R"({"format": "ocg-objects", "version": 1, "up": [0, 0, 1], "objects": [
                {"id": 4, "class_id": 41, "cuboid": {"centre": [1, 2, 3], "size": [0.1, 0.1, 0.1],
                 "yaw": 0.5}, "first_seen": 1000.5, "last_seen": 1010}]})");
  const auto readers = ObjectMapReaders();
  for (const std::string& path : {dir, dir + "/objects.json"}) {  // a run folder or the file
    const SavedObjectMap map = ReadObjectMap(path, readers);
    ASSERT_EQ(map.objects.size(), 1u);
    EXPECT_EQ(map.objects[0].id, 4);
    EXPECT_EQ(map.objects[0].cuboid.centre, Eigen::Vector3d(1, 2, 3));
    EXPECT_EQ(map.objects[0].cuboid.yaw, 0.5);
    EXPECT_EQ(map.objects[0].first_seen, 1000.5);
  }
  EXPECT_FALSE(ReadObjectMap(dir, readers).run) << "no run.json: no run record";
  WriteFile(dir + "/run.json", R"({"command": "objects", "session": {"index": 2,
             "map_loaded": "a.ocgmap", "map_saved": null}})");
  WriteFile(dir + "/changes.json", R"({"changes": [
             {"type": "moved", "object_id": 3, "session": 2, "to": {"object_id": 4}},
             {"type": "moved", "object_id": 5, "session": 2, "to": {"object_id": 6}},
             {"type": "restored", "object_id": 5}]})");
  const SavedObjectMap run = ReadObjectMap(dir, readers);
  ASSERT_TRUE(run.run);
  EXPECT_EQ(run.run->session, 2);
  EXPECT_EQ(run.run->map_loaded, "a.ocgmap");
  EXPECT_EQ(run.run->map_saved, "");
  EXPECT_TRUE(run.run->poses_given);
  ASSERT_EQ(run.run->moves.size(), 1u);  // the restored object moved nowhere
  EXPECT_EQ(run.run->moves[0].from, 3);
  EXPECT_EQ(run.run->moves[0].to, 4);
  WriteFile(dir + "/other.json", R"({"changes": []})");
  try {
    ReadObjectMap(dir + "/other.json", readers);
    FAIL() << "a foreign file was read";
  } catch (const FileError& error) {
    EXPECT_NE(std::string(error.what()).find("other.json"), std::string::npos);
    EXPECT_NE(std::string(error.what()).find("objects.json"), std::string::npos);
  }
  WriteFile(dir + "/cut.json", R"({"format": "ocg-objects", "objects": [{"id": 4, "cla)");
  EXPECT_THROW(ReadObjectMap(dir + "/cut.json", readers), ParseError);
  EXPECT_THROW(ReadObjectMap(dir + "/missing.json", readers), FileError);
}

}  // namespace
}  // namespace ocg
