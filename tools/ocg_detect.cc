// ocg_detect: runs a detector network (ONNX, OpenCV DNN, CPU) over a sequence's images and
// writes the detection files ocg_slam reads.

#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <opencv2/core/utility.hpp>

#include "cli_common.h"
#include "ocg/core/coco.h"
#include "ocg/core/file_io.h"
#include "ocg/detect/detect_images.h"

int main(int argc, char** argv) {
  CLI::App app{
      "ocg_detect: detects COCO-80 objects in a sequence's images with a detector network "
      "(ONNX: NanoDet, or a YOLOv5/YOLOv8 export; run on the CPU by OpenCV) and writes "
      "one EAO detection file per image (<timestamp>.txt: 'class_id x y w h confidence', x y "
      "the top-left corner), the input of ocg_slam run --detections. The default model "
      "comes from tools/get_detector.sh (docs/detector.md).",
      "ocg_detect"};
  const std::string default_model = ocg::DefaultDetectorModel();
  std::string log_level, images_path, out_dir, model_path = default_model, tile = "auto";
  ocg::DetectionModelOptions options;
  bool json = false;
  int threads = 0;
  ocg::tools::AddLogLevelOption(app, &log_level);
  app.add_option("--images", images_path,
                 "a TUM frame list (rgb.txt), a TUM sequence folder, or a folder of images "
                 "(file name without extension = timestamp)")
      ->required();
  app.add_option("--out", out_dir, "folder for the detection files (created if missing)")
      ->required();
  app.add_option("--model", model_path, "the detector, an .onnx file")->capture_default_str();
  app.add_option("--score", options.score_threshold, "minimum confidence of a box")
      ->capture_default_str();
  app.add_option("--nms-iou", options.nms_iou,
                 "class-wise NMS: drop a box overlapping a more confident one of its class by "
                 "more than this IoU")
      ->capture_default_str();
  app.add_option("--tile", tile,
                 "auto: cut images wider (or taller) than 1.5:1 into overlapping squares; off: "
                 "one pass over the whole image")
      ->check(CLI::IsMember({"auto", "off"}))
      ->capture_default_str();
  app.add_option("--input-size", options.input_size,
                 "network input side for models without a fixed one (0: the model's, else 640)")
      ->capture_default_str();
  app.add_flag("--json", json, "also write DIR/detections.json (the JSON list format)");
  app.add_option("--threads", threads, "OpenCV threads (0: all cores)")->capture_default_str();

  return ocg::tools::RunTool(app, argc, argv, log_level, [&] {
    if (threads > 0) cv::setNumThreads(threads);
    options.model_path = model_path;
    options.tile_mode = tile == "off" ? ocg::TileMode::kOff : ocg::TileMode::kAuto;
    ocg::RequireDetectorModel(model_path);
    // Every input is checked before the first image: the list and the model here, the
    // images and the output folder in DetectImagesToFolder.
    const std::vector<ocg::TimedImage> images = ocg::ListImagesToDetect(images_path);
    ocg::DetectionModel model(options);
    std::cout << "ocg_detect: " << images.size() << " images, model " << model_path << " ("
              << model.Describe() << "), score >= " << options.score_threshold << ", tiles " << tile
              << "\n";

    ocg::ProgressLine progress("images", images.size());
    auto last_log = std::chrono::steady_clock::now();
    const ocg::DetectRunSummary summary =
        ocg::DetectImagesToFolder(model, images, out_dir, json, [&](std::size_t done) {
          progress.Update(done);
          // Without a terminal (logs, CI) a line every few seconds instead.
          const auto now = std::chrono::steady_clock::now();
          if (!progress.enabled() && now - last_log > std::chrono::seconds(5)) {
            spdlog::info("{}/{} images", done, images.size());
            last_log = now;
          }
        });
    progress.Finish();
    const double per_image = summary.images ? 1000.0 / summary.images : 0.0;
    std::cout << summary.boxes << " boxes in " << summary.images << " images ("
              << std::lround(summary.seconds * per_image) << " ms per image, "
              << std::lround(summary.cpu_seconds * per_image) << " ms CPU)";
    std::string classes;
    for (const auto& [class_id, count] : summary.boxes_per_class) {
      classes += (classes.empty() ? "" : ", ") + ocg::CocoClassName(class_id) + " " +
                 std::to_string(count);
    }
    std::cout << (classes.empty() ? "" : ": " + classes) << "\nwrote " << out_dir
              << "/<timestamp>.txt" << (json ? " and detections.json" : "") << "\n";
  });
}
