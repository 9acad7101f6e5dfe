#include "ocg/io/sequence.h"

#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <stdexcept>

#include "ocg/core/file_io.h"
#include "ocg/core/options.h"
#include "ocg/core/settings_file.h"
#include "ocg/core/whole_number.h"
#include "ocg/io/text_lines.h"
#include "ocg/io/time_order.h"

namespace ocg {
namespace {

namespace fs = std::filesystem;

std::string JoinPath(const std::string& base, const std::string& relative) {
  return (fs::path(base) / relative).string();
}

// "1403715273262142976" (ns) to seconds, keeping precision by splitting the digits.
double NanosecondsToSeconds(const std::string& text, const std::string& path, int line) {
  const long long nanoseconds = ParseIntegerField(text, "timestamp [ns]", path, line);
  return static_cast<double>(nanoseconds / 1000000000LL) +
         static_cast<double>(nanoseconds % 1000000000LL) * 1e-9;
}

std::string SecondsText(const std::string& nanoseconds_text) {
  if (nanoseconds_text.size() <= 9)
    return "0." + std::string(9 - nanoseconds_text.size(), '0') + nanoseconds_text;
  return nanoseconds_text.substr(0, nanoseconds_text.size() - 9) + "." +
         nanoseconds_text.substr(nanoseconds_text.size() - 9);
}

void ReadEurocSensor(const std::string& path, ImageSequence* sequence) {
  const SettingsFile sensor = SettingsFile::Load(path);
  std::vector<double> intrinsics, distortion, resolution, extrinsics;
  if (!sensor.Read("intrinsics", &intrinsics) || intrinsics.size() != 4) {
    throw SettingsError(path + ": key 'intrinsics' must be a list [fu, fv, cu, cv]");
  }
  if (!sensor.Read("resolution", &resolution) || resolution.size() != 2) {
    throw SettingsError(path + ": key 'resolution' must be a list [width, height]");
  }
  const std::optional<int> width = WholeNumberAs<int>(resolution[0]);
  const std::optional<int> height = WholeNumberAs<int>(resolution[1]);
  if (!width || !height) {
    throw SettingsError(path + ": key 'resolution' must hold two whole numbers of pixels");
  }
  PinholeCamera camera;
  camera.fx = intrinsics[0];
  camera.fy = intrinsics[1];
  camera.cx = intrinsics[2];
  camera.cy = intrinsics[3];
  camera.width = *width;
  camera.height = *height;
  if (sensor.Read("distortion_coefficients", &distortion)) {
    if (distortion.size() < 4) {
      throw SettingsError(path + ": key 'distortion_coefficients' must hold k1 k2 p1 p2");
    }
    camera.k1 = distortion[0];
    camera.k2 = distortion[1];
    camera.p1 = distortion[2];
    camera.p2 = distortion[3];
    if (distortion.size() > 4) camera.k3 = distortion[4];
  }
  std::string model;
  if (sensor.Read("distortion_model", &model) && model != "radial-tangential") {
    throw SettingsError(path + ": distortion_model '" + model +
                        "' is not supported (only radial-tangential)");
  }
  try {
    camera.Check();
  } catch (const OptionError& error) {
    // Name the sensor.yaml key the bad value came from, not the settings key Check knows.
    const std::string& key = error.key();
    const char* source =
        key == "Camera.width" || key == "Camera.height" ? "resolution"
        : key == "Camera.fx" || key == "Camera.fy" || key == "Camera.cx" || key == "Camera.cy"
            ? "intrinsics"
            : "distortion_coefficients";
    throw SettingsError(path + ": key '" + source + "': " + key + " " + error.message());
  }
  sequence->camera = camera;
  if (sensor.Read("T_BS.data", &extrinsics)) {
    if (extrinsics.size() != 16) throw SettingsError(path + ": key 'T_BS.data' needs 16 numbers");
    sequence->T_body_camera = SE3::FromMatrix(
        Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(extrinsics.data()));
  }
}

std::vector<StampedPose> ReadEurocGroundtruth(const std::string& path) {
  std::vector<StampedPose> poses;
  std::vector<int> lines;
  ForEachDataLine(path, true, [&](int line, const std::vector<std::string>& fields) {
    if (fields.size() < 8) {
      ThrowParseError(path, line, "expected at least 8 fields 'timestamp px py pz qw qx qy qz'");
    }
    double values[7];
    for (int i = 0; i < 7; ++i) values[i] = ParseNumberField(fields[i + 1], "pose", path, line);
    StampedPose pose;
    pose.timestamp = NanosecondsToSeconds(fields[0], path, line);
    pose.timestamp_text = SecondsText(fields[0]);
    pose.T_wc = SE3(Eigen::Quaterniond(values[3], values[4], values[5], values[6]),
                    Eigen::Vector3d(values[0], values[1], values[2]));
    poses.push_back(pose);
    lines.push_back(line);
  });
  // Ground truth is reference data: read as the field's tools read it (io/time_order.h).
  return InReferenceOrder(path, poses, lines);
}

}  // namespace

std::vector<TimedImage> ReadTumImageList(const std::string& path, const std::string& base_dir) {
  std::vector<TimedImage> images;
  TimeOrderCheck order(path, "frame");
  ForEachDataLine(path, false, [&](int line, const std::vector<std::string>& fields) {
    if (fields.size() != 2) {
      ThrowParseError(
          path, line,
          "expected 2 fields 'timestamp filename', got " + std::to_string(fields.size()));
    }
    TimedImage image;
    image.timestamp_text = fields[0];
    image.timestamp = ParseNumberField(fields[0], "timestamp", path, line);
    order.Add(image.timestamp, fields[0], line);
    image.path = JoinPath(base_dir, fields[1]);
    images.push_back(std::move(image));
  });
  return images;
}

ImageSequence ReadTumSequence(const std::string& root) {
  const std::string list = JoinPath(root, "rgb.txt");
  if (!fs::exists(list)) {
    // The format is a choice (tum by default): name the one the folder looks like.
    std::string other;
    if (fs::exists(JoinPath(root, "times.txt")) && fs::exists(JoinPath(root, "image_0"))) {
      other =
          "; it holds times.txt and image_0/, a KITTI odometry folder: read it as format "
          "kitti (ocg_slam run --format kitti)";
    } else if (fs::exists(JoinPath(root, "mav0/cam0/data.csv"))) {
      other =
          "; it holds mav0/cam0/data.csv, a EuRoC folder: read it as format euroc "
          "(ocg_slam run --format euroc)";
    }
    throw FileError("'" + root + "' is not a TUM RGB-D sequence folder: '" + list + "' is missing" +
                    other);
  }
  ImageSequence sequence;
  sequence.root = root;
  sequence.list = list;
  sequence.images = ReadTumImageList(list, root);
  const std::string groundtruth = JoinPath(root, "groundtruth.txt");
  if (fs::exists(groundtruth)) sequence.groundtruth = ReadTumTrajectory(groundtruth);
  return sequence;
}

ImageSequence ReadEurocSequence(const std::string& root) {
  const std::string camera_dir = JoinPath(root, "mav0/cam0");
  const std::string list = JoinPath(camera_dir, "data.csv");
  if (!fs::exists(list)) {
    throw FileError("'" + root + "' is not a EuRoC sequence folder: '" + list + "' is missing");
  }
  ImageSequence sequence;
  sequence.root = root;
  sequence.list = list;
  TimeOrderCheck order(list, "frame");
  ForEachDataLine(list, true, [&](int line, const std::vector<std::string>& fields) {
    if (fields.size() != 2) {
      ThrowParseError(list, line, "expected 2 fields 'timestamp [ns],filename'");
    }
    TimedImage image;
    image.timestamp = NanosecondsToSeconds(fields[0], list, line);
    image.timestamp_text = fields[0];
    order.Add(image.timestamp, fields[0], line);
    image.path = JoinPath(camera_dir, "data/" + fields[1]);
    sequence.images.push_back(std::move(image));
  });
  ReadEurocSensor(JoinPath(camera_dir, "sensor.yaml"), &sequence);
  const std::string groundtruth = JoinPath(root, "mav0/state_groundtruth_estimate0/data.csv");
  if (fs::exists(groundtruth)) {
    sequence.groundtruth = ReadEurocGroundtruth(groundtruth);
    if (sequence.T_body_camera) {
      sequence.groundtruth = BodyToCameraPoses(sequence.groundtruth, *sequence.T_body_camera);
    }
  }
  return sequence;
}

namespace {

// calib.txt's "P0: p00 p01 ... p23" (3x4 projection of the left grey camera, row-major).
PinholeCamera ReadKittiCalibration(const std::string& path) {
  std::optional<PinholeCamera> camera;
  ForEachDataLine(path, false, [&](int line, const std::vector<std::string>& fields) {
    if (fields.empty() || fields[0] != "P0:") return;
    if (fields.size() != 13) {
      ThrowParseError(path, line,
                      "P0 must hold the 12 numbers of a 3x4 projection matrix, got " +
                          std::to_string(fields.size() - 1));
    }
    PinholeCamera read;
    read.fx = ParseNumberField(fields[1], "P0 fx", path, line);
    read.cx = ParseNumberField(fields[3], "P0 cx", path, line);
    read.fy = ParseNumberField(fields[6], "P0 fy", path, line);
    read.cy = ParseNumberField(fields[7], "P0 cy", path, line);
    camera = read;
  });
  if (!camera) throw FileError("'" + path + "' has no P0 line (the left grey camera)");
  return *camera;
}

}  // namespace

ImageSequence ReadKittiSequence(const std::string& root) {
  const std::string images = JoinPath(root, "image_0");
  const std::string times = JoinPath(root, "times.txt");
  for (const std::string& needed : {images, times, JoinPath(root, "calib.txt")}) {
    if (!fs::exists(needed)) {
      throw FileError("'" + root + "' is not a KITTI odometry sequence folder: '" + needed +
                      "' is missing");
    }
  }
  ImageSequence sequence;
  sequence.root = root;
  sequence.list = times;
  const KittiTimes frame_times = ReadKittiTimes(times);
  std::size_t image_files = 0;
  for (const auto& entry : fs::directory_iterator(images))
    image_files += entry.path().extension() == ".png" ? 1 : 0;
  if (frame_times.seconds.size() > image_files) {
    throw FileError("'" + times + "' lists " + std::to_string(frame_times.seconds.size()) +
                    " times, but '" + images + "' holds " + std::to_string(image_files) +
                    " PNG images: one time per image");
  }
  for (std::size_t i = 0; i < frame_times.seconds.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "%06zu.png", i);
    sequence.images.push_back(
        {frame_times.texts[i], frame_times.seconds[i], JoinPath(images, name)});
  }
  PinholeCamera camera = ReadKittiCalibration(JoinPath(root, "calib.txt"));
  if (!sequence.images.empty()) {
    const cv::Mat first = cv::imread(sequence.images.front().path, cv::IMREAD_UNCHANGED);
    if (first.empty()) {
      throw FileError("cannot read the first image '" + sequence.images.front().path + "'");
    }
    camera.width = first.cols;
    camera.height = first.rows;
    sequence.camera = camera;
  }
  return sequence;
}

ImageSequence ReadSequence(const std::string& root, const std::string& format) {
  std::string chosen = format;
  if (format == "auto") {
    if (fs::exists(JoinPath(root, "rgb.txt"))) {
      chosen = "tum";
    } else if (fs::exists(JoinPath(root, "mav0/cam0/data.csv"))) {
      chosen = "euroc";
    } else if (fs::exists(JoinPath(root, "times.txt")) && fs::exists(JoinPath(root, "image_0"))) {
      chosen = "kitti";
    } else {
      throw FileError("'" + root +
                      "' is no sequence folder: it holds no rgb.txt (TUM), no "
                      "mav0/cam0/data.csv (EuRoC), no times.txt with image_0/ (KITTI)");
    }
  }
  if (chosen == "tum") return ReadTumSequence(root);
  if (chosen == "euroc") return ReadEurocSequence(root);
  if (chosen == "kitti") return ReadKittiSequence(root);
  throw std::invalid_argument("sequence format '" + format + "': use tum, euroc, kitti or auto");
}

std::vector<StampedPose> BodyToCameraPoses(const std::vector<StampedPose>& body_poses,
                                           const SE3& T_body_camera) {
  std::vector<StampedPose> camera_poses = body_poses;
  for (StampedPose& pose : camera_poses) pose.T_wc = pose.T_wc * T_body_camera;
  return camera_poses;
}

}  // namespace ocg
