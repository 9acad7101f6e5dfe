#include "ocg/io/trajectory.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>

#include "ocg/core/file_io.h"
#include "ocg/io/text_lines.h"
#include "ocg/io/time_order.h"

namespace ocg {

std::vector<StampedPose> InReferenceOrder(const std::string& path,
                                          const std::vector<StampedPose>& poses,
                                          const std::vector<int>& lines) {
  std::vector<TimedLine> times;
  times.reserve(poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i)
    times.push_back({poses[i].timestamp, poses[i].timestamp_text, lines[i]});
  std::vector<StampedPose> ordered;
  const std::vector<std::size_t> kept = OrderReferenceTimes(path, "pose", times);
  ordered.reserve(kept.size());
  for (const std::size_t index : kept) ordered.push_back(poses[index]);
  return ordered;
}

std::vector<StampedPose> ReadTumTrajectory(const std::string& path) {
  std::vector<StampedPose> poses;
  std::vector<int> lines;
  // Commas and tabs separate fields as in TUM's associate.py.
  ForEachDataLine(path, true, [&](int line, const std::vector<std::string>& fields) {
    if (fields.size() != 8) {
      ThrowParseError(
          path, line,
          "expected 8 fields 'timestamp tx ty tz qx qy qz qw', got " +
              std::to_string(fields.size()) +
              (fields.size() == 12 ? " (12 numbers without a time are a KITTI pose line: "
                                     "'ocg_eval convert --to tum --times "
                                     "times.txt' gives TUM lines)"
                                   : ""));
    }
    static const char* const kNames[] = {"timestamp", "tx", "ty", "tz", "qx", "qy", "qz", "qw"};
    double values[8];
    for (int i = 0; i < 8; ++i) values[i] = ParseNumberField(fields[i], kNames[i], path, line);
    const Eigen::Quaterniond rotation(values[7], values[4], values[5], values[6]);
    const double norm = rotation.norm();
    if (std::abs(norm - 1.0) > 1e-2) {
      ThrowParseError(
          path, line,
          "quaternion (qx qy qz qw) must have unit length, has " + std::to_string(norm));
    }
    StampedPose pose;
    pose.timestamp = values[0];
    pose.timestamp_text = fields[0];
    pose.T_wc = SE3(rotation, Eigen::Vector3d(values[1], values[2], values[3]));
    poses.push_back(pose);
    lines.push_back(line);
  });
  return InReferenceOrder(path, poses, lines);
}

std::string FormatTumTrajectory(const std::vector<StampedPose>& poses) {
  std::string text;
  char buffer[256];
  for (const StampedPose& pose : poses) {
    const Eigen::Vector3d& t = pose.T_wc.translation();
    const Eigen::Quaterniond& q = pose.T_wc.quaternion();
    const std::string stamp =
        pose.timestamp_text.empty()
            ? (std::snprintf(buffer, sizeof(buffer), "%.6f", pose.timestamp), std::string(buffer))
            : pose.timestamp_text;
    std::snprintf(buffer, sizeof(buffer), " %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", t.x(), t.y(),
                  t.z(), q.x(), q.y(), q.z(), q.w());
    text += stamp;
    text += buffer;
  }
  return text;
}

void WriteTumTrajectory(const std::string& path, const std::vector<StampedPose>& poses) {
  WriteFileAtomically(path, FormatTumTrajectory(poses));
}

std::vector<StampedPose> ReadKittiTrajectory(const std::string& path) {
  std::vector<StampedPose> poses;
  ForEachDataLine(path, false, [&](int line, const std::vector<std::string>& fields) {
    if (fields.size() != 12) {
      ThrowParseError(path, line,
                      "expected the 12 numbers of a KITTI pose (3x4 [R | t], row-major), got " +
                          std::to_string(fields.size()) + " fields");
    }
    Eigen::Matrix4d matrix = Eigen::Matrix4d::Identity();
    for (int i = 0; i < 12; ++i) {
      matrix(i / 4, i % 4) =
          ParseNumberField(fields[i], "pose entry " + std::to_string(i + 1), path, line);
    }
    const Eigen::Matrix3d rotation = matrix.topLeftCorner<3, 3>();
    const double error = (rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).norm();
    if (!(error <= 1e-3) || rotation.determinant() < 0) {
      ThrowParseError(path, line,
                      "the 3x3 part is not a rotation (|R^T R - I| = " + std::to_string(error) +
                          ", det " + std::to_string(rotation.determinant()) + ")");
    }
    StampedPose pose;
    pose.timestamp = static_cast<double>(poses.size());
    pose.timestamp_text = std::to_string(poses.size());
    pose.T_wc = SE3::FromMatrix(matrix);
    poses.push_back(pose);
  });
  return poses;
}

std::string FormatKittiTrajectory(const std::vector<StampedPose>& poses) {
  std::string text;
  char buffer[64];
  for (const StampedPose& pose : poses) {
    const Eigen::Matrix4d matrix = pose.T_wc.Matrix();
    for (int i = 0; i < 12; ++i) {
      std::snprintf(buffer, sizeof(buffer), i == 0 ? "%.9g" : " %.9g", matrix(i / 4, i % 4));
      text += buffer;
    }
    text += '\n';
  }
  return text;
}

void WriteKittiTrajectory(const std::string& path, const std::vector<StampedPose>& poses) {
  WriteFileAtomically(path, FormatKittiTrajectory(poses));
}

TrajectoryFormat DetectTrajectoryFormat(const std::string& path) {
  std::optional<TrajectoryFormat> format;
  try {
    ForEachDataLine(path, true, [&](int, const std::vector<std::string>& fields) {
      format = fields.size() == 12 ? TrajectoryFormat::kKitti : TrajectoryFormat::kTum;
      throw std::out_of_range("first data line read");  // stop reading
    });
  } catch (const std::out_of_range&) {
  }
  if (!format) {
    throw ParseError(path + ": holds no pose (only comments or blank lines)");
  }
  return *format;
}

KittiTimes ReadKittiTimes(const std::string& path) {
  KittiTimes times;
  TimeOrderCheck order(path, "frame");
  ForEachDataLine(path, false, [&](int line, const std::vector<std::string>& fields) {
    if (fields.size() != 1) {
      ThrowParseError(path, line,
                      "expected one time in seconds per line (KITTI times.txt), got " +
                          std::to_string(fields.size()) + " fields");
    }
    const double seconds = ParseNumberField(fields[0], "time", path, line);
    order.Add(seconds, fields[0], line);
    char text[64];
    std::snprintf(text, sizeof(text), "%.6f", seconds);
    times.seconds.push_back(seconds);
    times.texts.push_back(text);
  });
  return times;
}

std::vector<StampedPose> ReadTrajectory(const std::string& path, const std::string& times_path) {
  if (DetectTrajectoryFormat(path) == TrajectoryFormat::kTum) return ReadTumTrajectory(path);
  std::vector<StampedPose> poses = ReadKittiTrajectory(path);
  if (times_path.empty()) return poses;
  const KittiTimes times = ReadKittiTimes(times_path);
  if (times.seconds.size() != poses.size()) {
    throw ParseError(path + ": " + std::to_string(poses.size()) + " KITTI poses, but '" +
                     times_path + "' lists " + std::to_string(times.seconds.size()) +
                     " times: give the times of the same frames (one per pose line)");
  }
  for (std::size_t i = 0; i < poses.size(); ++i) {
    poses[i].timestamp = times.seconds[i];
    poses[i].timestamp_text = times.texts[i];
  }
  return poses;
}

std::optional<SE3> PoseAtTime(const std::vector<StampedPose>& poses, double timestamp,
                              double max_gap, double tolerance) {
  const auto after =
      std::lower_bound(poses.begin(), poses.end(), timestamp,
                       [](const StampedPose& pose, double time) { return pose.timestamp < time; });
  const StampedPose* next = after != poses.end() ? &*after : nullptr;
  const StampedPose* previous = after != poses.begin() ? &*std::prev(after) : nullptr;
  if (next != nullptr && previous != nullptr && next->timestamp - previous->timestamp <= max_gap) {
    const double span = next->timestamp - previous->timestamp;
    const double share = span > 0 ? (timestamp - previous->timestamp) / span : 0.0;
    const Eigen::Quaterniond rotation =
        previous->T_wc.quaternion().slerp(share, next->T_wc.quaternion());
    const Eigen::Vector3d translation =
        (1.0 - share) * previous->T_wc.translation() + share * next->T_wc.translation();
    return SE3(rotation, translation).Inverse();
  }
  const StampedPose* nearest = previous;
  if (next != nullptr &&
      (nearest == nullptr || next->timestamp - timestamp < timestamp - nearest->timestamp)) {
    nearest = next;
  }
  if (nearest != nullptr && std::abs(nearest->timestamp - timestamp) <= tolerance) {
    return nearest->T_wc.Inverse();
  }
  return std::nullopt;
}

}  // namespace ocg
