#pragma once
// Wide (or tall) images through a square detector: overlapping square tiles, so that a
// 1226x370 KITTI frame is seen at its own resolution instead of squashed into one square,
// and the tiles' detections merged back into one list.

#include <opencv2/core/types.hpp>
#include <vector>

#include "ocg/io/detections.h"

namespace ocg {

struct TilingOptions {
  // Images whose long side exceeds the short one by more than this factor are tiled.
  double min_aspect = 1.5;
  // Neighbouring tiles share at least this fraction of their side, so that an object up
  // to that wide lies whole inside some tile.
  double min_overlap = 0.25;
  // A tile's box closer than this (pixels) to a tile edge inside the image is cut by the
  // tile, and dropped: a neighbour tile or the whole frame sees the object whole.
  double edge_margin = 2.0;
  // Throws std::invalid_argument naming the field when a value is impossible.
  void Check() const;
};

// Square tiles of side min(width, height) along the long side, evenly spaced from one
// end of the image to the other with at least options.min_overlap between neighbours.
// Empty when the image is not wide enough to tile (aspect <= options.min_aspect).
std::vector<cv::Rect> SquareTiles(cv::Size image, const TilingOptions& options);

// Merges per-tile detections (boxes in image pixels; per_tile[i] from tiles[i]) with
// detections of the whole frame: drops tile boxes cut by a tile edge inside the image (an
// object narrower than the overlap lies whole in the neighbour tile, a larger one is found
// in the whole frame), then applies class-wise NMS at iou_threshold over everything.
std::vector<Detection> MergeTileDetections(const std::vector<cv::Rect>& tiles,
                                           const std::vector<std::vector<Detection>>& per_tile,
                                           const std::vector<Detection>& whole_frame,
                                           cv::Size image, const TilingOptions& options,
                                           double iou_threshold);

}  // namespace ocg
