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

// The camera's distortion model, written once: normalized coordinates (x, y) = (X/Z, Y/Z)
// to distorted ones (PinholeCamera::Distort), and to the pixel (PinholeCamera::Project).
// Templated for automatic derivatives (Ceres Jets); T = double gives those methods' values.
template <typename T>
void DistortNormalized(const PinholeCamera& camera, const T& x, const T& y, T* x_distorted,
                       T* y_distorted) {
  const T r2 = x * x + y * y;
  const T radial = 1.0 + r2 * (camera.k1 + r2 * (camera.k2 + r2 * camera.k3));
  *x_distorted = x * radial + 2.0 * camera.p1 * x * y + camera.p2 * (r2 + 2.0 * x * x);
  *y_distorted = y * radial + camera.p1 * (r2 + 2.0 * y * y) + 2.0 * camera.p2 * x * y;
}
template <typename T>
void ProjectNormalized(const PinholeCamera& camera, const T& x, const T& y, T* u, T* v) {
  T x_distorted, y_distorted;
  DistortNormalized(camera, x, y, &x_distorted, &y_distorted);
  *u = camera.fx * x_distorted + camera.cx;
  *v = camera.fy * y_distorted + camera.cy;
}

}  // namespace ocg
