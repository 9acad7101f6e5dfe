// Square tiles over wide images, and the merge of their detections.

#include "ocg/detect/tiling.h"

#include <gtest/gtest.h>

#include "boxes.h"

namespace ocg {
namespace {

using testing::Box;

TEST(SquareTiles, CoverAKittiFrameWithTheOverlapAsked) {
  const cv::Size kitti(1226, 370);
  TilingOptions options;
  const std::vector<cv::Rect> tiles = SquareTiles(kitti, options);
  ASSERT_GE(tiles.size(), 4u);
  EXPECT_EQ(tiles.front().x, 0);
  EXPECT_EQ(tiles.back().br().x, kitti.width);
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    EXPECT_EQ(tiles[i].width, 370);
    EXPECT_EQ(tiles[i].height, 370);
    EXPECT_EQ(tiles[i].y, 0);
    if (i > 0) {
      EXPECT_GE((tiles[i - 1] & tiles[i]).width, 0.25 * 370) << "tile " << i;
    }
  }
  // One tile fewer would leave less than the overlap between neighbours.
  const double step_with_one_fewer = (1226.0 - 370.0) / (tiles.size() - 2);
  EXPECT_GT(370 - step_with_one_fewer, 0.0);
  EXPECT_LT(370 - step_with_one_fewer, 0.25 * 370);
}

TEST(SquareTiles, NoneForImagesCloseToSquareAndVerticalForTallOnes) {
  EXPECT_TRUE(SquareTiles({640, 480}, {}).empty());
  const std::vector<cv::Rect> tall = SquareTiles({300, 1000}, {});
  ASSERT_FALSE(tall.empty());
  EXPECT_EQ(tall.back().br().y, 1000);
  EXPECT_EQ(tall.front().width, 300);
}

TEST(MergeTileDetections, OneBoxPerObjectAcrossTilesAndTheWholeFrame) {
  const cv::Size image(1000, 400);
  TilingOptions options;
  const std::vector<cv::Rect> tiles = SquareTiles(image, options);
  ASSERT_EQ(tiles.size(), 3u);  // x 0, 300, 600: 100 px shared by neighbours
  // A car (2) at x 320..380 lies whole in tiles 0 and 1: seen twice, kept once.
  // A person (0) at x 250..330 crosses tile 1's left edge (300): tile 1 sees a part of it
  // (300..330), tile 0 sees it whole (250..330).
  // A truck (7) at x 200..800 is larger than any overlap: every tile sees part of it and
  // only the whole frame sees it whole.
  const std::vector<std::vector<Detection>> per_tile = {
      {Box(2, 320, 100, 60, 40, 0.8), Box(0, 250, 50, 80, 200, 0.7),
       Box(7, 200, 150, 200, 100, 0.6)},
      {Box(2, 321, 101, 59, 39, 0.9), Box(0, 300, 50, 30, 200, 0.75),
       Box(7, 300, 150, 300, 100, 0.6)},
      {Box(7, 600, 150, 200, 100, 0.6)}};
  const std::vector<Detection> whole = {Box(7, 205, 150, 590, 100, 0.5)};
  const std::vector<Detection> merged =
      MergeTileDetections(tiles, per_tile, whole, image, options, 0.5);
  ASSERT_EQ(merged.size(), 3u);
  EXPECT_EQ(merged[0].class_id, 2);
  EXPECT_DOUBLE_EQ(merged[0].confidence, 0.9);
  EXPECT_EQ(merged[1].class_id, 0);
  EXPECT_DOUBLE_EQ(merged[1].x, 250);  // the whole person, not the part cut by tile 1
  EXPECT_EQ(merged[2].class_id, 7);
  EXPECT_DOUBLE_EQ(merged[2].width, 590);  // the truck from the whole frame
}

TEST(MergeTileDetections, BoxesAtTheImageBorderAreNotCut) {
  const cv::Size image(1000, 400);
  const std::vector<cv::Rect> tiles = SquareTiles(image, {});
  const std::vector<std::vector<Detection>> per_tile = {
      {Box(2, 0, 0, 50, 50, 0.8)}, {}, {Box(2, 950, 350, 50, 50, 0.8)}};
  EXPECT_EQ(MergeTileDetections(tiles, per_tile, {}, image, {}, 0.5).size(), 2u);
}

TEST(TilingOptions, CheckNamesTheField) {
  TilingOptions options;
  options.min_overlap = 0.95;
  EXPECT_THROW(options.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace ocg
