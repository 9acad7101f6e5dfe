#include "ocg/detect/tiling.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <stdexcept>
#include <string>

#include "ocg/detect/decode.h"

namespace ocg {

void TilingOptions::Check() const {
  if (!(min_aspect >= 1.0)) {
    throw std::invalid_argument("TilingOptions.min_aspect must be >= 1, got " +
                                std::to_string(min_aspect));
  }
  if (!(min_overlap >= 0.0 && min_overlap < 0.9)) {
    throw std::invalid_argument("TilingOptions.min_overlap must be in [0, 0.9), got " +
                                std::to_string(min_overlap));
  }
  if (!(edge_margin >= 0.0)) {
    throw std::invalid_argument("TilingOptions.edge_margin must be >= 0, got " +
                                std::to_string(edge_margin));
  }
}

std::vector<cv::Rect> SquareTiles(cv::Size image, const TilingOptions& options) {
  const int side = std::min(image.width, image.height);
  const int length = std::max(image.width, image.height);
  if (side <= 0 || length <= options.min_aspect * side) return {};
  // Fewest tiles whose even spacing keeps the overlap: step <= side * (1 - min_overlap).
  const double max_step = side * (1.0 - options.min_overlap);
  const int count = 1 + static_cast<int>(std::ceil((length - side) / max_step));
  std::vector<cv::Rect> tiles;
  for (int i = 0; i < count; ++i) {
    const int start =
        static_cast<int>(std::lround(static_cast<double>(length - side) * i / (count - 1)));
    tiles.push_back(image.width >= image.height ? cv::Rect(start, 0, side, side)
                                                : cv::Rect(0, start, side, side));
  }
  return tiles;
}

namespace {

// True when the box touches an edge of the tile that lies inside the image: the tile cut
// the object. An object narrower than the overlap lies whole in the neighbour tile; a
// larger one is left to the pass over the whole frame.
bool CutByInnerEdge(const Detection& box, const cv::Rect& tile, cv::Size image, double margin) {
  const bool cut_left = tile.x > 0 && box.x <= tile.x + margin;
  const bool cut_top = tile.y > 0 && box.y <= tile.y + margin;
  const bool cut_right = tile.br().x < image.width && box.x + box.width >= tile.br().x - margin;
  const bool cut_bottom = tile.br().y < image.height && box.y + box.height >= tile.br().y - margin;
  return cut_left || cut_top || cut_right || cut_bottom;
}

}  // namespace

std::vector<Detection> MergeTileDetections(const std::vector<cv::Rect>& tiles,
                                           const std::vector<std::vector<Detection>>& per_tile,
                                           const std::vector<Detection>& whole_frame,
                                           cv::Size image, const TilingOptions& options,
                                           double iou_threshold) {
  assert(tiles.size() == per_tile.size());
  std::vector<Detection> all = whole_frame;
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    for (const Detection& box : per_tile[i]) {
      if (!CutByInnerEdge(box, tiles[i], image, options.edge_margin)) all.push_back(box);
    }
  }
  return ClassWiseNms(all, iou_threshold);
}

}  // namespace ocg
