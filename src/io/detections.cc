#include "ocg/io/detections.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>

#include "ocg/core/file_io.h"
#include "ocg/core/whole_number.h"
#include "ocg/io/text_lines.h"

namespace ocg {
namespace {

namespace fs = std::filesystem;

constexpr int kCocoClasses = 80;

// Throws ParseError with what is wrong with the detection, if anything.
void ValidateDetection(const Detection& detection, const std::string& where) {
  auto fail = [&](const std::string& message) { throw ParseError(where + ": " + message); };
  if (detection.class_id < 0 || detection.class_id >= kCocoClasses) {
    fail("class_id must be a COCO-80 index in [0, 79], got " + std::to_string(detection.class_id));
  }
  if (!(detection.width > 0) || !(detection.height > 0)) {
    fail("box width and height must be positive, got " + std::to_string(detection.width) + " x " +
         std::to_string(detection.height));
  }
  if (!(detection.confidence >= 0.0 && detection.confidence <= 1.0)) {
    fail("confidence must be in [0, 1], got " + std::to_string(detection.confidence));
  }
}

Detection ParseEaoLine(const std::vector<std::string>& fields, const std::string& path, int line) {
  if (fields.size() != 6) {
    ThrowParseError(
        path, line,
        "expected 6 fields 'class_id x y w h confidence', got " + std::to_string(fields.size()));
  }
  Detection detection;
  const long long class_id = ParseIntegerField(fields[0], "class_id", path, line);
  // Checked before narrowing: 4294967297 must not wrap to the valid class 1.
  if (class_id < 0 || class_id >= kCocoClasses) {
    ThrowParseError(path, line, "class_id must be a COCO-80 index in [0, 79], got " + fields[0]);
  }
  detection.class_id = static_cast<int>(class_id);
  detection.x = ParseNumberField(fields[1], "x", path, line);
  detection.y = ParseNumberField(fields[2], "y", path, line);
  detection.width = ParseNumberField(fields[3], "w", path, line);
  detection.height = ParseNumberField(fields[4], "h", path, line);
  detection.confidence = ParseNumberField(fields[5], "confidence", path, line);
  ValidateDetection(detection, FileLocation(path, line));
  return detection;
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

}  // namespace

std::vector<Detection> ReadEaoDetectionFile(const std::string& path,
                                            const DetectionReadOptions& options) {
  std::vector<Detection> detections;
  ForEachDataLine(path, false, [&](int line, const std::vector<std::string>& fields) {
    try {
      detections.push_back(ParseEaoLine(fields, path, line));
    } catch (const ParseError& error) {
      if (!options.lenient) throw;
      spdlog::warn("skipping malformed detection: {}", error.what());
    }
  });
  return detections;
}

std::vector<Detection> ReadEaoDetectionsForImage(const std::string& dir,
                                                 const std::string& timestamp_text,
                                                 const DetectionReadOptions& options) {
  const fs::path path = fs::path(dir) / (timestamp_text + ".txt");
  std::error_code error;
  if (!fs::exists(path, error)) return {};
  return ReadEaoDetectionFile(path.string(), options);
}

std::vector<DetectionFrame> ReadEaoDetectionDir(const std::string& dir,
                                                const DetectionReadOptions& options) {
  std::error_code error;
  if (!fs::is_directory(dir, error)) {
    throw FileError("detections folder '" + dir + "' does not exist");
  }
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.is_regular_file() && entry.path().extension() == ".txt")
      files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  std::vector<DetectionFrame> frames;
  frames.reserve(files.size());
  for (const fs::path& file : files) {
    frames.push_back({file.stem().string(), ReadEaoDetectionFile(file.string(), options)});
  }
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

std::vector<DetectionFrame> ReadJsonDetections(const std::string& path) {
  nlohmann::json root;
  try {
    root = nlohmann::json::parse(ReadTextFile(path));
  } catch (const nlohmann::json::exception& error) {
    // parse_error, and out_of_range for a number beyond a double (1e999).
    throw ParseError(path + ": not valid JSON: " + error.what());
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
        ValidateDetection(detection,
                          where + " ('" + frame.file_name + "') detection #" + std::to_string(j));
        frame.detections.push_back(detection);
      }
      frames.push_back(std::move(frame));
    } catch (const nlohmann::json::exception& error) {
      throw ParseError(where + ": " + error.what());
    }
  }
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
