#pragma once
// Where the text labels of a snapshot go so that none overlaps another: each one near the
// pixel it names, moved away when that place is taken (the caller draws a leader line back
// to its pixel), left out only when no free place is near enough. Pixels throughout.

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

namespace ocg {

struct LabelRequest {
  cv::Point anchor;  // the pixel the label names
  cv::Size size;     // the label's box
};

struct LabelLayoutOptions {
  // The preferred place: the box's bottom-left corner at anchor + offset (above right).
  cv::Point offset{4, -4};
  // How far a box's corner may move from its preferred place; farther, the label is left
  // out (a label far from its pixel names nothing).
  int max_shift = 220;
};

// Boxes for the requests, taken in order (earlier requests get the nearer places): each
// inside the image, overlapping no earlier box and no obstacle and 3 pixels clear of
// them, at the free place nearest
// its preferred one (places every 4 pixels across and 3 up and down); none when there is
// no free place within max_shift or the box is larger than the image.
std::vector<std::optional<cv::Rect>> PlaceLabels(const std::vector<LabelRequest>& requests,
                                                 const cv::Size& image,
                                                 const std::vector<cv::Rect>& obstacles,
                                                 const LabelLayoutOptions& options = {});

// A label as the snapshots draw it (black text with a white outline, drawing.h).
struct PlacedLabel {
  std::string text;
  cv::Point anchor;
  cv::Rect box;
  bool moved = false;  // not at its preferred place: drawn with a leader line to anchor
};

// The snapshots' labels (text at anchor, in order of priority) placed by PlaceLabels;
// those left out are not returned.
std::vector<PlacedLabel> LayOutLabels(const std::vector<std::pair<std::string, cv::Point>>& labels,
                                      const cv::Size& image,
                                      const std::vector<cv::Rect>& obstacles);
// Draws them: leader lines first, then every text over them.
void DrawLabels(cv::Mat& image, const std::vector<PlacedLabel>& labels);

}  // namespace ocg
