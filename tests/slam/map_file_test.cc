#include "ocg/slam/map_file.h"

#include <gtest/gtest.h>

#include <cstring>
#include <sstream>

#include "random_map.h"

namespace ocg {
namespace {

void ExpectSamePose(const SE3& a, const SE3& b, const std::string& what) {
  EXPECT_LT((a.Matrix() - b.Matrix()).cwiseAbs().maxCoeff(), 1e-15) << what;
}

void ExpectSamePoint(const MapPoint& a, const MapPoint& b) {
  const std::string what = "point " + std::to_string(a.id);
  EXPECT_EQ(a.id, b.id);
  EXPECT_EQ(a.position, b.position) << what;
  EXPECT_EQ(a.descriptor, b.descriptor) << what;
  EXPECT_EQ(a.normal, b.normal) << what;
  EXPECT_EQ(a.min_distance, b.min_distance) << what;
  EXPECT_EQ(a.max_distance, b.max_distance) << what;
  EXPECT_EQ(a.observations, b.observations) << what;
  EXPECT_EQ(a.reference, b.reference) << what;
  EXPECT_EQ(a.first_keyframe, b.first_keyframe) << what;
  EXPECT_EQ(a.first_frame, b.first_frame) << what;
  EXPECT_EQ(a.visible, b.visible) << what;
  EXPECT_EQ(a.found, b.found) << what;
  EXPECT_EQ(a.bad, b.bad) << what;
}

void ExpectSameKeyFrame(const KeyFrame& a, const KeyFrame& b) {
  const std::string what = "keyframe " + std::to_string(a.id);
  EXPECT_EQ(a.id, b.id);
  EXPECT_EQ(a.frame_id, b.frame_id) << what;
  EXPECT_EQ(a.timestamp, b.timestamp) << what;
  EXPECT_EQ(a.timestamp_text, b.timestamp_text) << what;
  ExpectSamePose(a.T_cw, b.T_cw, what);
  ASSERT_EQ(a.features.size(), b.features.size()) << what;
  for (std::size_t i = 0; i < a.features.size(); ++i) {
    const cv::KeyPoint& p = a.features.keypoints[i];
    const cv::KeyPoint& q = b.features.keypoints[i];
    EXPECT_TRUE(p.pt == q.pt && p.size == q.size && p.angle == q.angle &&
                p.response == q.response && p.octave == q.octave && p.class_id == q.class_id)
        << what << " keypoint " << i;
    ASSERT_EQ(a.features.undistorted[i], b.features.undistorted[i]) << what;
    ASSERT_EQ(a.features.descriptors[i], b.features.descriptors[i]) << what;
    ASSERT_EQ(a.points[i] ? a.points[i]->id : 0, b.points[i] ? b.points[i]->id : 0) << what;
    ASSERT_EQ(a.points[i] == nullptr, b.points[i] == nullptr) << what;
  }
  // The rebuilt grid answers radius queries as the saved one did.
  EXPECT_EQ(a.features.grid.columns(), b.features.grid.columns());
  EXPECT_EQ(a.features.grid.OccupiedCells(), b.features.grid.OccupiedCells()) << what;
  EXPECT_EQ(a.features.grid.InArea(320, 240, 60), b.features.grid.InArea(320, 240, 60)) << what;
  EXPECT_EQ(a.bow.entries, b.bow.entries) << what;
  EXPECT_EQ(a.feature_vector, b.feature_vector) << what;
  EXPECT_EQ(a.covisible, b.covisible) << what;
  EXPECT_EQ(a.ordered_covisible, b.ordered_covisible) << what;
  EXPECT_EQ(a.parent, b.parent) << what;
  EXPECT_EQ(a.has_parent, b.has_parent) << what;
  EXPECT_EQ(a.children, b.children) << what;
  EXPECT_EQ(a.loop_edges, b.loop_edges) << what;
  EXPECT_EQ(a.bad, b.bad) << what;
  ExpectSamePose(a.T_c_parent, b.T_c_parent, what);
}

constexpr int kLevels = 8;  // FillRandomMap's keypoints lie on levels 0 to 7

std::string Saved(const Map& map) {
  std::ostringstream out;
  SaveMap(map, out);
  return out.str();
}

TEST(SlamMapFile, RoundTripKeepsEveryField) {
  Map map;
  testing::FillRandomMap(120, 200, 7, &map);
  ASSERT_GT(map.points().size(), 1000u);
  const std::string bytes = Saved(map);
  Map loaded;
  std::istringstream in(bytes);
  LoadMap(in, &loaded, kLevels);
  EXPECT_EQ(loaded.next_keyframe_id(), map.next_keyframe_id());
  EXPECT_EQ(loaded.next_map_point_id(), map.next_map_point_id());
  ASSERT_EQ(loaded.points().size(), map.points().size());
  for (const auto& [id, point] : map.points()) ExpectSamePoint(*point, *loaded.points().at(id));
  ASSERT_EQ(loaded.keyframes().size(), map.keyframes().size());
  int bad = 0;
  for (const auto& [id, keyframe] : map.keyframes()) {
    ExpectSameKeyFrame(*keyframe, *loaded.GetKeyFrame(id));
    bad += keyframe->bad ? 1 : 0;
  }
  EXPECT_GE(bad, 2);  // culled keyframes are kept (frames may be anchored to them)
  // The links are pointers into the loaded map, not copies.
  for (const auto& [id, keyframe] : loaded.keyframes()) {
    for (const MapPointPtr& point : keyframe->points) {
      if (point) {
        EXPECT_EQ(point, loaded.points().at(point->id));
      }
    }
  }
  // Saving the loaded map gives the same bytes.
  EXPECT_EQ(Saved(loaded), bytes);
}

// Keyframes and points with id >= the given ones are retagged as map `tag`.
void Retag(Map* map, KeyFrameId first_keyframe, MapPointId first_point, int tag) {
  for (const auto& [id, keyframe] : map->keyframes()) {
    if (id >= first_keyframe) keyframe->map = tag;
  }
  for (const auto& [id, point] : map->points()) {
    if (id >= first_point) point->map = tag;
  }
}

// An atlas of three maps: 0, then 1 (current), then 2, merged into 0.
void FillAtlas(Map* map) {
  testing::FillRandomMap(30, 90, 11, map);
  for (int tag = 1; tag <= 2; ++tag) {
    map->StartNewMap();
    const KeyFrameId first_keyframe = map->next_keyframe_id();
    const MapPointId first_point = map->next_map_point_id();
    testing::FillRandomMap(20 + 5 * tag, 90, 11 + static_cast<std::uint64_t>(tag), map);
    Retag(map, first_keyframe, first_point, tag);
  }
  map->MoveMap(2, 0, Sim3(1.5, Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero()));
  map->SetCurrentMap(1);
}

// Every map of the atlas is saved with its keyframes, points and index, the current map
// and the merges; the loaded atlas equals the saved one and saves to the same bytes.
TEST(SlamMapFile, EveryMapOfTheAtlasRoundTrips) {
  Map map;
  FillAtlas(&map);
  const std::vector<MapMerge> merges = {{2, 0, 77, 1.5}};
  std::ostringstream out;
  SaveMap(map, out, merges);
  const std::string bytes = out.str();
  Map loaded;
  std::istringstream in(bytes);
  const std::vector<MapMerge> loaded_merges = LoadMap(in, &loaded, kLevels);
  EXPECT_EQ(loaded.map_count(), 3);
  EXPECT_EQ(loaded.current_map(), 1);
  for (int m = 0; m < 3; ++m) {
    EXPECT_EQ(loaded.KeyFrameCount(m), map.KeyFrameCount(m)) << "map " << m;
    EXPECT_EQ(loaded.LiveKeyFrameCount(m), map.LiveKeyFrameCount(m)) << "map " << m;
  }
  EXPECT_GT(map.KeyFrameCount(0), 40u);  // map 2 went into it
  EXPECT_EQ(map.KeyFrameCount(2), 0u);
  EXPECT_EQ(loaded.FirstKeyFrame(1), KeyFrameId{30});  // map 0 has ids 0 to 29
  ASSERT_EQ(loaded.keyframes().size(), map.keyframes().size());
  for (const auto& [id, keyframe] : map.keyframes()) {
    ExpectSameKeyFrame(*keyframe, *loaded.GetKeyFrame(id));
    EXPECT_EQ(loaded.GetKeyFrame(id)->map, keyframe->map) << id;
  }
  ASSERT_EQ(loaded.points().size(), map.points().size());
  for (const auto& [id, point] : map.points()) {
    ExpectSamePoint(*point, *loaded.points().at(id));
    EXPECT_EQ(loaded.points().at(id)->map, point->map) << id;
  }
  ASSERT_EQ(loaded_merges.size(), 1u);
  EXPECT_EQ(loaded_merges[0].merged_map, 2);
  EXPECT_EQ(loaded_merges[0].into_map, 0);
  EXPECT_EQ(loaded_merges[0].frame, 77u);
  EXPECT_EQ(loaded_merges[0].scale, 1.5);
  std::ostringstream again;
  SaveMap(loaded, again, loaded_merges);
  EXPECT_EQ(again.str(), bytes);
}

// The layout of files before the atlas: the current map alone, loaded as map 0.
TEST(SlamMapFile, TheSingleMapFormatHoldsTheCurrentMapAsMapZero) {
  Map map;
  FillAtlas(&map);
  std::ostringstream out;
  SaveMap(map, out, {}, MapFileFormat::kSingleMap);
  Map loaded;
  std::istringstream in(out.str());
  EXPECT_TRUE(LoadMap(in, &loaded, kLevels, MapFileFormat::kSingleMap).empty());
  EXPECT_EQ(loaded.map_count(), 1);
  EXPECT_EQ(loaded.current_map(), 0);
  EXPECT_EQ(loaded.KeyFrameCount(0), map.KeyFrameCount(1));
  for (const auto& [id, keyframe] : loaded.keyframes())
    ExpectSameKeyFrame(*map.GetKeyFrame(id), *keyframe);
}

// A point seen from a keyframe of another map would join two maps that share nothing:
// the file contradicts itself, and is refused.
TEST(SlamMapFile, APointSeenFromAnotherMapIsRefused) {
  Map map;
  FillAtlas(&map);
  const MapPointPtr point = map.points().begin()->second;
  ASSERT_EQ(point->map, 0);
  point->map = 1;
  std::ostringstream out;
  SaveMap(map, out);
  Map loaded;
  std::istringstream in(out.str());
  try {
    LoadMap(in, &loaded, kLevels);
    ADD_FAILURE() << "loaded";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("of map 1 is observed by keyframe"), std::string::npos)
        << error.what();
  }
  EXPECT_TRUE(loaded.keyframes().empty() && loaded.points().empty());
}

// Keyframes culled in the run (EraseKeyFrame releases their features) save and load.
TEST(SlamMapFile, KeyFramesCulledInTheRunRoundTrip) {
  Map map;
  testing::FillRandomMap(20, 80, 5, &map);
  std::size_t erased = 0;
  for (const auto& [id, keyframe] : map.keyframes()) {
    if (id % 3 == 1 && !keyframe->bad) {
      map.EraseKeyFrame(keyframe);
      erased += keyframe->bad ? 1 : 0;
    }
  }
  ASSERT_GT(erased, 2u);
  const std::string bytes = Saved(map);
  std::istringstream in(bytes);
  Map loaded;
  LoadMap(in, &loaded, kLevels);
  for (const auto& [id, keyframe] : map.keyframes())
    ExpectSameKeyFrame(*keyframe, *loaded.GetKeyFrame(id));
  EXPECT_EQ(Saved(loaded), bytes);
}

// A BoW entry (word id, weight) has 4 bytes of padding that nothing sets: the file must
// not depend on them, or two saves of one map differ (and uninitialised memory is written).
TEST(SlamMapFile, PaddingBytesDoNotReachTheFile) {
  Map map;
  testing::FillRandomMap(10, 60, 3, &map);
  const std::string before = Saved(map);
  int entries = 0;
  for (const auto& [id, keyframe] : map.keyframes()) {
    std::vector<std::pair<WordId, double>>& kept = keyframe->bow.entries;
    std::vector<std::pair<WordId, double>> dirty(kept.size());
    // The same values, set member by member in storage whose padding holds 0xAB (a copy of
    // a whole pair would carry the source's padding instead).
    std::memset(static_cast<void*>(dirty.data()), 0xAB, sizeof(kept[0]) * dirty.size());
    for (std::size_t i = 0; i < kept.size(); ++i) {
      dirty[i].first = kept[i].first;
      dirty[i].second = kept[i].second;
    }
    kept.swap(dirty);
    entries += static_cast<int>(kept.size());
  }
  ASSERT_GT(entries, 0);
  EXPECT_EQ(Saved(map), before);
}

TEST(SlamMapFile, NewIdsAfterLoadingDoNotReuseSavedOnes) {
  Map map;
  testing::FillRandomMap(10, 60, 3, &map);
  std::istringstream in(Saved(map));
  Map loaded;
  LoadMap(in, &loaded, kLevels);
  EXPECT_EQ(loaded.NextKeyFrameId(), 10u);
  EXPECT_EQ(loaded.NextMapPointId(), map.next_map_point_id());
}

TEST(SlamMapFile, TruncatedStreamThrowsAndLeavesTheMapEmpty) {
  Map map;
  testing::FillRandomMap(10, 60, 3, &map);
  const std::string bytes = Saved(map);
  for (const std::size_t size : {std::size_t{4}, bytes.size() / 2, bytes.size() - 1}) {
    std::istringstream in(bytes.substr(0, size));
    Map loaded;
    EXPECT_THROW(LoadMap(in, &loaded, kLevels), std::runtime_error) << size << " bytes";
    EXPECT_TRUE(loaded.keyframes().empty() && loaded.points().empty());
  }
}

TEST(SlamMapFile, LoadingIntoAMapThatHoldsSomethingIsRefused) {
  Map map;
  testing::FillRandomMap(3, 30, 1, &map);
  std::istringstream in(Saved(map));
  EXPECT_THROW(LoadMap(in, &map, kLevels), std::logic_error);
}

// A map made with a deeper pyramid than the one it is loaded for would index the
// pyramid's per-level tables past their end (scale distances, sigma2): refused at load,
// naming the keyframe, the level and the pyramid's size.
TEST(SlamMapFile, KeypointsBeyondThePyramidAreRefusedAtLoad) {
  Map map;
  testing::FillRandomMap(10, 60, 3, &map);
  const std::string bytes = Saved(map);
  for (const int levels : {3, 7}) {
    std::istringstream in(bytes);
    Map loaded;
    try {
      LoadMap(in, &loaded, levels);
      ADD_FAILURE() << "a map with keypoints on level 7 loaded for " << levels << " levels";
    } catch (const std::runtime_error& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find("lies on pyramid level"), std::string::npos) << message;
      EXPECT_NE(message.find("but the pyramid has " + std::to_string(levels) + " levels"),
                std::string::npos)
          << message;
    }
    EXPECT_TRUE(loaded.keyframes().empty() && loaded.points().empty());
  }
  std::istringstream in(bytes);
  Map loaded;
  EXPECT_NO_THROW(LoadMap(in, &loaded, 8));
}

}  // namespace
}  // namespace ocg
