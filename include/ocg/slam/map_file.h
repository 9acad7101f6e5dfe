#pragma once
// The SLAM map's part of a map file (docs/sessions.md): every keyframe (culled ones too,
// which frames may still be anchored to) with its pose T_cw, keypoints, undistorted
// positions, descriptors, BoW and feature vectors, map point links, covisibility,
// spanning tree and loop edges; every map point; the id counters. A cereal binary
// archive written into a stream that the caller frames (core/map_file.h).

#include <iosfwd>
#include <optional>

#include "ocg/slam/map.h"

namespace ocg {

// Locks the map while it writes. only_map: that map of the atlas alone (KeyFrame::map);
// it is loaded as map 0.
void SaveMap(const Map& map, std::ostream& out, std::optional<int> only_map = std::nullopt);

// Reads what SaveMap wrote into map, which must be empty (locks it while it reads). The
// keyframes' feature grids are rebuilt from the saved grid geometry. pyramid_levels: the
// levels of the scale pyramid the map will be used with; everything that indexes the
// pyramid by a keypoint's level (octave) relies on this check. Throws std::runtime_error
// (cereal::Exception is one) when the stream ends early or the data contradict themselves
// (a link to a point or keyframe that is not there) or a keypoint lies outside
// [0, pyramid_levels); the map is left empty then.
void LoadMap(std::istream& in, Map* map, int pyramid_levels);

}  // namespace ocg
