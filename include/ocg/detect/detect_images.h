#pragma once
// A detector over a list of images, into the detection files the rest of the product
// reads: what ocg_detect does, callable from C++ and Python.

#include <cstddef>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "ocg/detect/detection_model.h"
#include "ocg/io/sequence.h"

namespace ocg {

// The frames to detect on: a TUM frame list (rgb.txt: "timestamp path" lines), a TUM
// sequence folder holding rgb.txt, or a folder of images (.png .jpg .jpeg .bmp .ppm .pgm;
// the timestamp text of each is its file name without extension, frames sorted by name).
// Throws FileError naming the path when it is neither, or the folder holds no image;
// ParseError as ReadTumImageList.
std::vector<TimedImage> ListImagesToDetect(const std::string& path);

struct DetectRunSummary {
  std::size_t images = 0;
  std::size_t boxes = 0;
  std::map<int, std::size_t> boxes_per_class;  // COCO id -> boxes
  double seconds = 0.0;                        // wall time of the detections alone
  double cpu_seconds = 0.0;  // CPU time of the detections, all threads of the process
};

// Runs the model on every image and writes out_dir/<timestamp_text>.txt (EAO text format,
// one file per image, empty when nothing was found), each file written atomically; with
// write_json also out_dir/detections.json (the JSON list format, file_name the image
// path read). progress(done) after each image. Throws FileError naming a missing image or
// the folder when it cannot be written (both checked before the first image), or an
// image that cannot be decoded.
DetectRunSummary DetectImagesToFolder(DetectionModel& model, const std::vector<TimedImage>& images,
                                      const std::string& out_dir, bool write_json,
                                      const std::function<void(std::size_t)>& progress = {});

}  // namespace ocg
