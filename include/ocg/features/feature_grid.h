#pragma once
// A grid of cells over the undistorted image for radius queries: which keypoints lie
// within r pixels of a position, on which pyramid levels.

#include <Eigen/Core>
#include <vector>

namespace ocg {

struct PinholeCamera;

// Axis-aligned bounds of the undistorted image (distortion moves the corners).
struct ImageBounds {
  double min_x = 0.0;
  double max_x = 640.0;
  double min_y = 0.0;
  double max_y = 480.0;

  bool Contains(const Eigen::Vector2d& pixel) const {
    return pixel.x() >= min_x && pixel.x() < max_x && pixel.y() >= min_y && pixel.y() < max_y;
  }
};

ImageBounds UndistortedImageBounds(const PinholeCamera& camera);

class FeatureGrid {
 public:
  static constexpr int kDefaultColumns = 64;
  static constexpr int kDefaultRows = 48;

  FeatureGrid() = default;
  // positions and levels are parallel; positions outside bounds are left out.
  FeatureGrid(const std::vector<Eigen::Vector2d>& positions, const std::vector<int>& levels,
              const ImageBounds& bounds, int columns = kDefaultColumns, int rows = kDefaultRows);

  // Indices of the keypoints within radius of (x, y) (square window, as ORB-SLAM2) with a
  // level in [min_level, max_level] (max_level < 0: no upper limit), in ascending order.
  std::vector<int> InArea(double x, double y, double radius, int min_level = 0,
                          int max_level = -1) const;

  const ImageBounds& bounds() const { return bounds_; }
  int columns() const { return columns_; }
  int rows() const { return rows_; }
  // Number of cells holding at least one keypoint.
  int OccupiedCells() const;

 private:
  const std::vector<int>& Cell(int column, int row) const {
    return cells_[static_cast<std::size_t>(row * columns_ + column)];
  }

  ImageBounds bounds_;
  int columns_ = 0;
  int rows_ = 0;
  double cells_per_pixel_x_ = 0.0;
  double cells_per_pixel_y_ = 0.0;
  std::vector<std::vector<int>> cells_;
  std::vector<Eigen::Vector2d> positions_;
  std::vector<int> levels_;
};

}  // namespace ocg
