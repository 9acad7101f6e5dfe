#pragma once
// 2-D drawing shared by the map and frame views (internal to viewer).

#include <Eigen/Core>
#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <string>
#include <utility>
#include <vector>

namespace ocg {

// An RGB colour in [0, 1] as OpenCV's BGR in [0, 255].
inline cv::Scalar ToBgr(const Eigen::Vector3f& rgb) {
  return cv::Scalar(255.0 * rgb.z(), 255.0 * rgb.y(), 255.0 * rgb.x());
}

constexpr int kLabelFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kLabelScale = 0.45;

// Black text with a white outline: readable on any background. at: the baseline's start.
inline void DrawLabel(cv::Mat& image, const std::string& text, const cv::Point& at) {
  cv::putText(image, text, at, kLabelFont, kLabelScale, cv::Scalar(255, 255, 255), 3, cv::LINE_AA);
  cv::putText(image, text, at, kLabelFont, kLabelScale, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
}

// The box DrawLabel's text covers, outline included (2 pixels round the glyphs).
inline cv::Size LabelSize(const std::string& text) {
  int baseline = 0;
  const cv::Size size = cv::getTextSize(text, kLabelFont, kLabelScale, 1, &baseline);
  return {size.width + 4, size.height + baseline + 4};
}

// DrawLabel with its text in box (a box of LabelSize(text)).
inline void DrawLabelInBox(cv::Mat& image, const std::string& text, const cv::Rect& box) {
  int baseline = 0;
  cv::getTextSize(text, kLabelFont, kLabelScale, 1, &baseline);
  DrawLabel(image, text, cv::Point(box.x + 2, box.y + box.height - baseline - 2));
}

// A legend entry: its mark in a colour and what it stands for.
struct LegendEntry {
  enum class Mark { kFilled, kDashed, kArrow, kLine, kOutline, kPoint };
  Mark mark = Mark::kFilled;
  cv::Scalar colour;
  std::string text;
};

constexpr int kLegendRow = 18;

// The legend's entries of the OCG states drawn (drawn[state], states 0-4), in the order
// observed, recently observed, unknown, suspicious, not judged yet. colour: a state's.
template <class Colour>
void AddStateEntries(std::vector<LegendEntry>& entries, const bool (&drawn)[5],
                     LegendEntry::Mark mark, Colour colour) {
  const std::pair<int, const char*> states[] = {{1, "observed"},
                                                {2, "recently observed"},
                                                {3, "unknown"},
                                                {4, "suspicious"},
                                                {0, "not judged yet"}};
  for (const auto& [state, name] : states) {
    if (drawn[state]) entries.push_back({mark, ToBgr(colour(state)), name});
  }
}

// Where DrawLegend draws entries: the top-left corner (empty for no entries).
inline cv::Rect LegendBox(const std::vector<LegendEntry>& entries) {
  if (entries.empty()) return {};
  int width = 0;
  for (const LegendEntry& entry : entries) width = std::max(width, LabelSize(entry.text).width);
  return {6, 6, 22 + width + 4, kLegendRow * static_cast<int>(entries.size()) + 4};
}

inline void DrawLegend(cv::Mat& image, const std::vector<LegendEntry>& entries) {
  int y = 18;
  for (const LegendEntry& entry : entries) {
    const cv::Rect mark(10, y - 10, 12, 12);
    switch (entry.mark) {
      case LegendEntry::Mark::kFilled:
        cv::rectangle(image, mark, entry.colour, cv::FILLED);
        break;
      case LegendEntry::Mark::kDashed:
        for (int i = 0; i < 12; i += 4) {
          cv::line(image, {mark.x + i, mark.y}, {mark.x + i + 1, mark.y}, entry.colour, 2);
          cv::line(image, {mark.x + i, mark.y + 11}, {mark.x + i + 1, mark.y + 11}, entry.colour,
                   2);
          cv::line(image, {mark.x, mark.y + i}, {mark.x, mark.y + i + 1}, entry.colour, 2);
          cv::line(image, {mark.x + 11, mark.y + i}, {mark.x + 11, mark.y + i + 1}, entry.colour,
                   2);
        }
        break;
      case LegendEntry::Mark::kArrow:
        cv::arrowedLine(image, {mark.x, y - 4}, {mark.x + 12, y - 4}, entry.colour, 2, cv::LINE_AA,
                        0, 0.45);
        break;
      case LegendEntry::Mark::kLine:
        cv::line(image, {mark.x, y - 4}, {mark.x + 12, y - 4}, entry.colour, 2, cv::LINE_AA);
        break;
      case LegendEntry::Mark::kOutline:
        cv::rectangle(image, mark, entry.colour, 1);
        break;
      case LegendEntry::Mark::kPoint:
        cv::rectangle(image, cv::Rect(mark.x + 2, mark.y + 2, 8, 8), entry.colour, 1);
        cv::circle(image, {mark.x + 6, mark.y + 6}, 1, entry.colour, cv::FILLED);
        break;
    }
    DrawLabel(image, entry.text, cv::Point(28, y));
    y += kLegendRow;
  }
}

}  // namespace ocg
