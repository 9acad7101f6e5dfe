#pragma once
// Procedural textures with many distinct corners for ORB: multi-scale noise, blobs and
// print-like strokes and letters, different for every seed.

#include <cstdint>
#include <opencv2/core.hpp>

namespace ocg::sim {

// A size x size BGR texture, deterministic in seed.
cv::Mat MakeTexture(std::uint64_t seed, int size);

}  // namespace ocg::sim
