#include "ocg/features/feature_grid.h"

#include <algorithm>
#include <cmath>

#include "ocg/core/camera.h"

namespace ocg {

ImageBounds UndistortedImageBounds(const PinholeCamera& camera) {
  ImageBounds bounds;
  if (!camera.HasDistortion()) {
    bounds.max_x = camera.width;
    bounds.max_y = camera.height;
    return bounds;
  }
  const double w = camera.width;
  const double h = camera.height;
  const std::vector<Eigen::Vector2d> corners =
      camera.UndistortPixels({{0.0, 0.0}, {w, 0.0}, {0.0, h}, {w, h}});
  bounds.min_x = std::min(corners[0].x(), corners[2].x());
  bounds.max_x = std::max(corners[1].x(), corners[3].x());
  bounds.min_y = std::min(corners[0].y(), corners[1].y());
  bounds.max_y = std::max(corners[2].y(), corners[3].y());
  return bounds;
}

FeatureGrid::FeatureGrid(const std::vector<Eigen::Vector2d>& positions,
                         const std::vector<int>& levels, const ImageBounds& bounds, int columns,
                         int rows)
    : bounds_(bounds),
      columns_(columns),
      rows_(rows),
      cells_per_pixel_x_(columns / (bounds.max_x - bounds.min_x)),
      cells_per_pixel_y_(rows / (bounds.max_y - bounds.min_y)),
      cells_(static_cast<std::size_t>(columns * rows)),
      positions_(positions),
      levels_(levels) {
  for (std::size_t i = 0; i < positions.size(); ++i) {
    if (!bounds.Contains(positions[i])) continue;
    // Clamped: just below max_x, (x - min_x) * columns / width can round up to columns
    // (341 pixels in 48 rows: y = 340.99999999999994 gives row 48), which would drop a
    // keypoint that lies inside the image.
    const int column = std::min(
        columns - 1,
        static_cast<int>(std::floor((positions[i].x() - bounds.min_x) * cells_per_pixel_x_)));
    const int row = std::min(
        rows - 1,
        static_cast<int>(std::floor((positions[i].y() - bounds.min_y) * cells_per_pixel_y_)));
    cells_[static_cast<std::size_t>(row * columns + column)].push_back(static_cast<int>(i));
  }
}

std::vector<int> FeatureGrid::InArea(double x, double y, double radius, int min_level,
                                     int max_level) const {
  std::vector<int> found;
  if (columns_ == 0) return found;
  const int first_column =
      std::max(0, static_cast<int>(std::floor((x - radius - bounds_.min_x) * cells_per_pixel_x_)));
  const int last_column =
      std::min(columns_ - 1,
               static_cast<int>(std::floor((x + radius - bounds_.min_x) * cells_per_pixel_x_)));
  const int first_row =
      std::max(0, static_cast<int>(std::floor((y - radius - bounds_.min_y) * cells_per_pixel_y_)));
  const int last_row = std::min(
      rows_ - 1, static_cast<int>(std::floor((y + radius - bounds_.min_y) * cells_per_pixel_y_)));
  if (first_column > last_column || first_row > last_row) return found;
  for (int row = first_row; row <= last_row; ++row) {
    for (int column = first_column; column <= last_column; ++column) {
      for (const int index : Cell(column, row)) {
        const int level = levels_[static_cast<std::size_t>(index)];
        if (level < min_level || (max_level >= 0 && level > max_level)) continue;
        const Eigen::Vector2d& p = positions_[static_cast<std::size_t>(index)];
        if (std::abs(p.x() - x) <= radius && std::abs(p.y() - y) <= radius) found.push_back(index);
      }
    }
  }
  std::sort(found.begin(), found.end());
  return found;
}

int FeatureGrid::OccupiedCells() const {
  return static_cast<int>(std::count_if(
      cells_.begin(), cells_.end(), [](const std::vector<int>& cell) { return !cell.empty(); }));
}

}  // namespace ocg
