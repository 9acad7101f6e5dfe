#include "ocg/features/cell_split.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "ocg/features/feature_grid.h"
#include "ocg/features/orb_extractor.h"
#include "ocg/features/scale_pyramid.h"

namespace ocg {
namespace {

// Every length a grid may be laid over, from a tiny pyramid level to a 4000-pixel image,
// one pixel at a time: the rounding faults hide at particular remainders.
TEST(CellSplit, TilesEveryLengthExactlyWithNoEmptyCell) {
  for (const double nominal : {30.0, 7.5, 64.0}) {
    for (int length = 1; length <= 4000; ++length) {
      const CellSplit split = SplitIntoCells(length, nominal);
      ASSERT_GE(split.count, 1);
      ASSERT_LE(split.count, length);
      if (length >= nominal) {
        ASSERT_EQ(split.count, static_cast<int>(length / nominal));
      }
      ASSERT_EQ(split.Start(0), 0);
      ASSERT_EQ(split.Start(split.count), length) << "length " << length;
      for (int i = 0; i < split.count; ++i) {
        ASSERT_GE(split.Size(i), length / split.count) << "length " << length << " cell " << i;
        ASSERT_LE(split.Size(i), length / split.count + 1) << "length " << length << " cell " << i;
        // CellOf is monotonic, so its value at both ends of every cell pins it everywhere.
        ASSERT_EQ(split.CellOf(split.Start(i)), i) << "length " << length;
        ASSERT_EQ(split.CellOf(split.Start(i + 1) - 1), i) << "length " << length;
      }
    }
  }
}

TEST(CellSplit, MapsEveryPixelToTheCellHoldingIt) {
  for (int length = 1; length <= 700; ++length) {
    const CellSplit split = SplitIntoCells(length, 30.0);
    for (int x = 0; x < length; ++x) {
      const int cell = split.CellOf(x);
      ASSERT_GE(x, split.Start(cell)) << "length " << length;
      ASSERT_LT(x, split.Start(cell + 1)) << "length " << length;
    }
  }
}

TEST(CellSplit, RejectsEmptyLengthsAndCellSizes) {
  EXPECT_THROW(SplitIntoCells(0, 30.0), std::invalid_argument);
  EXPECT_THROW(SplitIntoCells(100, 0.0), std::invalid_argument);
  EXPECT_EQ(SplitIntoCells(100, 1e-300).count, 100);  // no int overflow
}

// The FAST cells of every pyramid level of every image from 320 to 4000 pixels wide (and
// high): each cell lies inside the level's detection region, none is empty, and together
// they cover the region. The old layout (floor(w / 30) columns of ceil width) let the last
// cells start past the region on 1920 x 1080 images and crashed in cv::FAST.
TEST(FastCells, CoverEveryLevelOfEveryImageSize) {
  struct PyramidCase {
    int levels;
    double scale_factor;
  };
  for (const PyramidCase& pyramid_case : {PyramidCase{8, 1.2}, PyramidCase{12, 1.1}}) {
    const ScalePyramid pyramid = MakeScalePyramid(pyramid_case.levels, pyramid_case.scale_factor);
    for (int side = 320; side <= 4000; ++side) {
      for (const cv::Size image : {cv::Size(side, 480), cv::Size(640, side)}) {
        const std::vector<cv::Size> levels = PyramidLevelSizes(image, pyramid);
        ASSERT_EQ(static_cast<int>(levels.size()), pyramid_case.levels);
        for (std::size_t level = 0; level < levels.size(); ++level) {
          const std::optional<FastCellLayout> layout = FastCells(levels[level]);
          ASSERT_TRUE(layout.has_value()) << image << " level " << level;
          const cv::Rect level_rect({0, 0}, levels[level]);
          ASSERT_EQ(layout->region & level_rect, layout->region);
          const cv::Rect region_rect({0, 0}, layout->region.size());
          int covered_width = 0;
          for (int column = 0; column < layout->columns.count; ++column) {
            const cv::Rect cell = layout->Cell(column, 0);
            ASSERT_FALSE(cell.empty()) << image << " level " << level << " column " << column;
            ASSERT_EQ(cell.x, covered_width) << image << " level " << level;
            ASSERT_EQ(cell & region_rect, cell) << image << " level " << level;
            covered_width += cell.width;
          }
          ASSERT_EQ(covered_width, layout->region.width) << image << " level " << level;
          int covered_height = 0;
          for (int row = 0; row < layout->rows.count; ++row) {
            const cv::Rect cell = layout->Cell(layout->columns.count - 1, row);
            ASSERT_FALSE(cell.empty()) << image << " level " << level << " row " << row;
            ASSERT_EQ(cell.y, covered_height) << image << " level " << level;
            ASSERT_EQ(cell & region_rect, cell) << image << " level " << level;
            covered_height += cell.height;
          }
          ASSERT_EQ(covered_height, layout->region.height) << image << " level " << level;
        }
      }
    }
  }
}

TEST(FastCells, NoneForALevelTooSmallForACorner) {
  EXPECT_FALSE(FastCells({38, 200}).has_value());
  EXPECT_FALSE(FastCells({200, 38}).has_value());
  const std::optional<FastCellLayout> smallest = FastCells({39, 39});
  ASSERT_TRUE(smallest.has_value());
  EXPECT_EQ(smallest->columns.count, 1);
  EXPECT_EQ(smallest->region.width, 7);
}

// The matching grid over the undistorted image: a keypoint just inside the far edge
// stays in the grid for every image size. Before the cell index was clamped, (x - min) *
// columns / width rounded up to columns for 625 of these sizes and grid layouts (341
// pixels in 48 rows, the first) and the keypoint was dropped.
TEST(FeatureGridCells, KeepPointsJustInsideTheFarEdgeForEverySize) {
  for (int side = 320; side <= 4000; ++side) {
    for (const int cells : {FeatureGrid::kDefaultColumns, FeatureGrid::kDefaultRows, 12}) {
      ImageBounds bounds;
      bounds.max_x = side;
      bounds.max_y = side;
      const double edge = std::nextafter(static_cast<double>(side), 0.0);
      const FeatureGrid grid({{edge, edge}, {0.0, 0.0}, {side, 0.0}}, {0, 0, 0}, bounds, cells,
                             cells);
      ASSERT_EQ(grid.InArea(edge, edge, 1.0), std::vector<int>{0}) << side << " " << cells;
      ASSERT_EQ(grid.InArea(0.0, 0.0, 1.0), std::vector<int>{1});
      // Outside (x == max_x) is still left out.
      ASSERT_TRUE(grid.InArea(side, 0.0, 0.5).empty()) << side;
    }
  }
}

}  // namespace
}  // namespace ocg
