#include "ocg/detect/decode.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>

#include "ocg/core/box2.h"

namespace ocg {
namespace {

// The strides NanoDet-like heads use; a level's stride is the one whose grid has its
// number of cells.
constexpr int kCandidateStrides[] = {8, 16, 32, 64, 128};

int CellCount(cv::Size input, int stride) {
  return ((input.width + stride - 1) / stride) * ((input.height + stride - 1) / stride);
}

int StrideForCells(int cells, cv::Size input) {
  for (int stride : kCandidateStrides) {
    if (CellCount(input, stride) == cells) return stride;
  }
  return 0;
}

std::string ShapeText(const std::vector<int>& shape) {
  std::string text = "[";
  for (std::size_t i = 0; i < shape.size(); ++i) text += (i ? ", " : "") + std::to_string(shape[i]);
  return text + "]";
}

std::vector<int> ShapeOf(const cv::Mat& m) { return std::vector<int>(m.size.p, m.size.p + m.dims); }

bool IsBatchOf3d(const std::vector<int>& shape) { return shape.size() == 3 && shape[0] == 1; }

// NanoDet levels: pairs of (class tensor, distance tensor) with the same cell count.
struct NanoDetLevel {
  int class_index = -1;
  int distance_index = -1;
  int stride = 0;
};

std::vector<NanoDetLevel> NanoDetLevels(const std::vector<std::vector<int>>& shapes, cv::Size input,
                                        int* num_classes) {
  std::map<int, std::vector<int>> by_cells;
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    if (!IsBatchOf3d(shapes[i])) return {};
    by_cells[shapes[i][1]].push_back(static_cast<int>(i));
  }
  std::vector<NanoDetLevel> levels;
  int classes = 0;
  int distances = 0;
  for (const auto& [cells, indices] : by_cells) {
    if (indices.size() != 2) return {};
    NanoDetLevel level;
    level.stride = StrideForCells(cells, input);
    if (level.stride == 0) return {};
    const int a = shapes[indices[0]][2];
    const int b = shapes[indices[1]][2];
    level.class_index = a > b ? indices[0] : indices[1];
    level.distance_index = a > b ? indices[1] : indices[0];
    const int c = std::max(a, b);
    const int d = std::min(a, b);
    if (d % 4 != 0 || d / 4 < 2 || (classes && (c != classes || d != distances))) return {};
    classes = c;
    distances = d;
    levels.push_back(level);
  }
  *num_classes = classes;
  return levels;
}

Detection FromCentre(int class_id, double score, double cx, double cy, double w, double h) {
  Detection d;
  d.class_id = class_id;
  d.confidence = score;
  d.x = cx - 0.5 * w;
  d.y = cy - 0.5 * h;
  d.width = w;
  d.height = h;
  return d;
}

// Best class of one anchor; scores[k * step] is class k's score.
std::pair<int, float> BestClass(const float* scores, int num_classes, int step) {
  int best = 0;
  for (int k = 1; k < num_classes; ++k) {
    if (scores[k * step] > scores[best * step]) best = k;
  }
  return {best, scores[best * step]};
}

// Expected distance (in bins) of a softmax distribution over `bins` values.
double ExpectedBin(const float* logits, int bins) {
  const float top = *std::max_element(logits, logits + bins);
  double sum = 0.0;
  double weighted = 0.0;
  for (int i = 0; i < bins; ++i) {
    const double e = std::exp(static_cast<double>(logits[i] - top));
    sum += e;
    weighted += e * i;
  }
  return weighted / sum;
}

std::vector<Detection> DecodeNanoDet(const std::vector<cv::Mat>& outputs, cv::Size input,
                                     double score_threshold) {
  std::vector<std::vector<int>> shapes;
  for (const cv::Mat& m : outputs) shapes.push_back(ShapeOf(m));
  int num_classes = 0;
  const std::vector<NanoDetLevel> levels = NanoDetLevels(shapes, input, &num_classes);
  assert(!levels.empty());
  std::vector<Detection> boxes;
  for (const NanoDetLevel& level : levels) {
    const cv::Mat& scores = outputs[level.class_index];
    const cv::Mat& distances = outputs[level.distance_index];
    const int cells = scores.size[1];
    const int bins = distances.size[2] / 4;
    const int columns = (input.width + level.stride - 1) / level.stride;
    for (int cell = 0; cell < cells; ++cell) {
      const float* s = scores.ptr<float>(0) + static_cast<std::size_t>(cell) * num_classes;
      const auto [class_id, score] = BestClass(s, num_classes, 1);
      if (score < score_threshold) continue;
      const float* d = distances.ptr<float>(0) + static_cast<std::size_t>(cell) * 4 * bins;
      // Cell centres sit half a stride into the cell, rows in order (row-major grid).
      const double cx = (cell % columns + 0.5) * level.stride;
      const double cy = (cell / columns + 0.5) * level.stride;
      const double left = ExpectedBin(d, bins) * level.stride;
      const double top = ExpectedBin(d + bins, bins) * level.stride;
      const double right = ExpectedBin(d + 2 * bins, bins) * level.stride;
      const double bottom = ExpectedBin(d + 3 * bins, bins) * level.stride;
      Detection box;
      box.class_id = class_id;
      box.confidence = score;
      box.x = cx - left;
      box.y = cy - top;
      box.width = left + right;
      box.height = top + bottom;
      boxes.push_back(box);
    }
  }
  return boxes;
}

std::vector<Detection> DecodeYoloV5(const cv::Mat& output, int num_classes,
                                    double score_threshold) {
  std::vector<Detection> boxes;
  const int anchors = output.size[1];
  const int stride = output.size[2];
  for (int a = 0; a < anchors; ++a) {
    const float* row = output.ptr<float>(0) + static_cast<std::size_t>(a) * stride;
    const float objectness = row[4];
    if (objectness < score_threshold) continue;  // the product cannot reach it either
    const auto [class_id, class_score] = BestClass(row + 5, num_classes, 1);
    const double score = static_cast<double>(objectness) * class_score;
    if (score < score_threshold) continue;
    boxes.push_back(FromCentre(class_id, score, row[0], row[1], row[2], row[3]));
  }
  return boxes;
}

std::vector<Detection> DecodeYoloV8(const cv::Mat& output, int num_classes,
                                    double score_threshold) {
  std::vector<Detection> boxes;
  const int anchors = output.size[2];
  const float* base = output.ptr<float>(0);
  for (int a = 0; a < anchors; ++a) {
    const float* column = base + a;  // channel k of anchor a at column[k * anchors]
    const auto [class_id, score] = BestClass(column + 4 * anchors, num_classes, anchors);
    if (score < score_threshold) continue;
    boxes.push_back(FromCentre(class_id, score, column[0], column[anchors], column[2 * anchors],
                               column[3 * anchors]));
  }
  return boxes;
}

}  // namespace

std::string LayoutName(OutputLayout layout) {
  switch (layout) {
    case OutputLayout::kNanoDet:
      return "NanoDet";
    case OutputLayout::kYoloV5:
      return "YOLOv5";
    case OutputLayout::kYoloV8:
      return "YOLOv8";
  }
  return "unknown";
}

ModelOutputs ChooseLayout(const std::vector<std::vector<int>>& output_shapes, cv::Size input_size) {
  ModelOutputs model;
  if (output_shapes.size() == 1 && IsBatchOf3d(output_shapes[0])) {
    const int a = output_shapes[0][1];
    const int b = output_shapes[0][2];
    if (a > b && b > 5) {
      model.layout = OutputLayout::kYoloV5;
      model.num_classes = b - 5;
      return model;
    }
    if (b > a && a > 4) {
      model.layout = OutputLayout::kYoloV8;
      model.num_classes = a - 4;
      return model;
    }
  }
  if (output_shapes.size() >= 2 && output_shapes.size() % 2 == 0) {
    int classes = 0;
    if (!NanoDetLevels(output_shapes, input_size, &classes).empty()) {
      model.layout = OutputLayout::kNanoDet;
      model.num_classes = classes;
      return model;
    }
  }
  std::string shapes;
  for (const auto& shape : output_shapes) shapes += (shapes.empty() ? "" : ", ") + ShapeText(shape);
  throw std::invalid_argument(
      "the model's outputs (" + shapes + ", input " + std::to_string(input_size.width) + "x" +
      std::to_string(input_size.height) +
      ") fit no known detector layout: YOLOv5 export [1, N, 5 + classes], YOLOv8 export "
      "[1, 4 + classes, N], or NanoDet pairs [1, cells, classes] + [1, cells, 4 (bins)] per "
      "stride 8, 16, 32, ...");
}

std::vector<Detection> DecodeOutputs(const ModelOutputs& model, const std::vector<cv::Mat>& outputs,
                                     cv::Size input_size, double score_threshold) {
  for (const cv::Mat& m : outputs) {
    assert(m.type() == CV_32F && m.isContinuous() && m.dims == 3);
    (void)m;
  }
  switch (model.layout) {
    case OutputLayout::kNanoDet:
      return DecodeNanoDet(outputs, input_size, score_threshold);
    case OutputLayout::kYoloV5:
      assert(outputs.size() == 1 && outputs[0].size[2] == model.num_classes + 5);
      return DecodeYoloV5(outputs[0], model.num_classes, score_threshold);
    case OutputLayout::kYoloV8:
      assert(outputs.size() == 1 && outputs[0].size[1] == model.num_classes + 4);
      return DecodeYoloV8(outputs[0], model.num_classes, score_threshold);
  }
  return {};
}

double BoxIou(const Detection& a, const Detection& b) {
  const auto corners = [](const Detection& d) {
    return Box2{d.x, d.y, d.x + d.width, d.y + d.height};
  };
  return IntersectionOverUnion(corners(a), corners(b));
}

std::vector<Detection> ClassWiseNms(const std::vector<Detection>& boxes, double iou_threshold) {
  std::vector<std::size_t> order(boxes.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) {
    return boxes[i].confidence > boxes[j].confidence;
  });
  std::vector<Detection> kept;
  for (std::size_t i : order) {
    const Detection& candidate = boxes[i];
    const bool suppressed = std::any_of(kept.begin(), kept.end(), [&](const Detection& k) {
      return k.class_id == candidate.class_id && BoxIou(k, candidate) > iou_threshold;
    });
    if (!suppressed) kept.push_back(candidate);
  }
  return kept;
}

}  // namespace ocg
