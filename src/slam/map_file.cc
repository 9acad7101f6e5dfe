#include "ocg/slam/map_file.h"

#include <cereal/archives/binary.hpp>
#include <cereal/types/array.hpp>
#include <cereal/types/map.hpp>
#include <cereal/types/set.hpp>
#include <cereal/types/string.hpp>
#include <cereal/types/utility.hpp>
#include <cereal/types/vector.hpp>
#include <cstring>
#include <istream>
#include <limits>
#include <new>
#include <ostream>
#include <stdexcept>
#include <type_traits>

#include "ocg/core/cereal_types.h"

namespace ocg {
namespace {

constexpr MapPointId kNoPoint = std::numeric_limits<MapPointId>::max();

// Vectors of plain values (keypoints, pixels, descriptors) as one block each: a map of
// 500 keyframes holds half a million of each, and element-wise archiving would cost most
// of the load time. cv::KeyPoint and Eigen's fixed vectors declare copy constructors, so
// they are not "trivially copyable", but they are plain fields in standard layout.
template <class T>
void SaveBlock(cereal::BinaryOutputArchive& archive, const std::vector<T>& values) {
  static_assert(std::is_standard_layout_v<T>, "blocks of plain values only");
  archive(cereal::make_size_tag(static_cast<cereal::size_type>(values.size())));
  // Copied member by member into zeroed bytes: a value's padding (the 4 bytes after the
  // word id of a BoW entry) is never set, and writing it raw made two saves of one map
  // differ and wrote uninitialised memory into the file.
  std::vector<unsigned char> bytes(sizeof(T) * values.size(), 0);
  for (std::size_t i = 0; i < values.size(); ++i) new (bytes.data() + i * sizeof(T)) T(values[i]);
  archive(cereal::binary_data(bytes.data(), bytes.size()));
}
// A pair is written member by member into zeroed bytes: its implicit copy may move the
// whole 16 bytes of a pair<uint32_t, double>, padding included, so the generic copy above
// carried the uninitialised padding of BoW entries into the file and two runs wrote
// different map files. The layout is that of the vector's storage, as before.
template <class A, class B>
void SaveBlock(cereal::BinaryOutputArchive& archive, const std::vector<std::pair<A, B>>& values) {
  using T = std::pair<A, B>;
  static_assert(std::is_standard_layout_v<T> && std::is_trivially_copyable_v<A> &&
                    std::is_trivially_copyable_v<B>,
                "blocks of plain values only");
  archive(cereal::make_size_tag(static_cast<cereal::size_type>(values.size())));
  std::vector<unsigned char> bytes(sizeof(T) * values.size(), 0);
  for (std::size_t i = 0; i < values.size(); ++i) {
    const auto* base = reinterpret_cast<const unsigned char*>(&values[i]);
    const auto* first = reinterpret_cast<const unsigned char*>(&values[i].first);
    const auto* second = reinterpret_cast<const unsigned char*>(&values[i].second);
    unsigned char* out = bytes.data() + i * sizeof(T);
    std::memcpy(out + (first - base), first, sizeof(A));
    std::memcpy(out + (second - base), second, sizeof(B));
  }
  archive(cereal::binary_data(bytes.data(), bytes.size()));
}

template <class T>
void LoadBlock(cereal::BinaryInputArchive& archive, std::vector<T>* values) {
  cereal::size_type size = 0;
  archive(cereal::make_size_tag(size));
  values->resize(static_cast<std::size_t>(size));
  archive(cereal::binary_data(values->data(), sizeof(T) * values->size()));
}

void SavePoint(cereal::BinaryOutputArchive& archive, const MapPoint& point, MapFileFormat format) {
  archive(point.id, point.position, point.descriptor, point.normal, point.min_distance,
          point.max_distance, point.observations, point.reference, point.first_keyframe,
          point.first_frame, point.visible, point.found, point.bad);
  if (format == MapFileFormat::kAtlas) archive(point.map);
}

void LoadPoint(cereal::BinaryInputArchive& archive, MapPoint* point, MapFileFormat format) {
  archive(point->id, point->position, point->descriptor, point->normal, point->min_distance,
          point->max_distance, point->observations, point->reference, point->first_keyframe,
          point->first_frame, point->visible, point->found, point->bad);
  point->map = 0;
  if (format == MapFileFormat::kAtlas) archive(point->map);
}

void SaveKeyFrame(cereal::BinaryOutputArchive& archive, const KeyFrame& keyframe, const Map& map,
                  MapFileFormat format) {
  archive(keyframe.id, keyframe.frame_id, keyframe.timestamp, keyframe.timestamp_text,
          keyframe.T_cw);
  SaveBlock(archive, keyframe.features.keypoints);
  SaveBlock(archive, keyframe.features.undistorted);
  SaveBlock(archive, keyframe.features.descriptors);
  const FeatureGrid& grid = keyframe.features.grid;
  archive(grid.bounds().min_x, grid.bounds().max_x, grid.bounds().min_y, grid.bounds().max_y,
          grid.columns(), grid.rows());
  SaveBlock(archive, keyframe.bow.entries);
  archive(keyframe.feature_vector);
  std::vector<MapPointId> points(keyframe.points.size(), kNoPoint);
  for (std::size_t i = 0; i < points.size(); ++i) {
    // A link to a point no longer in the map would come back as a dangling id.
    const MapPointPtr& point = keyframe.points[i];
    if (point && map.points().count(point->id) > 0) points[i] = point->id;
  }
  SaveBlock(archive, points);
  archive(keyframe.covisible, keyframe.ordered_covisible, keyframe.parent, keyframe.has_parent,
          keyframe.children, keyframe.loop_edges, keyframe.bad, keyframe.T_c_parent);
  if (format == MapFileFormat::kAtlas) archive(keyframe.map);
}

void LoadKeyFrame(cereal::BinaryInputArchive& archive, KeyFrame* keyframe, const Map& map,
                  int pyramid_levels, MapFileFormat format) {
  archive(keyframe->id, keyframe->frame_id, keyframe->timestamp, keyframe->timestamp_text,
          keyframe->T_cw);
  ExtractedFeatures& features = keyframe->features;
  LoadBlock(archive, &features.keypoints);
  LoadBlock(archive, &features.undistorted);
  LoadBlock(archive, &features.descriptors);
  if (features.undistorted.size() != features.keypoints.size() ||
      features.descriptors.size() != features.keypoints.size()) {
    throw std::runtime_error("keyframe " + std::to_string(keyframe->id) +
                             ": keypoints, positions and descriptors differ in number");
  }
  for (std::size_t i = 0; i < features.keypoints.size(); ++i) {
    const int level = features.keypoints[i].octave;
    if (level < 0 || level >= pyramid_levels) {
      throw std::runtime_error("keyframe " + std::to_string(keyframe->id) + ": keypoint " +
                               std::to_string(i) + " lies on pyramid level " +
                               std::to_string(level) + ", but the pyramid has " +
                               std::to_string(pyramid_levels) + " levels");
    }
  }
  ImageBounds bounds;
  int columns = 0, rows = 0;
  archive(bounds.min_x, bounds.max_x, bounds.min_y, bounds.max_y, columns, rows);
  features.grid = FeatureGrid(features.undistorted, features.Levels(), bounds, columns, rows);
  LoadBlock(archive, &keyframe->bow.entries);
  archive(keyframe->feature_vector);
  std::vector<MapPointId> points;
  LoadBlock(archive, &points);
  if (points.size() != features.keypoints.size()) {
    throw std::runtime_error("keyframe " + std::to_string(keyframe->id) + ": " +
                             std::to_string(points.size()) + " point links for " +
                             std::to_string(features.keypoints.size()) + " features");
  }
  keyframe->points.assign(points.size(), nullptr);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (points[i] == kNoPoint) continue;
    const auto it = map.points().find(points[i]);
    if (it == map.points().end()) {
      throw std::runtime_error("keyframe " + std::to_string(keyframe->id) + " links point " +
                               std::to_string(points[i]) + ", which the file does not hold");
    }
    keyframe->points[i] = it->second;
  }
  archive(keyframe->covisible, keyframe->ordered_covisible, keyframe->parent, keyframe->has_parent,
          keyframe->children, keyframe->loop_edges, keyframe->bad, keyframe->T_c_parent);
  keyframe->map = 0;
  if (format == MapFileFormat::kAtlas) archive(keyframe->map);
}

}  // namespace

void SaveMap(const Map& map, std::ostream& out, const std::vector<MapMerge>& merges,
             MapFileFormat format) {
  std::lock_guard<std::mutex> lock(map.mutex());
  cereal::BinaryOutputArchive archive(out);
  archive(map.next_keyframe_id(), map.next_map_point_id());
  // The single-map format holds the current map alone (maps share no point and no
  // covisibility edge: one is whole without the others).
  const auto saved = [&](int tag) {
    return format == MapFileFormat::kAtlas || tag == map.current_map();
  };
  std::size_t count = 0;
  for (const auto& [id, point] : map.points()) count += saved(point->map) ? 1 : 0;
  archive(cereal::make_size_tag(static_cast<cereal::size_type>(count)));
  for (const auto& [id, point] : map.points()) {
    if (saved(point->map)) SavePoint(archive, *point, format);
  }
  count = 0;
  for (const auto& [id, keyframe] : map.keyframes()) count += saved(keyframe->map) ? 1 : 0;
  archive(cereal::make_size_tag(static_cast<cereal::size_type>(count)));
  for (const auto& [id, keyframe] : map.keyframes()) {
    if (saved(keyframe->map)) SaveKeyFrame(archive, *keyframe, map, format);
  }
  if (format != MapFileFormat::kAtlas) return;
  archive(map.map_count(), map.current_map());
  archive(cereal::make_size_tag(static_cast<cereal::size_type>(merges.size())));
  for (const MapMerge& merge : merges)
    archive(merge.merged_map, merge.into_map, merge.frame, merge.scale);
}

std::vector<MapMerge> LoadMap(std::istream& in, Map* map, int pyramid_levels,
                              MapFileFormat format) {
  std::lock_guard<std::mutex> lock(map->mutex());
  if (!map->keyframes().empty() || !map->points().empty()) {
    throw std::logic_error("LoadMap: the map must be empty");
  }
  std::vector<MapMerge> merges;
  try {
    cereal::BinaryInputArchive archive(in);
    KeyFrameId next_keyframe = 0;
    MapPointId next_point = 0;
    archive(next_keyframe, next_point);
    cereal::size_type count = 0;
    archive(cereal::make_size_tag(count));
    for (cereal::size_type i = 0; i < count; ++i) {
      auto point = std::make_shared<MapPoint>();
      LoadPoint(archive, point.get(), format);
      map->Add(point);
    }
    archive(cereal::make_size_tag(count));
    for (cereal::size_type i = 0; i < count; ++i) {
      auto keyframe = std::make_shared<KeyFrame>();
      LoadKeyFrame(archive, keyframe.get(), *map, pyramid_levels, format);
      map->Add(keyframe);
    }
    int map_count = 1, current_map = 0;
    if (format == MapFileFormat::kAtlas) {
      archive(map_count, current_map);
      archive(cereal::make_size_tag(count));
      merges.resize(static_cast<std::size_t>(count));
      for (MapMerge& merge : merges)
        archive(merge.merged_map, merge.into_map, merge.frame, merge.scale);
    }
    const auto check_map = [map_count](int tag, const std::string& what) {
      if (tag < 0 || tag >= map_count) {
        throw std::runtime_error(what + " is in map " + std::to_string(tag) +
                                 ", but the atlas has " + std::to_string(map_count) + " maps");
      }
    };
    if (map_count < 1) throw std::runtime_error("the atlas has no map");
    check_map(current_map, "the current map");
    for (const MapMerge& merge : merges) {
      check_map(merge.merged_map, "a merged map");
      check_map(merge.into_map, "a merged map's destination");
    }
    for (const auto& [id, point] : map->points()) {
      check_map(point->map, "point " + std::to_string(id));
      for (const auto& [keyframe, feature] : point->observations) {
        const KeyFramePtr observer = map->GetKeyFrame(keyframe);
        if (!observer) {
          throw std::runtime_error("point " + std::to_string(id) + " is observed by keyframe " +
                                   std::to_string(keyframe) + ", which the file does not hold");
        }
        if (observer->map != point->map) {
          throw std::runtime_error("point " + std::to_string(id) + " of map " +
                                   std::to_string(point->map) + " is observed by keyframe " +
                                   std::to_string(keyframe) + " of map " +
                                   std::to_string(observer->map));
        }
      }
    }
    for (const auto& [id, keyframe] : map->keyframes())
      check_map(keyframe->map, "keyframe " + std::to_string(id));
    // The maps' indices as saved (merged and reset ones hold nothing but keep theirs).
    while (map->map_count() < map_count) map->StartNewMap();
    map->SetCurrentMap(current_map);
    map->RestoreIdCounters(next_keyframe, next_point);
  } catch (...) {
    map->Clear();
    throw;
  }
  return merges;
}

}  // namespace ocg
