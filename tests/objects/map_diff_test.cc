// Moves linked from removals and appearances, and the diff of two object maps, on
// constructed maps with known answers.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "ocg/core/file_io.h"
#include "ocg/io/text_lines.h"
#include "ocg/objects/map_diff.h"
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

TEST(LinkMoves, SameClassNearAndAfterTheLastSightingIsAMove) {
  const MoveLinkOptions options;  // within 10 extents, beyond one
  const std::vector<ObjectRecord> removed = {Record(1, kCup, 0, 0, 0.1, 0, 10)};
  // Appeared 0.5 m away after the cup was last seen: a move, with both cuboids.
  std::vector<MoveLink> links =
      LinkMoves(removed, {Record(7, kCup, 0.5, 0, 0.1, 20, 30)}, options, true);
  ASSERT_EQ(links.size(), 1u);
  EXPECT_EQ(links[0].from.id, 1);
  EXPECT_EQ(links[0].to.id, 7);
  EXPECT_NEAR(links[0].distance, 0.5, 1e-12);
  EXPECT_NEAR(links[0].to.cuboid.centre.x(), 0.5, 1e-12);
  // Seen while the cup was still seen at its place: a neighbour, not the cup moved.
  EXPECT_TRUE(LinkMoves(removed, {Record(7, kCup, 0.5, 0, 0.1, 5, 30)}, options, true).empty());
  EXPECT_EQ(LinkMoves(removed, {Record(7, kCup, 0.5, 0, 0.1, 5, 30)}, options, false).size(), 1u);
  // Another class, too far for its size (1.5 m > 10 x 0.1 m), or overlapping its old
  // place (0.08 m < one extent: the same cup re-created): none.
  EXPECT_TRUE(LinkMoves(removed, {Record(7, kBowl, 0.5, 0, 0.1, 20)}, options, true).empty());
  EXPECT_TRUE(LinkMoves(removed, {Record(7, kCup, 1.5, 0, 0.1, 20)}, options, true).empty());
  EXPECT_TRUE(LinkMoves(removed, {Record(7, kCup, 0.08, 0, 0.1, 20)}, options, true).empty());
  // The same 1.5 m is within reach of a laptop (0.33 m: 3.3 m).
  EXPECT_EQ(LinkMoves({Record(2, kLaptop, 0, 0, 0.33, 0, 10)},
                      {Record(8, kLaptop, 1.5, 0, 0.33, 20)}, options, true)
                .size(),
            1u);
}

TEST(LinkMoves, NearestPairsFirstEachObjectOnceAndScaleFree) {
  const std::vector<ObjectRecord> removed = {Record(1, kCup, 0, 0, 0.1, 0, 10),
                                             Record(2, kCup, 0.6, 0, 0.1, 0, 10)};
  const std::vector<ObjectRecord> appeared = {Record(11, kCup, 0.85, 0, 0.1, 20),
                                              Record(12, kCup, -0.3, 0, 0.1, 20),
                                              Record(13, kCup, 0.85, 0.35, 0.1, 20)};
  const auto pairs = Pairs(LinkMoves(removed, appeared, {}, true));
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
  EXPECT_EQ(Pairs(LinkMoves(scaled(removed), scaled(appeared), {}, true)), pairs);
  MoveLinkOptions bad;
  bad.same_place_factor = 20;
  EXPECT_THROW(LinkMoves(removed, appeared, bad, true), std::invalid_argument);
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
