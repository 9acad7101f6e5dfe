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

// Reference poses (ground truth, a trajectory to evaluate or to map along), read as TUM's
// associate.py and evo read them: '#' comments, fields separated by spaces, tabs or
// commas; lines in any time order (sorted, with a warning); a time listed twice keeps its
// first pose (with a warning naming the lines and the count; io/time_order.h). Returned
// in strictly increasing time.
// Throws FileError when missing, ParseError naming file and line when a line is malformed
// (not 8 numbers, a quaternion not of unit length).
std::vector<StampedPose> ReadTumTrajectory(const std::string& path);
// Poses of a reference file in file order, lines[i] the line of poses[i]: sorted and
// without repeated times as ReadTumTrajectory's (for readers of other formats).
std::vector<StampedPose> InReferenceOrder(const std::string& path,
                                          const std::vector<StampedPose>& poses,
                                          const std::vector<int>& lines);
// Writes atomically; timestamps as their text when known, else with 6 decimals.
void WriteTumTrajectory(const std::string& path, const std::vector<StampedPose>& poses);
std::string FormatTumTrajectory(const std::vector<StampedPose>& poses);

// KITTI odometry poses (what `evo_ape kitti` and the KITTI devkit read): one line per
// frame, the 12 numbers of the 3x4 matrix [R | t] of T_wc (camera to world) row-major, no
// time; the frames' times are the sequence's times.txt.
//
// ReadKittiTrajectory: the poses in file order, each with its row index as time (0, 1, 2,
// ...; text "0", "1", ...), so that two KITTI files pair row by row as evo pairs them.
// Throws FileError when missing, ParseError naming file and line when a line is not 12
// numbers or its 3x3 part is not a rotation (R^T R off the identity by more than 1e-3).
std::vector<StampedPose> ReadKittiTrajectory(const std::string& path);
// One line per pose, in the order given (times are dropped), %.9g; atomically.
std::string FormatKittiTrajectory(const std::vector<StampedPose>& poses);
void WriteKittiTrajectory(const std::string& path, const std::vector<StampedPose>& poses);

enum class TrajectoryFormat { kTum, kKitti };
// By content: KITTI when the first data line holds 12 fields (a TUM line holds 8). Throws
// FileError when missing, ParseError when the file holds no data line.
TrajectoryFormat DetectTrajectoryFormat(const std::string& path);
// Either format, as detected: KITTI poses take the times of times_path (a KITTI times.txt,
// one time per frame) when given, row i the i-th time, else their row indices; the two
// files must then hold as many lines (else ParseError naming both counts).
std::vector<StampedPose> ReadTrajectory(const std::string& path,
                                        const std::string& times_path = "");

// KITTI times.txt: one time in seconds per line (e.g. "1.038752e-01"), strictly increasing
// (the frames of a run: io/time_order.h). Texts are "%.6f" of the values (KITTI gives 7
// significant digits), as the frames' timestamps are written in trajectories.
struct KittiTimes {
  std::vector<double> seconds;
  std::vector<std::string> texts;
};
KittiTimes ReadKittiTimes(const std::string& path);

// T_cw (world to camera) at a time, from poses sorted by timestamp: interpolated (rotation slerp,
// translation linear) between the two around it when they are at most max_gap seconds
// apart, else the nearest one if within tolerance seconds; none otherwise.
std::optional<SE3> PoseAtTime(const std::vector<StampedPose>& poses, double timestamp,
                              double max_gap = 0.1, double tolerance = 0.02);

}  // namespace ocg
