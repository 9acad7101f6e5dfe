#include "ocg/core/camera.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "ocg/core/options.h"

namespace ocg {
namespace {

// Fixed-point iterations to invert the distortion; converges for the mild distortion
// of real lenses well within these steps.
constexpr int kUndistortIterations = 20;
constexpr double kUndistortTolerance = 1e-12;

}  // namespace

void PinholeCamera::Check() const {
  RequireOption(std::isfinite(fx) && fx > 0, "Camera.fx", "must be positive");
  RequireOption(std::isfinite(fy) && fy > 0, "Camera.fy", "must be positive");
  RequireOption(std::isfinite(cx), "Camera.cx", "must be finite");
  RequireOption(std::isfinite(cy), "Camera.cy", "must be finite");
  RequireOption(width > 0, "Camera.width", "must be positive");
  RequireOption(height > 0, "Camera.height", "must be positive");
  const char* names[] = {"Camera.k1", "Camera.k2", "Camera.k3", "Camera.p1", "Camera.p2"};
  const double values[] = {k1, k2, k3, p1, p2};
  for (int i = 0; i < 5; ++i) RequireOption(std::isfinite(values[i]), names[i], "must be finite");
}

bool PinholeCamera::HasDistortion() const {
  return k1 != 0.0 || k2 != 0.0 || k3 != 0.0 || p1 != 0.0 || p2 != 0.0;
}

Eigen::Vector2d PinholeCamera::Distort(const Eigen::Vector2d& normalized) const {
  Eigen::Vector2d distorted;
  DistortNormalized(*this, normalized.x(), normalized.y(), &distorted.x(), &distorted.y());
  return distorted;
}

Eigen::Vector2d PinholeCamera::Project(const Eigen::Vector3d& point_camera) const {
  Eigen::Vector2d pixel;
  ProjectNormalized(*this, point_camera.x() / point_camera.z(), point_camera.y() / point_camera.z(),
                    &pixel.x(), &pixel.y());
  return pixel;
}

Eigen::Vector2d PinholeCamera::ProjectUndistorted(const Eigen::Vector3d& point_camera) const {
  return {fx * point_camera.x() / point_camera.z() + cx,
          fy * point_camera.y() / point_camera.z() + cy};
}

Eigen::Vector3d PinholeCamera::Unproject(const Eigen::Vector2d& pixel) const {
  const Eigen::Vector2d distorted((pixel.x() - cx) / fx, (pixel.y() - cy) / fy);
  Eigen::Vector2d undistorted = distorted;
  if (HasDistortion()) {
    for (int iteration = 0; iteration < kUndistortIterations; ++iteration) {
      const Eigen::Vector2d residual = Distort(undistorted) - distorted;
      undistorted -= residual;
      if (residual.squaredNorm() < kUndistortTolerance * kUndistortTolerance) break;
    }
  }
  return {undistorted.x(), undistorted.y(), 1.0};
}

Eigen::Vector2d PinholeCamera::UndistortPixel(const Eigen::Vector2d& pixel) const {
  return ProjectUndistorted(Unproject(pixel));
}

std::vector<Eigen::Vector2d> PinholeCamera::UndistortPixels(
    const std::vector<Eigen::Vector2d>& pixels) const {
  std::vector<Eigen::Vector2d> undistorted;
  undistorted.reserve(pixels.size());
  for (const Eigen::Vector2d& pixel : pixels) undistorted.push_back(UndistortPixel(pixel));
  return undistorted;
}

bool PinholeCamera::IsInImage(const Eigen::Vector2d& pixel, double margin) const {
  return pixel.x() >= margin && pixel.y() >= margin && pixel.x() < width - margin &&
         pixel.y() < height - margin;
}

}  // namespace ocg
