#pragma once
// Procedural textures with many distinct corners for ORB: multi-scale noise, blobs and
// print-like strokes and letters, different for every seed.

#include <cstdint>
#include <opencv2/core.hpp>

namespace ocg::sim {

// A size x size BGR texture, deterministic in seed, for a surface span_metres wide.
// Features have physical sizes (centimetres) and a constant density per square metre,
// so a wall and a cup look equally detailed from the same distance; small surfaces get
// a minimum number of features.
cv::Mat MakeTexture(std::uint64_t seed, int size, double span_metres);

}  // namespace ocg::sim
