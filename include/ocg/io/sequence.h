#pragma once
// Image sequences on disk: TUM RGB-D, EuRoC MAV and KITTI odometry folders.

#include <optional>
#include <string>
#include <vector>

#include "ocg/core/camera.h"
#include "ocg/core/lie.h"
#include "ocg/io/trajectory.h"

namespace ocg {

struct TimedImage {
  std::string timestamp_text;  // exactly as in the list, used to find detection files
  double timestamp = 0.0;      // seconds
  std::string path;            // image file, sequence folder prepended
};

struct ImageSequence {
  std::string root;
  std::string list;  // the frame list read: root/rgb.txt or root/mav0/cam0/data.csv
  std::vector<TimedImage> images;
  std::vector<StampedPose> groundtruth;  // camera poses T_wc; empty when not provided
  // EuRoC only: the calibration from sensor.yaml and the body-from-camera transform.
  std::optional<PinholeCamera> camera;
  std::optional<SE3> T_body_camera;
};

// "timestamp path" lines (TUM rgb.txt). Paths are made relative to base_dir.
// Frame lists must list frames in strictly increasing time (io/time_order.h): a frame out
// of order or a repeated time throws ParseError naming both lines. Throws FileError when
// path is not a readable regular file.
std::vector<TimedImage> ReadTumImageList(const std::string& path, const std::string& base_dir);

// A TUM RGB-D folder: rgb.txt, optional groundtruth.txt (camera-to-world).
ImageSequence ReadTumSequence(const std::string& root);

// A EuRoC MAV folder (the one holding mav0/): mav0/cam0/data.csv, mav0/cam0/sensor.yaml
// (intrinsics, radial-tangential distortion, resolution, T_BS), and the ground truth of
// mav0/state_groundtruth_estimate0/data.csv when present, turned into camera poses
// T_wc = T_wb * T_BS. Timestamps in nanoseconds become seconds; data.csv and the ground
// truth must increase strictly in time, as rgb.txt.
// Throws FileError when a file is missing, ParseError naming file and line for a bad list
// line (or a time out of order), SettingsError naming sensor.yaml and the key for a bad or
// impossible calibration.
ImageSequence ReadEurocSequence(const std::string& root);

// A KITTI odometry sequence folder (sequences/NN/): image_0/NNNNNN.png (the left grey
// camera), times.txt (one time in seconds per image, strictly increasing; ReadKittiTimes),
// calib.txt (its P0 line gives fx, fy, cx, cy; the image size is the first image's). The
// frames' timestamp texts are the times as "%.6f" (detection files: "<text>.txt"). No
// ground truth: KITTI keeps it in poses/NN.txt, outside the folder.
// Throws FileError when image_0/, times.txt or calib.txt is missing, when times.txt lists
// more times than image_0/ holds images or the first image cannot be read; ParseError
// naming file and line for a bad time or a bad P0 line.
ImageSequence ReadKittiSequence(const std::string& root);

// format "tum", "euroc" or "kitti"; "auto": the one whose files the folder holds (rgb.txt,
// mav0/cam0/data.csv, times.txt with image_0/). Throws std::invalid_argument for another
// format, FileError when "auto" finds none (naming what it looked for).
ImageSequence ReadSequence(const std::string& root, const std::string& format);

// Camera poses from body poses: T_wc = T_wb * T_body_camera.
std::vector<StampedPose> BodyToCameraPoses(const std::vector<StampedPose>& body_poses,
                                           const SE3& T_body_camera);

}  // namespace ocg
