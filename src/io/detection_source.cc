#include "ocg/io/detection_source.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <unordered_set>

#include "ocg/core/file_io.h"
#include "ocg/io/text_lines.h"

namespace ocg {
namespace {

namespace fs = std::filesystem;

// The frame a JSON entry's file_name names: its file name when that is a frame's
// timestamp text, else the file name without extension.
std::string FrameOfFileName(const std::string& file_name,
                            const std::unordered_set<std::string>& frames) {
  const fs::path path(file_name);
  const std::string name = path.filename().string();
  if (frames.count(name) > 0) return name;
  return path.stem().string();
}

// A timestamp text as a number; false unless the whole text is one.
bool ParseTimestamp(const std::string& text, double* seconds) {
  if (text.empty()) return false;
  char* end = nullptr;
  *seconds = std::strtod(text.c_str(), &end);
  return end != text.c_str() && *end == '\0';
}

FileError NeitherFolderNorList(const std::string& path) {
  return FileError("detections '" + path +
                   "' is neither a folder of <timestamp>.txt files (EAO format) nor a JSON "
                   "detection list file");
}

}  // namespace

InMemoryDetectionSource::InMemoryDetectionSource(
    std::unordered_map<std::string, std::vector<Detection>> by_frame,
    const std::vector<std::string>& frames)
    : by_frame_(std::move(by_frame)) {
  for (const auto& [frame, detections] : by_frame_) {
    for (std::size_t i = 0; i < detections.size(); ++i)
      CheckDetection(detections[i], "detections of frame " + frame + ": box " + std::to_string(i));
  }
  for (const std::string& frame : frames) matched_ += by_frame_.count(frame);
}

std::vector<Detection> InMemoryDetectionSource::DetectionsFor(const std::string& timestamp_text,
                                                              const cv::Mat& /*image*/) {
  const auto it = by_frame_.find(timestamp_text);
  return it == by_frame_.end() ? std::vector<Detection>() : it->second;
}

JsonDetectionSource::JsonDetectionSource(const std::string& path,
                                         const std::vector<std::string>& frames,
                                         const DetectionReadOptions& options)
    : path_(path) {
  std::vector<DetectionFrame> entries = ReadJsonDetections(path, options);
  const std::unordered_set<std::string> wanted(frames.begin(), frames.end());
  std::unordered_map<std::string, std::string> named_by;  // frame -> the file_name naming it
  for (DetectionFrame& entry : entries) {
    const std::string frame = FrameOfFileName(entry.file_name, wanted);
    const auto [it, fresh] = named_by.emplace(frame, entry.file_name);
    if (!fresh) {
      throw ParseError(path + ": the entries '" + it->second + "' and '" + entry.file_name +
                       "' name the same frame " + frame);
    }
    if (wanted.count(frame) > 0) by_frame_.emplace(frame, std::move(entry.detections));
  }
  if (by_frame_.empty() && !frames.empty()) {
    throw FileError(
        "no entry of the detection list '" + path +
        "' matches a frame: expected file_name entries named by the frames' "
        "timestamps as in the image list, e.g. 'rgb/" +
        frames.front() + ".png', found " + std::to_string(entries.size()) + " entries" +
        (entries.empty() ? std::string() : " such as '" + entries.front().file_name + "'"));
  }
}

std::vector<Detection> JsonDetectionSource::DetectionsFor(const std::string& timestamp_text,
                                                          const cv::Mat& /*image*/) {
  const auto it = by_frame_.find(timestamp_text);
  return it == by_frame_.end() ? std::vector<Detection>() : it->second;
}

std::unique_ptr<DetectionSource> OpenDetectionFiles(const std::string& path,
                                                    const std::vector<std::string>& frames,
                                                    const DetectionReadOptions& options) {
  std::error_code error;
  if (fs::is_directory(path, error))
    return std::make_unique<FolderDetectionSource>(EaoDetectionFolder(path, frames, options), path);
  if (fs::is_regular_file(path, error))
    return std::make_unique<JsonDetectionSource>(path, frames, options);
  throw NeitherFolderNorList(path);
}

std::vector<TimedImage> FramesNamedByDetections(const std::string& path,
                                                const DetectionReadOptions& options) {
  std::vector<TimedImage> frames;
  std::error_code error;
  const auto add = [&frames](const std::string& name, const std::string& what) {
    TimedImage frame;
    if (!ParseTimestamp(name, &frame.timestamp))
      throw std::invalid_argument(what + " (give the frames with --frames)");
    frame.timestamp_text = name;
    frames.push_back(frame);
  };
  if (fs::is_directory(path, error)) {
    for (const auto& entry : fs::directory_iterator(path)) {
      if (entry.path().extension() != ".txt") continue;
      add(entry.path().stem().string(),
          "detection file '" + entry.path().string() + "' is not named <timestamp>.txt");
    }
  } else if (fs::is_regular_file(path, error)) {
    for (const DetectionFrame& entry : ReadJsonDetections(path, options)) {
      const fs::path name(entry.file_name);
      double seconds = 0.0;
      const std::string whole = name.filename().string();
      add(ParseTimestamp(whole, &seconds) ? whole : name.stem().string(),
          path + ": the entry '" + entry.file_name + "' is not named by a timestamp");
    }
  } else {
    throw NeitherFolderNorList(path);
  }
  std::stable_sort(frames.begin(), frames.end(), [](const TimedImage& a, const TimedImage& b) {
    return a.timestamp < b.timestamp;
  });
  return frames;
}

}  // namespace ocg
