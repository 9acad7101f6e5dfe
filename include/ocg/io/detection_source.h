#pragma once
// Where a run's 2-D detections come from: files written beforehand by any detector (the
// EAO text folder or the JSON list), boxes handed over in memory (Python), or a detector
// run on the frame itself (ocg/detect/detection_model.h). The sequence runner
// (ocg/app/sequence_runner.h) asks one source per frame and does not care which; a new
// detection format is one more implementation here.

#include <cstddef>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <string>
#include <unordered_map>
#include <vector>

#include "ocg/io/detections.h"
#include "ocg/io/sequence.h"

namespace ocg {

class DetectionSource {
 public:
  virtual ~DetectionSource() = default;
  // The detections of one frame, boxes in the frame's pixels (x y the top-left corner),
  // COCO-80 class ids. timestamp_text: the frame's time exactly as in rgb.txt (the name of
  // its detection file). image: the frame as read from disk (cv::IMREAD_UNCHANGED: 8-bit,
  // 1, 3 or 4 channels BGR) when NeedsImage(), else possibly empty. Not safe to call from
  // two threads at once unless the implementation says so.
  virtual std::vector<Detection> DetectionsFor(const std::string& timestamp_text,
                                               const cv::Mat& image) = 0;
  // Whether DetectionsFor looks at the image (a detector network): the runner then
  // decodes each frame for it too, on its reader thread.
  virtual bool NeedsImage() const { return false; }
  // For logs and run.json: "EAO folder 'DIR'", "NanoDet, 80 classes, input 416x416".
  virtual std::string Describe() const = 0;
  // Frames of the run the source holds an entry for (files: those matched); 0 for a
  // detector.
  virtual std::size_t FramesMatched() const { return 0; }
};

// An EAO text folder, every frame's file read and checked at construction (EaoDetectionFolder).
class FolderDetectionSource : public DetectionSource {
 public:
  explicit FolderDetectionSource(EaoDetectionFolder folder, std::string dir = "")
      : folder_(std::move(folder)), dir_(std::move(dir)) {}
  std::vector<Detection> DetectionsFor(const std::string& timestamp_text,
                                       const cv::Mat& /*image*/) override {
    return folder_.ForFrame(timestamp_text);
  }
  std::string Describe() const override { return "EAO folder '" + dir_ + "'"; }
  std::size_t FramesMatched() const override { return folder_.FilesMatched(); }
  const EaoDetectionFolder& folder() const { return folder_; }

 private:
  EaoDetectionFolder folder_;
  std::string dir_;
};

// Boxes per frame, keyed by the frame's timestamp text (the Python binding's dict).
// Every box is checked at construction (CheckDetection: ParseError naming the frame and
// the box). Frames without an entry have none.
class InMemoryDetectionSource : public DetectionSource {
 public:
  explicit InMemoryDetectionSource(std::unordered_map<std::string, std::vector<Detection>> by_frame,
                                   const std::vector<std::string>& frames = {});
  std::vector<Detection> DetectionsFor(const std::string& timestamp_text,
                                       const cv::Mat& /*image*/) override;
  std::string Describe() const override { return "boxes in memory"; }
  std::size_t FramesMatched() const override { return matched_; }

 private:
  std::unordered_map<std::string, std::vector<Detection>> by_frame_;
  std::size_t matched_ = 0;
};

// A JSON detection list (ReadJsonDetections), read and checked whole at construction. An
// entry belongs to the frame whose timestamp text is its file_name's file name, or that
// name without its extension ("rgb/1305031102.175304.png" is frame 1305031102.175304, as
// ocg_convert_detections names the EAO files). Throws as ReadJsonDetections; FileError when
// no entry matches a frame (naming an expected and a found name); ParseError when two
// entries name the same frame.
class JsonDetectionSource : public DetectionSource {
 public:
  JsonDetectionSource(const std::string& path, const std::vector<std::string>& frames,
                      const DetectionReadOptions& options = {});
  std::vector<Detection> DetectionsFor(const std::string& timestamp_text,
                                       const cv::Mat& /*image*/) override;
  std::string Describe() const override { return "JSON list '" + path_ + "'"; }
  std::size_t FramesMatched() const override { return by_frame_.size(); }

 private:
  std::string path_;
  std::unordered_map<std::string, std::vector<Detection>> by_frame_;
};

// The detection files at path, their format told by what path is: a folder of EAO text
// files or a JSON list file. frames: the timestamp texts of the frames to process. Throws
// FileError when path is neither, and as the sources' constructors.
std::unique_ptr<DetectionSource> OpenDetectionFiles(const std::string& path,
                                                    const std::vector<std::string>& frames,
                                                    const DetectionReadOptions& options = {});

// The frames detection files name, in time order, when no frame list is given
// (`ocg_slam objects` without --frames): an EAO folder's "<timestamp>.txt" files or a JSON
// list's file names (as JsonDetectionSource matches them). The paths are empty. Throws
// std::invalid_argument naming a file whose name is not a timestamp, FileError as
// OpenDetectionFiles.
std::vector<TimedImage> FramesNamedByDetections(const std::string& path,
                                                const DetectionReadOptions& options = {});

}  // namespace ocg
