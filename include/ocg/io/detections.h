#pragma once
// Offline 2-D object detections in the two formats object SLAM systems ship:
//  - EAO-SLAM / YOLO text: one file per image, "<timestamp>.txt", one detection per line
//    "class_id x y w h confidence", x y the top-left corner in pixels, COCO-80 class ids.
//  - JSON list: [{"file_name": ..., "detections": [{"category_id", "detection_score",
//    "bbox": [x1, y1, x2, y2]}]}].

#include <cstdint>
#include <string>
#include <unordered_map>
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

// The one check of a detection, whatever gave it (an EAO text line, a JSON entry, a Python
// array): class_id a COCO-80 index in [0, 79], x and y finite, width and height positive
// and finite, confidence in [0, 1]. Throws ParseError "where: what is wrong".
void CheckDetection(const Detection& detection, const std::string& where);
// A row [class_id, x, y, w, h, confidence] of numbers: class_id must be a whole number,
// then CheckDetection. Throws ParseError "where: what is wrong".
Detection DetectionFromRow(const double (&row)[6], const std::string& where);

struct DetectionFrame {
  std::string file_name;  // image the detections belong to
  std::vector<Detection> detections;
};

struct DetectionReadOptions {
  // Skip malformed lines with a warning instead of failing (the --lenient flag).
  bool lenient = false;
  // Larger EAO files are refused. One image's detections take a few hundred bytes (the
  // real TUM files: at most 391 bytes, 30 boxes); 16 MiB would be some 400,000 boxes in
  // one image, far past what any detector keeps (YOLO: at most a few hundred), so a file
  // this large is not a detection file, or is broken.
  std::uintmax_t max_file_bytes = std::uintmax_t{16} << 20;
  // Larger JSON lists (every image of a sequence in one file) are refused: parsed, a
  // JSON file takes about ten times its size in memory.
  std::uintmax_t max_json_bytes = std::uintmax_t{256} << 20;
};

// One EAO text file, read line by line. Throws FileError when it is missing, not a
// regular file, unreadable or larger than options.max_file_bytes; ParseError naming file
// and line when a line is malformed (unless lenient).
std::vector<Detection> ReadEaoDetectionFile(const std::string& path,
                                            const DetectionReadOptions& options = {});
// The detections of one image in a folder of EAO files: "<dir>/<timestamp_text>.txt".
// No file at that path means the detector found nothing: an empty list. Anything else
// there that is not a readable file (a folder, a broken link) is a FileError.
std::vector<Detection> ReadEaoDetectionsForImage(const std::string& dir,
                                                 const std::string& timestamp_text,
                                                 const DetectionReadOptions& options = {});

// The detections of a run's frames, all read and checked before the first frame is
// processed, so a bad file fails at start and not after the whole sequence.
class EaoDetectionFolder {
 public:
  // frames: the timestamp texts of the frames to process, as in rgb.txt (file
  // "<dir>/<text>.txt"). Throws FileError when dir is not a folder, when it holds no
  // .txt file or none of its files matches a frame (the message gives an expected name
  // and a name found), or when a frame's path is not a readable file; ParseError as
  // ReadEaoDetectionFile. Warns, naming the folder, when every box lies within 0..1.
  EaoDetectionFolder(const std::string& dir, const std::vector<std::string>& frames,
                     const DetectionReadOptions& options = {});
  // The frame's detections; empty when its file is missing.
  const std::vector<Detection>& ForFrame(const std::string& timestamp_text) const;
  std::size_t FilesMatched() const { return by_frame_.size(); }
  std::size_t DetectionCount() const { return detections_; }
  bool LooksNormalized() const { return looks_normalized_; }

 private:
  std::unordered_map<std::string, std::vector<Detection>> by_frame_;
  std::size_t detections_ = 0;
  bool looks_normalized_ = false;
};

// All "*.txt" files of a folder, sorted by name; file_name is the file's stem. Throws
// FileError when the folder holds none, or a "*.txt" entry is not a readable file; warns
// when every box lies within 0..1.
std::vector<DetectionFrame> ReadEaoDetectionDir(const std::string& dir,
                                                const DetectionReadOptions& options = {});
// True when there is a box and every x, y, w and h lies within [0, 1]: normalized
// coordinates (YOLO's "cls cx cy w h"), not the pixels the EAO format and this program use.
bool BoxesLookNormalized(const std::vector<DetectionFrame>& frames);
std::string FormatEaoDetections(const std::vector<Detection>& detections);
// The detections as an EAO text file keeps them: FormatEaoDetections (coordinates to 6
// significant digits, confidence to 6 decimals) read back by the file reader. A detector
// run inside a run (`ocg_slam run --detect`) hands these over, so that a run does not
// depend on whether its detections were stored first (`ocg_detect`, then --detections).
std::vector<Detection> AsStoredInEaoFiles(const std::vector<Detection>& detections);

// JSON list format. Throws FileError when the file is not a readable file or is larger
// than options.max_json_bytes, ParseError naming the file and the offending entry. Warns
// when every box lies within 0..1.
std::vector<DetectionFrame> ReadJsonDetections(const std::string& path,
                                               const DetectionReadOptions& options = {});
std::string FormatJsonDetections(const std::vector<DetectionFrame>& frames);

}  // namespace ocg
