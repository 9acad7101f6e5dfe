#include "ocg/core/convex_hull.h"

#include <gtest/gtest.h>

namespace ocg {
namespace {

TEST(ConvexHull, SquareWithInnerAndEdgePointsCounterClockwise) {
  const std::vector<Eigen::Vector2d> hull =
      ConvexHull({{1, 1}, {0, 0}, {2, 0}, {0.5, 0.5}, {2, 2}, {1, 0}, {0, 2}, {0, 0}});
  const std::vector<Eigen::Vector2d> expected = {{0, 0}, {2, 0}, {2, 2}, {0, 2}};
  EXPECT_EQ(hull, expected) << "inner, collinear and repeated points are left out";
  for (std::size_t i = 0; i < hull.size(); ++i) {
    EXPECT_GT(Turn(hull[i], hull[(i + 1) % hull.size()], hull[(i + 2) % hull.size()]), 0.0);
  }
}

TEST(ConvexHull, PointsOnALineGiveItsEnds) {
  const std::vector<Eigen::Vector2d> ends = {{0, 0}, {3, 3}};
  EXPECT_EQ(ConvexHull({{1, 1}, {3, 3}, {0, 0}, {2, 2}}), ends);
}

}  // namespace
}  // namespace ocg
