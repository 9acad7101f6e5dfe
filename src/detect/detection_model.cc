#include "ocg/detect/detection_model.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "ocg/core/file_io.h"
#include "ocg/detect/onnx_file.h"
#include "ocg/io/text_lines.h"

namespace ocg {
namespace {

constexpr int kCocoClasses = 80;
constexpr int kDefaultYoloInput = 640;  // what YOLOv5/v8 exports use unless told otherwise
const cv::Scalar kLetterboxGrey(114, 114, 114);
// NanoDet's input normalisation (its training configuration, BGR order): (pixel - mean) / std.
const cv::Scalar kNanoDetMeanBgr(103.53, 116.28, 123.675);
const cv::Scalar kNanoDetInverseStdBgr(1.0 / 57.375, 1.0 / 57.12, 1.0 / 58.395);

// How network-input pixels map back to image pixels: image = (net - offset) / scale.
struct InputMapping {
  double scale_x = 1.0;
  double scale_y = 1.0;
  double offset_x = 0.0;
  double offset_y = 0.0;
};

cv::Size InputSizeOf(const std::string& path, int fallback) {
  for (const OnnxInput& input : ReadOnnxInputs(path)) {
    if (input.dims.size() != 4) continue;
    const int height = input.dims[2] > 0 ? static_cast<int>(input.dims[2]) : fallback;
    const int width = input.dims[3] > 0 ? static_cast<int>(input.dims[3]) : fallback;
    if (input.dims[1] > 0 && input.dims[1] != 3) {
      throw std::invalid_argument(path + ": the image input '" + input.name + "' has " +
                                  std::to_string(input.dims[1]) +
                                  " channels; a detector takes 3 (NCHW)");
    }
    return {width, height};
  }
  throw std::invalid_argument(path + ": the model has no 4-D (NCHW) image input");
}

std::vector<int> ShapeOf(const cv::Mat& m) { return std::vector<int>(m.size.p, m.size.p + m.dims); }

cv::Mat ToBgr(const cv::Mat& image) {
  if (image.empty()) throw std::invalid_argument("DetectionModel: empty image");
  if (image.depth() != CV_8U) {
    throw std::invalid_argument("DetectionModel: expects an 8-bit image, got depth " +
                                std::to_string(image.depth()));
  }
  cv::Mat bgr;
  switch (image.channels()) {
    case 1:
      cv::cvtColor(image, bgr, cv::COLOR_GRAY2BGR);
      return bgr;
    case 3:
      return image;
    case 4:
      cv::cvtColor(image, bgr, cv::COLOR_BGRA2BGR);
      return bgr;
    default:
      throw std::invalid_argument("DetectionModel: expects 1, 3 or 4 channels, got " +
                                  std::to_string(image.channels()));
  }
}

Detection ToImage(const Detection& box, const InputMapping& map) {
  Detection out = box;
  out.x = (box.x - map.offset_x) / map.scale_x;
  out.y = (box.y - map.offset_y) / map.scale_y;
  out.width = box.width / map.scale_x;
  out.height = box.height / map.scale_y;
  return out;
}

// Clipped to the image; false when less than a pixel is left.
bool ClipToImage(Detection* box, cv::Size image) {
  const double x1 = std::clamp(box->x, 0.0, static_cast<double>(image.width));
  const double y1 = std::clamp(box->y, 0.0, static_cast<double>(image.height));
  const double x2 = std::clamp(box->x + box->width, 0.0, static_cast<double>(image.width));
  const double y2 = std::clamp(box->y + box->height, 0.0, static_cast<double>(image.height));
  box->x = x1;
  box->y = y1;
  box->width = x2 - x1;
  box->height = y2 - y1;
  return box->width >= 1.0 && box->height >= 1.0;
}

}  // namespace

std::string DefaultDetectorModel() {
  if (const char* env = std::getenv("OCG_DETECTOR_MODEL"); env && *env) return env;
  for (const char* candidate : {OCG_SOURCE_DETECTOR_MODEL, OCG_INSTALLED_DETECTOR_MODEL}) {
    std::error_code error;
    if (std::filesystem::is_regular_file(candidate, error)) return candidate;
  }
  return OCG_SOURCE_DETECTOR_MODEL;
}

void RequireDetectorModel(const std::string& path) {
  std::error_code error;
  if (std::filesystem::exists(path, error)) return;
  const char* env = std::getenv("OCG_DETECTOR_MODEL");
  std::string hint = "give an existing .onnx file";
  if (path == DefaultDetectorModel()) {
    hint = env && *env ? "it is $OCG_DETECTOR_MODEL; unset it or point it at an .onnx file"
                       : "run tools/get_detector.sh once (it builds the default NanoDet model "
                         "there; docs/detector.md), or give --model F.onnx";
  }
  throw FileError("no detector model at '" + path + "': " + hint);
}

void DetectionModelOptions::Check() const {
  if (model_path.empty()) throw std::invalid_argument("DetectionModelOptions.model_path is empty");
  if (!(score_threshold > 0.0 && score_threshold < 1.0)) {
    throw std::invalid_argument("DetectionModelOptions.score_threshold must be in (0, 1), got " +
                                std::to_string(score_threshold));
  }
  if (!(nms_iou > 0.0 && nms_iou <= 1.0)) {
    throw std::invalid_argument("DetectionModelOptions.nms_iou must be in (0, 1], got " +
                                std::to_string(nms_iou));
  }
  if (input_size < 0 || input_size > 4096 || input_size % 32 != 0) {
    throw std::invalid_argument(
        "DetectionModelOptions.input_size must be 0 (the model's) or a multiple of 32 up to "
        "4096, got " +
        std::to_string(input_size));
  }
  tiling.Check();
}

struct DetectionModel::Impl {
  cv::dnn::Net net;
  std::vector<std::string> output_names;

  std::vector<cv::Mat> Forward(const cv::Mat& blob) {
    net.setInput(blob);
    std::vector<cv::Mat> outputs;
    net.forward(outputs, output_names);
    return outputs;
  }
};

DetectionModel::DetectionModel(const DetectionModelOptions& options)
    : options_(options), impl_(std::make_unique<Impl>()) {
  options_.Check();
  const std::string& path = options_.model_path;
  RequireRegularFile(path);
  input_size_ =
      InputSizeOf(path, options_.input_size > 0 ? options_.input_size : kDefaultYoloInput);
  try {
    impl_->net = cv::dnn::readNetFromONNX(path);
  } catch (const cv::Exception& error) {
    throw ParseError(path + ": OpenCV cannot load this ONNX model: " + error.what());
  }
  if (impl_->net.empty()) throw ParseError(path + ": OpenCV loaded an empty network");
  impl_->net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  impl_->net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  impl_->output_names = impl_->net.getUnconnectedOutLayersNames();
  std::vector<std::vector<int>> shapes;
  try {
    const cv::Mat blank(input_size_, CV_8UC3, cv::Scalar::all(0));
    for (const cv::Mat& m : impl_->Forward(cv::dnn::blobFromImage(blank, 1.0 / 255.0))) {
      shapes.push_back(ShapeOf(m));
    }
  } catch (const cv::Exception& error) {
    throw ParseError(path + ": OpenCV cannot run this ONNX model on a " +
                     std::to_string(input_size_.width) + "x" + std::to_string(input_size_.height) +
                     " input: " + error.what());
  }
  try {
    outputs_ = ChooseLayout(shapes, input_size_);
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument(path + ": " + error.what());
  }
  if (options_.require_coco80 && outputs_.num_classes != kCocoClasses) {
    throw std::invalid_argument(path + ": a " + LayoutName(outputs_.layout) + " model with " +
                                std::to_string(outputs_.num_classes) +
                                " classes; detection files hold COCO-80 class ids, so the "
                                "model must have the 80 COCO classes in COCO order");
  }
}

DetectionModel::~DetectionModel() = default;

std::string DetectionModel::Describe() const {
  return LayoutName(outputs_.layout) + ", " + std::to_string(outputs_.num_classes) +
         " classes, input " + std::to_string(input_size_.width) + "x" +
         std::to_string(input_size_.height);
}

std::vector<Detection> DetectionModel::DetectOnce(const cv::Mat& bgr) {
  InputMapping map;
  cv::Mat blob;
  if (outputs_.layout == OutputLayout::kNanoDet) {
    // Stretched to the square and normalised per channel, as NanoDet was trained.
    map.scale_x = static_cast<double>(input_size_.width) / bgr.cols;
    map.scale_y = static_cast<double>(input_size_.height) / bgr.rows;
    cv::Mat resized;
    cv::resize(bgr, resized, input_size_, 0, 0, cv::INTER_LINEAR);
    cv::Mat normalised;
    resized.convertTo(normalised, CV_32F);
    cv::subtract(normalised, kNanoDetMeanBgr, normalised);
    cv::multiply(normalised, kNanoDetInverseStdBgr, normalised);
    blob = cv::dnn::blobFromImage(normalised, 1.0, cv::Size(), cv::Scalar(), false, false);
  } else {
    // Letterboxed, as the YOLO exports were trained and validated.
    const double scale = std::min(static_cast<double>(input_size_.width) / bgr.cols,
                                  static_cast<double>(input_size_.height) / bgr.rows);
    const cv::Size scaled(std::max(1, static_cast<int>(std::lround(bgr.cols * scale))),
                          std::max(1, static_cast<int>(std::lround(bgr.rows * scale))));
    cv::Mat canvas(input_size_, CV_8UC3, kLetterboxGrey);
    const int left = (input_size_.width - scaled.width) / 2;
    const int top = (input_size_.height - scaled.height) / 2;
    cv::resize(bgr, canvas(cv::Rect(left, top, scaled.width, scaled.height)), scaled, 0, 0,
               cv::INTER_LINEAR);
    map.scale_x = map.scale_y = scale;
    map.offset_x = left;
    map.offset_y = top;
    blob = cv::dnn::blobFromImage(canvas, 1.0 / 255.0, cv::Size(), cv::Scalar(), true, false);
  }
  const std::vector<cv::Mat> outputs = impl_->Forward(blob);
  std::vector<Detection> boxes;
  for (const Detection& box :
       DecodeOutputs(outputs_, outputs, input_size_, options_.score_threshold)) {
    Detection mapped = ToImage(box, map);
    if (ClipToImage(&mapped, bgr.size())) boxes.push_back(mapped);
  }
  return ClassWiseNms(boxes, options_.nms_iou);
}

std::vector<Detection> DetectionModel::Detect(const cv::Mat& image) {
  const cv::Mat bgr = ToBgr(image);
  const std::vector<cv::Rect> tiles = options_.tile_mode == TileMode::kAuto
                                          ? SquareTiles(bgr.size(), options_.tiling)
                                          : std::vector<cv::Rect>{};
  if (tiles.empty()) return DetectOnce(bgr);
  std::vector<std::vector<Detection>> per_tile;
  for (const cv::Rect& tile : tiles) {
    std::vector<Detection> boxes = DetectOnce(bgr(tile));
    for (Detection& box : boxes) {
      box.x += tile.x;
      box.y += tile.y;
    }
    per_tile.push_back(std::move(boxes));
  }
  return MergeTileDetections(tiles, per_tile, DetectOnce(bgr), bgr.size(), options_.tiling,
                             options_.nms_iou);
}

}  // namespace ocg
