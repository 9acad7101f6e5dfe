#pragma once
// A SLAM map of random content with every field set (map-file tests and the load bench).

#include <cstdint>

#include "ocg/slam/map.h"

namespace ocg::testing {

// Fills an empty map with keyframes of `features` features each (640 x 480 pixels, 8
// levels), a map point for every third feature slot, each seen by up to three
// keyframes, covisibility and a spanning tree along the sequence, loop edges, and every
// 50th keyframe culled. Same seed, same map.
void FillRandomMap(int keyframes, int features, std::uint64_t seed, Map* map);

}  // namespace ocg::testing
