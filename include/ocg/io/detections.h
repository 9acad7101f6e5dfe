#pragma once
// Offline 2-D object detections in the two formats object SLAM systems ship:
//  - EAO-SLAM / YOLO text: one file per image, "<timestamp>.txt", one detection per line
//    "class_id x y w h confidence", x y the top-left corner in pixels, COCO-80 class ids.
//  - JSON list: [{"file_name": ..., "detections": [{"category_id", "detection_score",
//    "bbox": [x1, y1, x2, y2]}]}].

#include <string>
#include <vector>

namespace ocg {

struct Detection {
  int class_id = 0;  // COCO-80 index
  double x = 0.0;    // top-left corner, pixels
  double y = 0.0;
  double width = 0.0;  // pixels, > 0
  double height = 0.0;
  double confidence = 0.0;  // in [0, 1]
};

struct DetectionFrame {
  std::string file_name;  // image the detections belong to
  std::vector<Detection> detections;
};

struct DetectionReadOptions {
  // Skip malformed lines with a warning instead of failing (the --lenient flag).
  bool lenient = false;
};

// One EAO text file. Throws FileError when missing, ParseError naming file and line
// when a line is malformed (unless lenient).
std::vector<Detection> ReadEaoDetectionFile(const std::string& path,
                                            const DetectionReadOptions& options = {});
// The detections of one image in a folder of EAO files: "<dir>/<timestamp_text>.txt".
// A missing file means the detector found nothing: an empty list.
std::vector<Detection> ReadEaoDetectionsForImage(const std::string& dir,
                                                 const std::string& timestamp_text,
                                                 const DetectionReadOptions& options = {});
// All "*.txt" files of a folder, sorted by name; file_name is the file's stem.
std::vector<DetectionFrame> ReadEaoDetectionDir(const std::string& dir,
                                                const DetectionReadOptions& options = {});
std::string FormatEaoDetections(const std::vector<Detection>& detections);

// JSON list format. Throws ParseError naming the file and the offending entry.
std::vector<DetectionFrame> ReadJsonDetections(const std::string& path);
std::string FormatJsonDetections(const std::vector<DetectionFrame>& frames);

}  // namespace ocg
