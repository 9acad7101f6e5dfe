#pragma once
// A detector network in an ONNX file, run with OpenCV's DNN module on the CPU: image in,
// COCO-80 boxes out. The output layout (NanoDet, YOLOv5 or YOLOv8 export) is recognised
// from the model's output shapes when it is loaded; the input size is read from the file.
//
// Preprocessing per layout: NanoDet takes the image stretched to its input square, BGR,
// normalised per channel as in its training ((pixel - mean) / std, mean 103.53 116.28
// 123.675, std 57.375 57.12 58.395); YOLO exports take it letterboxed (aspect kept, grey
// 114 borders), RGB, scaled to [0, 1]. Wide images are cut into overlapping squares
// (ocg/detect/tiling.h).
//
// Threads: one DetectionModel runs one frame at a time (not thread-safe); use one per
// thread. OpenCV's own worker threads follow cv::setNumThreads.

#include <memory>
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

#include "ocg/detect/decode.h"
#include "ocg/detect/tiling.h"
#include "ocg/io/detection_source.h"

namespace ocg {

enum class TileMode { kAuto, kOff };

// Where the default model is looked for: $OCG_DETECTOR_MODEL when set, else
// models/nanodet/nanodet.onnx of the source tree (tools/get_detector.sh puts it there),
// else <prefix>/share/ocg/models/nanodet.onnx of an installed build. The first that
// exists; the source-tree path when none does (so the error can name it).
std::string DefaultDetectorModel();

// Throws FileError when there is no file at path, saying how to get one: the default
// model is built once by tools/get_detector.sh (docs/detector.md), nothing is downloaded
// at run time. For ocg_detect and `ocg_slam run --detect`, before any frame.
void RequireDetectorModel(const std::string& path);

struct DetectionModelOptions {
  std::string model_path;  // an .onnx file
  // Boxes below this confidence are dropped. 0.4 keeps the default NanoDet model's false
  // boxes below 2 a frame on real desk frames (docs/detector.md); YOLO exports use 0.25.
  double score_threshold = 0.4;
  // Class-wise NMS: a box overlapping a more confident one of its class by more is dropped.
  double nms_iou = 0.5;
  // kAuto tiles images whose aspect exceeds tiling.min_aspect; kOff never tiles.
  TileMode tile_mode = TileMode::kAuto;
  TilingOptions tiling;
  // Network input side for models whose file leaves it open (dynamic axes); 0 keeps the
  // file's. YOLO exports are usually 640.
  int input_size = 0;
  // The product's detection files hold COCO-80 ids: refuse models with another number of
  // classes unless this is false (then ids are the model's own).
  bool require_coco80 = true;
  // Throws std::invalid_argument naming the field when a value is impossible.
  void Check() const;
};

class DetectionModel : public DetectionSource {
 public:
  // Loads the model and runs it once on a blank image to learn its output layout.
  // Throws FileError when the file cannot be read, ParseError when it is not ONNX or
  // OpenCV cannot load it (the message names the file and OpenCV's reason), and
  // std::invalid_argument when its outputs fit no known layout or it has not 80 classes.
  explicit DetectionModel(const DetectionModelOptions& options);
  ~DetectionModel() override;
  DetectionModel(const DetectionModel&) = delete;
  DetectionModel& operator=(const DetectionModel&) = delete;

  // Detections of one image (8-bit, 1, 3 or 4 channels, BGR as cv::imread gives), boxes
  // in its pixels clipped to it, ordered by decreasing confidence. Throws
  // std::invalid_argument for an empty image or another depth.
  std::vector<Detection> Detect(const cv::Mat& image);

  // Detect's boxes as the detection files ocg_detect writes keep them
  // (AsStoredInEaoFiles), so `ocg_slam run --detect` equals ocg_detect then --detections.
  // The frame's image must be given (NeedsImage); Detect's errors.
  std::vector<Detection> DetectionsFor(const std::string& /*timestamp_text*/,
                                       const cv::Mat& image) override {
    return AsStoredInEaoFiles(Detect(image));
  }
  bool NeedsImage() const override { return true; }

  const ModelOutputs& outputs() const { return outputs_; }
  cv::Size input_size() const { return input_size_; }
  // "NanoDet, 80 classes, input 416x416" for logs and run.json.
  std::string Describe() const override;

 private:
  struct Impl;
  // One pass of the network over a 3-channel BGR image, boxes in its pixels after NMS.
  std::vector<Detection> DetectOnce(const cv::Mat& bgr);
  DetectionModelOptions options_;
  std::unique_ptr<Impl> impl_;
  ModelOutputs outputs_;
  cv::Size input_size_;
};

}  // namespace ocg
