#include "ocg/io/detections.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "ocg/core/file_io.h"
#include "ocg/core/whole_number.h"
#include "ocg/io/text_lines.h"

namespace ocg {
namespace {

namespace fs = std::filesystem;

constexpr int kCocoClasses = 80;

Detection ParseEaoLine(const std::vector<std::string>& fields, const std::string& path, int line) {
  if (fields.size() != 6) {
    ThrowParseError(
        path, line,
        "expected 6 fields 'class_id x y w h confidence', got " + std::to_string(fields.size()));
  }
  // The class as text must be an integer ("39", not "39.0"); the rest is DetectionFromRow's.
  const long long class_id = ParseIntegerField(fields[0], "class_id", path, line);
  const double row[6] = {static_cast<double>(class_id),
                         ParseNumberField(fields[1], "x", path, line),
                         ParseNumberField(fields[2], "y", path, line),
                         ParseNumberField(fields[3], "w", path, line),
                         ParseNumberField(fields[4], "h", path, line),
                         ParseNumberField(fields[5], "confidence", path, line)};
  return DetectionFromRow(row, FileLocation(path, line));
}

std::string FormatNumber(double value) {
  char buffer[64];
  if (value == std::round(value) && std::abs(value) < 1e9) {
    std::snprintf(buffer, sizeof(buffer), "%.0f", value);
  } else {
    std::snprintf(buffer, sizeof(buffer), "%.6g", value);
  }
  return buffer;
}

bool WithinUnit(const Detection& detection) {
  auto unit = [](double value) { return value >= 0.0 && value <= 1.0; };
  return unit(detection.x) && unit(detection.y) && unit(detection.width) && unit(detection.height);
}

void WarnNormalized(const std::string& where) {
  spdlog::warn(
      "every box in '{}' lies within 0..1: these look like normalized coordinates (YOLO's "
      "'class cx cy w h'), but detections must be 'class_id x y w h confidence' in pixels, "
      "x y the top-left corner; no object will be found. Convert them: x = (cx - w/2) * "
      "image width, w = w * image width (y and h likewise)",
      where);
}

std::string ByteCount(std::uintmax_t bytes) {
  if (bytes < (1u << 20)) return std::to_string(bytes) + " bytes";
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.1f MiB", static_cast<double>(bytes) / (1 << 20));
  return buffer;
}

// What is at path, for messages: "a directory", "a broken symbolic link", ...
std::string DescribeNonRegular(const fs::path& path) {
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (fs::is_symlink(fs::symlink_status(path, error)) && !fs::exists(status))
    return "a broken symbolic link";
  if (fs::is_directory(status)) return "a directory";
  if (!fs::exists(status)) return "missing";
  return "not a regular file";
}

// Throws FileError unless path is a regular file of at most max_bytes.
void CheckDetectionFile(const fs::path& path, std::uintmax_t max_bytes, const char* limit_what) {
  std::error_code error;
  if (!fs::is_regular_file(path, error)) {
    throw FileError("detection file '" + path.string() + "' is " + DescribeNonRegular(path) +
                    ", not a readable file");
  }
  const std::uintmax_t size = fs::file_size(path, error);
  if (error) {
    throw FileError("cannot read detection file '" + path.string() + "': " + error.message());
  }
  if (size > max_bytes) {
    throw FileError("detection file '" + path.string() + "' is " + ByteCount(size) +
                    ", more than the limit of " + ByteCount(max_bytes) + " " + limit_what +
                    ": far more than any detector writes, so it is not a detection file "
                    "or it is broken");
  }
}

// True when something (a file, a folder, a broken link) is at path.
bool Exists(const fs::path& path) {
  std::error_code error;
  return fs::exists(fs::symlink_status(path, error));
}
}  // namespace

void CheckDetection(const Detection& detection, const std::string& where) {
  auto fail = [&](const std::string& message) { throw ParseError(where + ": " + message); };
  if (detection.class_id < 0 || detection.class_id >= kCocoClasses) {
    fail("class_id must be a COCO-80 index in [0, 79], got " + std::to_string(detection.class_id));
  }
  if (!std::isfinite(detection.x) || !std::isfinite(detection.y)) {
    fail("box corner x y must be finite numbers (pixels), got " + FormatNumber(detection.x) + " " +
         FormatNumber(detection.y));
  }
  if (!(detection.width > 0) || !(detection.height > 0) || !std::isfinite(detection.width) ||
      !std::isfinite(detection.height)) {
    fail("box width and height must be positive, got " + std::to_string(detection.width) + " x " +
         std::to_string(detection.height));
  }
  if (!(detection.confidence >= 0.0 && detection.confidence <= 1.0)) {
    fail("confidence must be in [0, 1], got " + std::to_string(detection.confidence));
  }
}

Detection DetectionFromRow(const double (&row)[6], const std::string& where) {
  // Checked before narrowing: 4294967297 must not wrap to the valid class 1.
  const std::optional<int> class_id = WholeNumberAs<int>(row[0]);
  if (!class_id || *class_id < 0 || *class_id >= kCocoClasses) {
    char given[32];
    std::snprintf(given, sizeof(given), "%.15g", row[0]);  // every digit of 4294967297
    throw ParseError(where + ": class_id must be a COCO-80 index in [0, 79], got " + given);
  }
  Detection detection;
  detection.class_id = *class_id;
  detection.x = row[1];
  detection.y = row[2];
  detection.width = row[3];
  detection.height = row[4];
  detection.confidence = row[5];
  CheckDetection(detection, where);
  return detection;
}

std::vector<Detection> ReadEaoDetectionFile(const std::string& path,
                                            const DetectionReadOptions& options) {
  CheckDetectionFile(path, options.max_file_bytes, "for one image's detections");
  std::vector<Detection> detections;
  try {
    ForEachDataLine(path, false, [&](int line, const std::vector<std::string>& fields) {
      try {
        detections.push_back(ParseEaoLine(fields, path, line));
      } catch (const ParseError& error) {
        if (!options.lenient) throw;
        spdlog::warn("skipping malformed detection: {}", error.what());
      }
    });
  } catch (const ParseError& error) {
    throw ParseError(std::string(error.what()) +
                     " (--lenient skips malformed detection lines with a warning)");
  }
  return detections;
}

std::vector<Detection> ReadEaoDetectionsForImage(const std::string& dir,
                                                 const std::string& timestamp_text,
                                                 const DetectionReadOptions& options) {
  const fs::path path = fs::path(dir) / (timestamp_text + ".txt");
  if (!Exists(path)) return {};
  return ReadEaoDetectionFile(path.string(), options);
}

EaoDetectionFolder::EaoDetectionFolder(const std::string& dir,
                                       const std::vector<std::string>& frames,
                                       const DetectionReadOptions& options) {
  std::error_code error;
  if (!fs::is_directory(dir, error)) {
    throw FileError("detections folder '" + dir + "' does not exist or is not a folder");
  }
  const std::string expected =
      frames.empty() ? std::string("<timestamp>.txt") : "'" + frames.front() + ".txt'";
  std::size_t text_files = 0;
  std::string found_example;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".txt") continue;
    ++text_files;
    const std::string name = entry.path().filename().string();
    if (found_example.empty() || name < found_example) found_example = name;
  }
  if (text_files == 0) {
    throw FileError("detections folder '" + dir +
                    "' holds no .txt file: expected one file per frame named by the frame's "
                    "timestamp as in the image list, e.g. " +
                    expected);
  }
  bool within_unit = true;
  for (const std::string& frame : frames) {
    const fs::path path = fs::path(dir) / (frame + ".txt");
    if (by_frame_.count(frame) > 0 || !Exists(path)) continue;
    std::vector<Detection> detections = ReadEaoDetectionFile(path.string(), options);
    for (const Detection& detection : detections)
      within_unit = within_unit && WithinUnit(detection);
    detections_ += detections.size();
    by_frame_.emplace(frame, std::move(detections));
  }
  if (by_frame_.empty() && !frames.empty()) {
    throw FileError("no detection file in '" + dir + "' matches a frame: expected files named " +
                    "by the frames' timestamps as in the image list, e.g. " + expected +
                    ", found " + std::to_string(text_files) + " .txt file(s) such as '" +
                    found_example + "'");
  }
  looks_normalized_ = detections_ > 0 && within_unit;
  if (looks_normalized_) WarnNormalized(dir);
}

const std::vector<Detection>& EaoDetectionFolder::ForFrame(
    const std::string& timestamp_text) const {
  static const std::vector<Detection> kNone;
  const auto it = by_frame_.find(timestamp_text);
  return it == by_frame_.end() ? kNone : it->second;
}

bool BoxesLookNormalized(const std::vector<DetectionFrame>& frames) {
  bool any = false;
  for (const DetectionFrame& frame : frames) {
    for (const Detection& detection : frame.detections) {
      if (!WithinUnit(detection)) return false;
      any = true;
    }
  }
  return any;
}

std::vector<DetectionFrame> ReadEaoDetectionDir(const std::string& dir,
                                                const DetectionReadOptions& options) {
  std::error_code error;
  if (!fs::is_directory(dir, error)) {
    throw FileError("detections folder '" + dir + "' does not exist");
  }
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() == ".txt") files.push_back(entry.path());
  }
  if (files.empty()) {
    throw FileError("detections folder '" + dir +
                    "' holds no .txt file (expected <timestamp>.txt files, one per image)");
  }
  std::sort(files.begin(), files.end());
  std::vector<DetectionFrame> frames;
  frames.reserve(files.size());
  for (const fs::path& file : files) {
    frames.push_back({file.stem().string(), ReadEaoDetectionFile(file.string(), options)});
  }
  if (BoxesLookNormalized(frames)) WarnNormalized(dir);
  return frames;
}

std::string FormatEaoDetections(const std::vector<Detection>& detections) {
  std::string text;
  char confidence[32];
  for (const Detection& detection : detections) {
    std::snprintf(confidence, sizeof(confidence), "%.6f", detection.confidence);
    text += std::to_string(detection.class_id) + " " + FormatNumber(detection.x) + " " +
            FormatNumber(detection.y) + " " + FormatNumber(detection.width) + " " +
            FormatNumber(detection.height) + " " + confidence + "\n";
  }
  return text;
}

std::vector<Detection> AsStoredInEaoFiles(const std::vector<Detection>& detections) {
  std::vector<Detection> stored;
  stored.reserve(detections.size());
  std::istringstream text(FormatEaoDetections(detections));
  std::string line;
  for (int number = 1; std::getline(text, line); ++number) {
    std::istringstream fields_of(line);
    std::vector<std::string> fields;
    for (std::string field; fields_of >> field;) fields.push_back(field);
    stored.push_back(ParseEaoLine(fields, "(detections as stored)", number));
  }
  return stored;
}

std::vector<DetectionFrame> ReadJsonDetections(const std::string& path,
                                               const DetectionReadOptions& options) {
  CheckDetectionFile(path, options.max_json_bytes, "for a JSON detection list");
  nlohmann::json root;
  {
    std::ifstream stream(path, std::ios::binary);
    if (!stream) throw FileError("cannot open '" + path + "': " + std::strerror(errno));
    try {
      root = nlohmann::json::parse(stream);  // from the stream: no copy of the text
    } catch (const nlohmann::json::exception& error) {
      // parse_error, and out_of_range for a number beyond a double (1e999).
      throw ParseError(path + ": not valid JSON: " + error.what());
    }
  }
  if (!root.is_array()) throw ParseError(path + ": expected a JSON list of images");
  std::vector<DetectionFrame> frames;
  frames.reserve(root.size());
  for (size_t i = 0; i < root.size(); ++i) {
    const std::string where = path + ": image #" + std::to_string(i);
    try {
      const nlohmann::json& image = root[i];
      DetectionFrame frame;
      frame.file_name = image.at("file_name").get<std::string>();
      const nlohmann::json& list = image.at("detections");
      for (size_t j = 0; j < list.size(); ++j) {
        const nlohmann::json& entry = list[j];
        const auto box = entry.at("bbox").get<std::vector<double>>();
        if (box.size() != 4) {
          throw ParseError(where + " detection #" + std::to_string(j) +
                           ": bbox must be [x1, y1, x2, y2]");
        }
        Detection detection;
        const std::optional<int> class_id = JsonWholeNumberAs<int>(entry.at("category_id"));
        if (!class_id) {
          throw ParseError(where + " detection #" + std::to_string(j) +
                           ": category_id must be a whole number, got " +
                           entry.at("category_id").dump());
        }
        detection.class_id = *class_id;
        detection.confidence = entry.at("detection_score").get<double>();
        detection.x = box[0];
        detection.y = box[1];
        detection.width = box[2] - box[0];
        detection.height = box[3] - box[1];
        CheckDetection(detection,
                       where + " ('" + frame.file_name + "') detection #" + std::to_string(j));
        frame.detections.push_back(detection);
      }
      frames.push_back(std::move(frame));
    } catch (const nlohmann::json::exception& error) {
      throw ParseError(where + ": " + error.what());
    }
  }
  if (BoxesLookNormalized(frames)) WarnNormalized(path);
  return frames;
}

std::string FormatJsonDetections(const std::vector<DetectionFrame>& frames) {
  nlohmann::json root = nlohmann::json::array();
  for (const DetectionFrame& frame : frames) {
    nlohmann::json list = nlohmann::json::array();
    for (const Detection& detection : frame.detections) {
      list.push_back({{"category_id", detection.class_id},
                      {"detection_score", detection.confidence},
                      {"bbox",
                       {detection.x, detection.y, detection.x + detection.width,
                        detection.y + detection.height}}});
    }
    root.push_back({{"file_name", frame.file_name}, {"detections", list}});
  }
  return root.dump(1) + "\n";
}

}  // namespace ocg
