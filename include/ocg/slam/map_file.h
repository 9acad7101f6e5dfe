#pragma once
// The SLAM map's part of a map file (docs/sessions.md): the whole atlas, with every
// keyframe (culled ones too, which frames may still be anchored to) with its pose T_cw,
// keypoints, undistorted positions, descriptors, BoW and feature vectors, map point links,
// covisibility, spanning tree, loop edges and map index; every map point with its map
// index; the id counters; the number of maps, the current one and the merges. A cereal
// binary archive written into a stream that the caller frames (core/map_file.h).

#include <cstdint>
#include <iosfwd>
#include <vector>

#include "ocg/slam/map.h"

namespace ocg {

// The layout of the SLAM part. kSingleMap: the current map alone, every keyframe and point
// loaded as map 0 (files of the session format before version 5). kAtlas: every map of the
// atlas, each keyframe and point with its map index, then the number of maps, the current
// one and the merges so far.
enum class MapFileFormat { kSingleMap, kAtlas };

// A map merged into another (LoopEvent's merged_map, into_map, frame and scale), kept in
// the file so that a later session still says where the map went.
struct MapMerge {
  int merged_map = -1;
  int into_map = -1;
  std::uint64_t frame = 0;
  double scale = 1.0;
};

// Locks the map while it writes. merges: those of the maps in it (kAtlas only).
void SaveMap(const Map& map, std::ostream& out, const std::vector<MapMerge>& merges = {},
             MapFileFormat format = MapFileFormat::kAtlas);

// Reads what SaveMap wrote into map, which must be empty (locks it while it reads), and
// returns the merges it holds. The atlas comes back whole: its maps, their indices and
// the current one. The keyframes' feature grids are rebuilt from the saved grid geometry.
// pyramid_levels: the levels of the scale pyramid the map will be used with; everything
// that indexes the pyramid by a keypoint's level (octave) relies on this check. Throws
// std::runtime_error (cereal::Exception is one) when the stream ends early or the data
// contradict themselves (a link to a point or keyframe that is not there, a point seen
// from another map, a map index beyond the atlas) or a keypoint lies outside
// [0, pyramid_levels); the map is left empty then.
std::vector<MapMerge> LoadMap(std::istream& in, Map* map, int pyramid_levels,
                              MapFileFormat format = MapFileFormat::kAtlas);

}  // namespace ocg
