#pragma once
// Pinhole camera with OpenCV's radial-tangential (plumb bob) distortion:
// k1, k2, k3 radial and p1, p2 tangential, applied to normalized coordinates.

#include <Eigen/Core>
#include <string>
#include <vector>

namespace ocg {

// Defaults: the nominal 640x480 camera of the TUM RGB-D benchmark (fx = fy = 525), so
// that a settings file without Camera.* keys is still a valid camera.
struct PinholeCamera {
  double fx = 525.0;  // focal length in pixels
  double fy = 525.0;
  double cx = 319.5;  // principal point in pixels
  double cy = 239.5;
  double k1 = 0.0;  // radial distortion
  double k2 = 0.0;
  double k3 = 0.0;
  double p1 = 0.0;  // tangential distortion
  double p2 = 0.0;
  int width = 640;  // image size in pixels
  int height = 480;

  // Throws std::invalid_argument naming the field when the model is impossible.
  void Check() const;
  bool HasDistortion() const;

  // Pixel of a point in camera coordinates (z > 0 expected), with distortion.
  Eigen::Vector2d Project(const Eigen::Vector3d& point_camera) const;
  // Pixel of a point in camera coordinates, ignoring distortion.
  Eigen::Vector2d ProjectUndistorted(const Eigen::Vector3d& point_camera) const;
  // Bearing (x, y, 1) in normalized coordinates of a distorted pixel.
  Eigen::Vector3d Unproject(const Eigen::Vector2d& pixel) const;
  // Pixel position the distorted pixel would have in an ideal pinhole camera.
  Eigen::Vector2d UndistortPixel(const Eigen::Vector2d& pixel) const;
  std::vector<Eigen::Vector2d> UndistortPixels(const std::vector<Eigen::Vector2d>& pixels) const;
  // Normalized coordinates after distortion.
  Eigen::Vector2d Distort(const Eigen::Vector2d& normalized) const;
  // True when the pixel lies inside the image shrunk by margin pixels on every side.
  bool IsInImage(const Eigen::Vector2d& pixel, double margin = 0.0) const;
};

}  // namespace ocg
