#pragma once
// From a detector network's raw output tensors to boxes: the output layouts of NanoDet and
// of the ONNX exports of YOLOv5 and YOLOv8, recognised from the tensors' shapes, and
// class-wise non-maximum suppression.
//
// Boxes come out in the network input's pixels (x y the top-left corner); the caller maps
// them to the image (ocg/detect/detection_model.h).

#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

#include "ocg/io/detections.h"

namespace ocg {

enum class OutputLayout {
  // Per feature level (strides 8, 16, 32, ...), two tensors of N = cells of the level:
  // class scores [1, N, C] (after the sigmoid) and side distances [1, N, 4 (R + 1)], a
  // distribution over R + 1 bins per side (left, top, right, bottom) in units of the
  // stride, from the cell centre. C > 4 (R + 1) tells them apart (80 > 44 for COCO).
  kNanoDet,
  // One tensor [1, N, 5 + C]: centre x, centre y, width, height (input pixels),
  // objectness, C class scores (all after the sigmoid); score = objectness * class.
  kYoloV5,
  // One tensor [1, 4 + C, N]: centre x, centre y, width, height, C class scores.
  kYoloV8,
};

std::string LayoutName(OutputLayout layout);

struct ModelOutputs {
  OutputLayout layout = OutputLayout::kNanoDet;
  int num_classes = 0;
};

// The layout that fits the output shapes ([1, A, B] each) for a network input of
// input_size. Throws std::invalid_argument listing the shapes and the layouts it knows
// when none fits.
ModelOutputs ChooseLayout(const std::vector<std::vector<int>>& output_shapes, cv::Size input_size);

// Every candidate whose best class scores at least score_threshold (one box per anchor,
// of its best class), before suppression. outputs: the tensors, CV_32F, in any order.
// Asserts that they have the layout's shapes.
std::vector<Detection> DecodeOutputs(const ModelOutputs& model, const std::vector<cv::Mat>& outputs,
                                     cv::Size input_size, double score_threshold);

// Intersection over union of two boxes (x y top-left, width height); 0 when either is
// empty.
double BoxIou(const Detection& a, const Detection& b);

// Class-wise non-maximum suppression: per class, in decreasing confidence (ties: input
// order), a box is kept unless it overlaps a kept box of its class by IoU > iou_threshold.
// The result is ordered by decreasing confidence, so it is the same for the same input.
std::vector<Detection> ClassWiseNms(const std::vector<Detection>& boxes, double iou_threshold);

}  // namespace ocg
