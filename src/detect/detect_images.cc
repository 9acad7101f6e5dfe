#include "ocg/detect/detect_images.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <set>

#include "ocg/core/cpu_time.h"
#include "ocg/core/file_io.h"

namespace ocg {
namespace {

namespace fs = std::filesystem;

bool IsImageFile(const fs::path& path) {
  static const std::set<std::string> kExtensions = {".png", ".jpg", ".jpeg",
                                                    ".bmp", ".ppm", ".pgm"};
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return kExtensions.count(extension) > 0;
}

}  // namespace

std::vector<TimedImage> ListImagesToDetect(const std::string& path) {
  std::error_code error;
  if (fs::is_regular_file(path, error)) {
    return ReadTumImageList(path, fs::path(path).parent_path().string());
  }
  if (!fs::is_directory(path, error)) {
    throw FileError("'" + path +
                    "' is neither a frame list (rgb.txt) nor a folder of images or a TUM "
                    "sequence folder");
  }
  const fs::path list = fs::path(path) / "rgb.txt";
  if (fs::is_regular_file(list, error)) return ReadTumImageList(list.string(), path);
  std::vector<fs::path> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(path)) {
    if (entry.is_regular_file() && IsImageFile(entry.path())) files.push_back(entry.path());
  }
  if (files.empty()) {
    throw FileError("'" + path +
                    "' holds no rgb.txt and no image (.png .jpg .jpeg .bmp .ppm .pgm)");
  }
  std::sort(files.begin(), files.end());
  std::vector<TimedImage> images;
  for (const fs::path& file : files) {
    TimedImage image;
    image.timestamp_text = file.stem().string();
    image.path = file.string();
    images.push_back(image);
  }
  return images;
}

DetectRunSummary DetectImagesToFolder(DetectionModel& model, const std::vector<TimedImage>& images,
                                      const std::string& out_dir, bool write_json,
                                      const std::function<void(std::size_t)>& progress) {
  // Every image must be there before the first is processed: a missing file fails now,
  // not after the rest of the sequence.
  for (const TimedImage& timed : images) RequireRegularFile(timed.path);
  CheckWritableFolder(out_dir);
  DetectRunSummary summary;
  std::vector<DetectionFrame> frames;
  for (const TimedImage& timed : images) {
    const cv::Mat image = cv::imread(timed.path, cv::IMREAD_UNCHANGED);
    if (image.empty()) {
      throw FileError("cannot read the image '" + timed.path + "' (missing or not an image)");
    }
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = ProcessCpuSeconds();
    std::vector<Detection> detections = model.Detect(image);
    summary.cpu_seconds += ProcessCpuSeconds() - cpu_start;
    summary.seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    WriteFileAtomically((fs::path(out_dir) / (timed.timestamp_text + ".txt")).string(),
                        FormatEaoDetections(detections));
    ++summary.images;
    summary.boxes += detections.size();
    for (const Detection& d : detections) ++summary.boxes_per_class[d.class_id];
    if (write_json) frames.push_back({timed.path, std::move(detections)});
    if (progress) progress(summary.images);
  }
  if (write_json) {
    WriteFileAtomically((fs::path(out_dir) / "detections.json").string(),
                        FormatJsonDetections(frames));
  }
  return summary;
}

}  // namespace ocg
