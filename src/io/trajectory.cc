#include "ocg/io/trajectory.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "ocg/core/file_io.h"
#include "ocg/io/text_lines.h"
#include "ocg/io/time_order.h"

namespace ocg {

std::vector<StampedPose> ReadTumTrajectory(const std::string& path) {
  std::vector<StampedPose> poses;
  TimeOrderCheck order(path, "pose");
  ForEachDataLine(path, false, [&](int line, const std::vector<std::string>& fields) {
    if (fields.size() != 8) {
      ThrowParseError(path, line,
                      "expected 8 fields 'timestamp tx ty tz qx qy qz qw', got " +
                          std::to_string(fields.size()));
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
    order.Add(values[0], fields[0], line);
    pose.timestamp = values[0];
    pose.timestamp_text = fields[0];
    pose.T_wc = SE3(rotation, Eigen::Vector3d(values[1], values[2], values[3]));
    poses.push_back(pose);
  });
  return poses;
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
