#include "ocg/viewer/label_layout.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "drawing.h"

namespace ocg {
namespace {

constexpr int kStepX = 4;
constexpr int kStepY = 3;

// Shifts of a box within max_shift, nearest first (ties: up before down, right before
// left, so that equal scenes give equal layouts).
std::vector<cv::Point> ShiftsNearestFirst(int max_shift) {
  std::vector<cv::Point> shifts;
  for (int dy = -(max_shift / kStepY) * kStepY; dy <= max_shift; dy += kStepY) {
    for (int dx = -(max_shift / kStepX) * kStepX; dx <= max_shift; dx += kStepX) {
      if (dx * dx + dy * dy <= max_shift * max_shift) shifts.emplace_back(dx, dy);
    }
  }
  std::stable_sort(shifts.begin(), shifts.end(), [](const cv::Point& a, const cv::Point& b) {
    const int da = a.x * a.x + a.y * a.y, db = b.x * b.x + b.y * b.y;
    if (da != db) return da < db;
    if (a.y != b.y) return a.y < b.y;
    return a.x > b.x;
  });
  return shifts;
}

// Labels side by side read as one ("21 tv46 bottle"): a free place keeps this many pixels
// from the others.
constexpr int kGap = 3;

bool Overlaps(const cv::Rect& a, const cv::Rect& b) {
  const cv::Rect grown(a.x - kGap, a.y - kGap, a.width + 2 * kGap, a.height + 2 * kGap);
  return (grown & b).area() > 0;
}

// The point of box nearest to p.
cv::Point NearestPoint(const cv::Rect& box, const cv::Point& p) {
  return {std::clamp(p.x, box.x, box.x + box.width - 1),
          std::clamp(p.y, box.y, box.y + box.height - 1)};
}

}  // namespace

std::vector<std::optional<cv::Rect>> PlaceLabels(const std::vector<LabelRequest>& requests,
                                                 const cv::Size& image,
                                                 const std::vector<cv::Rect>& obstacles,
                                                 const LabelLayoutOptions& options) {
  // The snapshots' own layouts all use the default reach: its shifts are sorted once.
  static const LabelLayoutOptions kDefault;
  static const std::vector<cv::Point> kDefaultShifts = ShiftsNearestFirst(kDefault.max_shift);
  std::vector<cv::Point> own_shifts;
  if (options.max_shift != kDefault.max_shift)
    own_shifts = ShiftsNearestFirst(std::max(0, options.max_shift));
  const std::vector<cv::Point>& shifts =
      options.max_shift == kDefault.max_shift ? kDefaultShifts : own_shifts;
  const cv::Rect frame(0, 0, image.width, image.height);
  std::vector<cv::Rect> taken = obstacles;
  std::vector<std::optional<cv::Rect>> boxes;
  boxes.reserve(requests.size());
  for (const LabelRequest& request : requests) {
    const cv::Point preferred(request.anchor.x + options.offset.x,
                              request.anchor.y + options.offset.y - request.size.height);
    std::optional<cv::Rect> found;
    // Neighbouring places are mostly blocked by the same box: it is tried first.
    std::size_t blocker = 0;
    for (const cv::Point& shift : shifts) {
      const cv::Rect box(preferred + shift, request.size);
      if ((box & frame) != box) continue;
      if (blocker < taken.size() && Overlaps(box, taken[blocker])) continue;
      const auto other = std::find_if(taken.begin(), taken.end(),
                                      [&](const cv::Rect& rect) { return Overlaps(box, rect); });
      if (other == taken.end()) {
        found = box;
        break;
      }
      blocker = static_cast<std::size_t>(other - taken.begin());
    }
    if (found) taken.push_back(*found);
    boxes.push_back(found);
  }
  return boxes;
}

std::vector<PlacedLabel> LayOutLabels(const std::vector<std::pair<std::string, cv::Point>>& labels,
                                      const cv::Size& image,
                                      const std::vector<cv::Rect>& obstacles) {
  std::vector<LabelRequest> requests;
  requests.reserve(labels.size());
  for (const auto& [text, anchor] : labels) requests.push_back({anchor, LabelSize(text)});
  const LabelLayoutOptions options;
  const std::vector<std::optional<cv::Rect>> boxes = PlaceLabels(requests, image, obstacles);
  std::vector<PlacedLabel> placed;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (!boxes[i]) continue;
    const cv::Point preferred(labels[i].second.x + options.offset.x,
                              labels[i].second.y + options.offset.y - requests[i].size.height);
    placed.push_back({labels[i].first, labels[i].second, *boxes[i], boxes[i]->tl() != preferred});
  }
  return placed;
}

void DrawLabels(cv::Mat& image, const std::vector<PlacedLabel>& labels) {
  for (const PlacedLabel& label : labels) {
    if (!label.moved) continue;
    const cv::Point end = NearestPoint(label.box, label.anchor);
    cv::line(image, label.anchor, end, cv::Scalar(255, 255, 255), 3, cv::LINE_AA);
    cv::line(image, label.anchor, end, cv::Scalar(60, 60, 60), 1, cv::LINE_AA);
    cv::circle(image, label.anchor, 2, cv::Scalar(60, 60, 60), cv::FILLED, cv::LINE_AA);
  }
  for (const PlacedLabel& label : labels) DrawLabelInBox(image, label.text, label.box);
}

}  // namespace ocg
