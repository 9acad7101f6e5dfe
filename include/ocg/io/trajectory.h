#pragma once
// TUM trajectory files: "timestamp tx ty tz qx qy qz qw" per line, the pose of the
// camera in the world (T_wc), '#' comments.

#include <optional>
#include <string>
#include <vector>

#include "ocg/core/lie.h"

namespace ocg {

struct StampedPose {
  double timestamp = 0.0;
  std::string timestamp_text;  // exactly as in the file; empty for computed poses
  SE3 T_wc;
};

// Throws FileError when missing, ParseError naming file and line when malformed or when
// the poses are not in strictly increasing time (naming the earlier line too).
std::vector<StampedPose> ReadTumTrajectory(const std::string& path);
// Writes atomically; timestamps as their text when known, else with 6 decimals.
void WriteTumTrajectory(const std::string& path, const std::vector<StampedPose>& poses);
std::string FormatTumTrajectory(const std::vector<StampedPose>& poses);

// T_cw (world to camera) at a time, from poses sorted by timestamp: interpolated (rotation slerp,
// translation linear) between the two around it when they are at most max_gap seconds
// apart, else the nearest one if within tolerance seconds; none otherwise.
std::optional<SE3> PoseAtTime(const std::vector<StampedPose>& poses, double timestamp,
                              double max_gap = 0.1, double tolerance = 0.02);

}  // namespace ocg
