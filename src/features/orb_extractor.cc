#include "ocg/features/orb_extractor.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <queue>
#include <stdexcept>
#include <string>
#include <tuple>

namespace ocg {
namespace {

// Keypoints keep this far from each level's border so that the rotated 31x31 BRIEF patch
// (radius up to 15 * sqrt(2)) and the orientation patch fit inside the level image.
constexpr int kEdgeThreshold = 19;
constexpr int kFastBorder = 3;  // FAST needs a circle of radius 3 around a corner
constexpr int kPatchSize = 31;
constexpr int kOrientationRadius = 15;
constexpr double kFastCellSize = 30.0;

std::vector<int> SplitFeaturesOverLevels(int features, int levels, double scale_factor) {
  const double shrink = 1.0 / scale_factor;
  const double first =
      features * (1.0 - shrink) / (1.0 - std::pow(shrink, static_cast<double>(levels)));
  std::vector<int> per_level(static_cast<std::size_t>(levels));
  int assigned = 0;
  double wanted = first;
  for (int level = 0; level + 1 < levels; ++level) {
    per_level[static_cast<std::size_t>(level)] = static_cast<int>(std::lround(wanted));
    assigned += per_level[static_cast<std::size_t>(level)];
    wanted *= shrink;
  }
  per_level.back() = std::max(features - assigned, 0);
  return per_level;
}

}  // namespace

std::vector<int> ExtractedFeatures::Levels() const {
  std::vector<int> levels(keypoints.size());
  for (std::size_t i = 0; i < keypoints.size(); ++i) levels[i] = keypoints[i].octave;
  return levels;
}

std::vector<int> CircleHalfWidths(int radius) {
  std::vector<int> half_width(static_cast<std::size_t>(radius + 1));
  for (int v = 0; v <= radius; ++v) {
    half_width[static_cast<std::size_t>(v)] =
        static_cast<int>(std::lround(std::sqrt(static_cast<double>(radius * radius - v * v))));
  }
  return half_width;
}

float IntensityCentroidAngle(const cv::Mat& gray, const cv::Point2f& point,
                             const std::vector<int>& circle_half_width) {
  const int x = static_cast<int>(std::lround(point.x));
  const int y = static_cast<int>(std::lround(point.y));
  const int radius = static_cast<int>(circle_half_width.size()) - 1;
  long m01 = 0;
  long m10 = 0;
  const std::uint8_t* centre_row = gray.ptr<std::uint8_t>(y);
  for (int u = -radius; u <= radius; ++u) m10 += u * centre_row[x + u];
  for (int v = 1; v <= radius; ++v) {
    const std::uint8_t* below = gray.ptr<std::uint8_t>(y + v);
    const std::uint8_t* above = gray.ptr<std::uint8_t>(y - v);
    const int half = circle_half_width[static_cast<std::size_t>(v)];
    long row_difference = 0;
    for (int u = -half; u <= half; ++u) {
      const int sum = below[x + u] + above[x + u];
      row_difference += below[x + u] - above[x + u];
      m10 += u * sum;
    }
    m01 += v * row_difference;
  }
  return cv::fastAtan2(static_cast<float>(m01), static_cast<float>(m10));
}

std::vector<int> DistributeByQuadtree(const std::vector<cv::KeyPoint>& candidates,
                                      const cv::Point2f& min, const cv::Point2f& max, int wanted) {
  if (wanted <= 0 || candidates.empty()) return {};
  struct Node {
    cv::Point2f min, max;
    std::vector<int> members;
    int depth = 0;
    bool alive = true;
  };
  std::vector<Node> nodes;
  // Start with square-ish nodes side by side, as wide images would otherwise split into
  // tall thin cells first.
  const float width = max.x - min.x;
  const float height = max.y - min.y;
  const int initial = std::max(1, static_cast<int>(std::lround(width / height)));
  const float strip = width / static_cast<float>(initial);
  for (int i = 0; i < initial; ++i) {
    Node node;
    node.min = {min.x + strip * static_cast<float>(i), min.y};
    node.max = {i + 1 == initial ? max.x : min.x + strip * static_cast<float>(i + 1), max.y};
    nodes.push_back(node);
  }
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const int strip_index =
        std::clamp(static_cast<int>((candidates[i].pt.x - min.x) / strip), 0, initial - 1);
    nodes[static_cast<std::size_t>(strip_index)].members.push_back(static_cast<int>(i));
  }
  // Shallow (large) nodes are split first, so that every part of the image gets corners
  // before a crowded patch gets many; among equals the most crowded, then the older.
  using Entry = std::tuple<int, std::size_t, int>;  // (-depth, members, -node index)
  std::priority_queue<Entry> crowded;
  int alive = 0;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].members.empty()) {
      nodes[i].alive = false;
      continue;
    }
    ++alive;
    if (nodes[i].members.size() > 1)
      crowded.push({0, nodes[i].members.size(), -static_cast<int>(i)});
  }
  while (alive < wanted && !crowded.empty()) {
    const std::size_t parent = static_cast<std::size_t>(-std::get<2>(crowded.top()));
    crowded.pop();
    const cv::Point2f low = nodes[parent].min;
    const cv::Point2f high = nodes[parent].max;
    const cv::Point2f middle = (low + high) * 0.5f;
    if (high.x - low.x < 1.0f && high.y - low.y < 1.0f) continue;  // coincident corners
    Node children[4];
    for (int c = 0; c < 4; ++c) {
      children[c].depth = nodes[parent].depth + 1;
      children[c].min = {(c & 1) ? middle.x : low.x, (c & 2) ? middle.y : low.y};
      children[c].max = {(c & 1) ? high.x : middle.x, (c & 2) ? high.y : middle.y};
    }
    for (const int member : nodes[parent].members) {
      const cv::Point2f& p = candidates[static_cast<std::size_t>(member)].pt;
      children[(p.x >= middle.x ? 1 : 0) + (p.y >= middle.y ? 2 : 0)].members.push_back(member);
    }
    nodes[parent].alive = false;
    nodes[parent].members.clear();
    --alive;
    for (Node& child : children) {
      if (child.members.empty()) continue;
      ++alive;
      nodes.push_back(std::move(child));
      const std::size_t index = nodes.size() - 1;
      if (nodes[index].members.size() > 1) {
        crowded.push({-nodes[index].depth, nodes[index].members.size(), -static_cast<int>(index)});
      }
    }
  }
  std::vector<int> kept;
  for (const Node& node : nodes) {
    if (!node.alive) continue;
    int best = node.members.front();
    for (const int member : node.members) {
      if (candidates[static_cast<std::size_t>(member)].response >
          candidates[static_cast<std::size_t>(best)].response) {
        best = member;
      }
    }
    kept.push_back(best);
  }
  if (static_cast<int>(kept.size()) > wanted) {
    std::stable_sort(kept.begin(), kept.end(), [&](int a, int b) {
      return candidates[static_cast<std::size_t>(a)].response >
             candidates[static_cast<std::size_t>(b)].response;
    });
    kept.resize(static_cast<std::size_t>(wanted));
  }
  std::sort(kept.begin(), kept.end());
  return kept;
}

OrbExtractor::OrbExtractor(const OrbExtractorOptions& options)
    : options_(options),
      pyramid_(MakeScalePyramid(options.levels, options.scale_factor)),
      features_per_level_(
          SplitFeaturesOverLevels(options.features, options.levels, options.scale_factor)),
      circle_half_width_(CircleHalfWidths(kOrientationRadius)),
      levels_(static_cast<std::size_t>(options.levels)) {
  options.Check();
  describer_ = cv::ORB::create(options.features, static_cast<float>(options.scale_factor),
                               options.levels, kEdgeThreshold, 0, 2, cv::ORB::HARRIS_SCORE,
                               kPatchSize, options.initial_fast_threshold);
}

OrbExtractor::~OrbExtractor() = default;

std::vector<cv::Size> PyramidLevelSizes(const cv::Size& image, const ScalePyramid& pyramid) {
  std::vector<cv::Size> sizes;
  for (const double scale : pyramid.scale) {
    sizes.emplace_back(static_cast<int>(std::lround(image.width / scale)),
                       static_cast<int>(std::lround(image.height / scale)));
  }
  return sizes;
}

std::optional<FastCellLayout> FastCells(const cv::Size& level_size) {
  const int border = kEdgeThreshold - kFastBorder;
  FastCellLayout layout;
  layout.region =
      cv::Rect(border, border, level_size.width - 2 * border, level_size.height - 2 * border);
  if (layout.region.width <= 2 * kFastBorder || layout.region.height <= 2 * kFastBorder) {
    return std::nullopt;
  }
  layout.columns = SplitIntoCells(layout.region.width, kFastCellSize);
  layout.rows = SplitIntoCells(layout.region.height, kFastCellSize);
  return layout;
}

cv::Rect FastCellLayout::Cell(int column, int row) const {
  return {columns.Start(column), rows.Start(row), columns.Size(column), rows.Size(row)};
}

void OrbExtractor::BuildPyramid(const cv::Mat& gray) {
  const std::vector<cv::Size> sizes = PyramidLevelSizes(gray.size(), pyramid_);
  levels_[0] = gray;
  for (int level = 1; level < options_.levels; ++level) {
    cv::resize(levels_[static_cast<std::size_t>(level - 1)],
               levels_[static_cast<std::size_t>(level)], sizes[static_cast<std::size_t>(level)], 0,
               0, cv::INTER_LINEAR);
  }
}

void OrbExtractor::DetectLevel(int level, int wanted, std::vector<cv::KeyPoint>* keypoints) const {
  const cv::Mat& image = levels_[static_cast<std::size_t>(level)];
  const std::optional<FastCellLayout> layout = FastCells(image.size());
  if (!layout || wanted <= 0) return;
  const cv::Rect& region = layout->region;
  const cv::Mat detection_area = image(region);
  std::vector<cv::KeyPoint> candidates;
  cv::FAST(detection_area, candidates, options_.initial_fast_threshold, true);
  // Cells where the strict threshold found nothing get a second chance with the lenient
  // one, so that low-contrast parts of the image still get corners.
  const int columns = layout->columns.count;
  const int rows = layout->rows.count;
  std::vector<char> occupied(static_cast<std::size_t>(columns * rows), 0);
  for (const cv::KeyPoint& k : candidates) {
    const int column = layout->columns.CellOf(static_cast<int>(k.pt.x));
    const int row = layout->rows.CellOf(static_cast<int>(k.pt.y));
    occupied[static_cast<std::size_t>(row * columns + column)] = 1;
  }
  std::vector<cv::KeyPoint> found;
  for (int row = 0; row < rows; ++row) {
    for (int column = 0; column < columns; ++column) {
      if (occupied[static_cast<std::size_t>(row * columns + column)]) continue;
      const cv::Rect cell = layout->Cell(column, row);
      const cv::Rect padded = (cell + cv::Size(2 * kFastBorder, 2 * kFastBorder) -
                               cv::Point(kFastBorder, kFastBorder)) &
                              cv::Rect(0, 0, region.width, region.height);
      found.clear();
      cv::FAST(detection_area(padded), found, options_.minimum_fast_threshold, true);
      for (cv::KeyPoint k : found) {
        k.pt += cv::Point2f(static_cast<float>(padded.x), static_cast<float>(padded.y));
        if (cell.contains(cv::Point(static_cast<int>(k.pt.x), static_cast<int>(k.pt.y)))) {
          candidates.push_back(k);
        }
      }
    }
  }
  const std::vector<int> kept = DistributeByQuadtree(
      candidates, {0.0f, 0.0f},
      {static_cast<float>(region.width), static_cast<float>(region.height)}, wanted);
  const float scale = static_cast<float>(pyramid_.scale[static_cast<std::size_t>(level)]);
  for (const int index : kept) {
    cv::KeyPoint k = candidates[static_cast<std::size_t>(index)];
    k.pt += cv::Point2f(static_cast<float>(region.x), static_cast<float>(region.y));
    k.angle = IntensityCentroidAngle(image, k.pt, circle_half_width_);
    k.pt *= scale;
    k.octave = level;
    k.size = kPatchSize * scale;
    keypoints->push_back(k);
  }
}

void OrbExtractor::Detect(const cv::Mat& gray, std::vector<cv::KeyPoint>* keypoints,
                          std::vector<Descriptor>* descriptors) {
  keypoints->clear();
  descriptors->clear();
  BuildPyramid(gray);
  // A level short of corners passes its shortfall on to the next one, so that the total
  // stays close to the requested count on weakly textured images.
  int shortfall = 0;
  for (int level = 0; level < options_.levels; ++level) {
    const std::size_t before = keypoints->size();
    const int wanted = features_per_level_[static_cast<std::size_t>(level)] + shortfall;
    DetectLevel(level, wanted, keypoints);
    shortfall = wanted - static_cast<int>(keypoints->size() - before);
  }
  if (keypoints->empty()) return;
  const std::size_t detected = keypoints->size();
  cv::Mat rows;
  describer_->compute(gray, *keypoints, rows);
  // Our keypoints keep kEdgeThreshold from every level's border and come sorted by level,
  // so cv::ORB neither drops nor reorders them.
  if (keypoints->size() != detected || rows.rows != static_cast<int>(detected)) {
    throw std::logic_error("cv::ORB::compute dropped keypoints (" + std::to_string(detected) +
                           " -> " + std::to_string(keypoints->size()) + ")");
  }
  descriptors->resize(detected);
  for (int i = 0; i < rows.rows; ++i) {
    (*descriptors)[static_cast<std::size_t>(i)] = DescriptorFromBytes(rows.ptr<std::uint8_t>(i));
  }
}

ExtractedFeatures OrbExtractor::Extract(const cv::Mat& image, const PinholeCamera& camera) {
  if (image.empty()) throw std::invalid_argument("OrbExtractor: empty image");
  if (image.cols != camera.width || image.rows != camera.height) {
    throw std::invalid_argument("OrbExtractor: image is " + std::to_string(image.cols) + "x" +
                                std::to_string(image.rows) + " but the camera is " +
                                std::to_string(camera.width) + "x" + std::to_string(camera.height) +
                                " (Camera.width/height)");
  }
  cv::Mat gray = image;
  if (image.channels() == 3) {
    cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  } else if (image.channels() == 4) {
    cv::cvtColor(image, gray, cv::COLOR_BGRA2GRAY);
  }
  if (gray.type() != CV_8UC1) throw std::invalid_argument("OrbExtractor: image is not 8-bit");
  ExtractedFeatures features;
  Detect(gray, &features.keypoints, &features.descriptors);
  std::vector<Eigen::Vector2d> pixels(features.keypoints.size());
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    pixels[i] = {features.keypoints[i].pt.x, features.keypoints[i].pt.y};
  }
  features.undistorted = camera.HasDistortion() ? camera.UndistortPixels(pixels) : pixels;
  features.grid =
      FeatureGrid(features.undistorted, features.Levels(), UndistortedImageBounds(camera));
  return features;
}

}  // namespace ocg
