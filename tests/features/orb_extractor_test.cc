#include "ocg/features/orb_extractor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "feature_test_images.h"
#include "ocg/core/options.h"
#include "ocg/features/matcher.h"
#include "test_support.h"

namespace ocg {
namespace {

constexpr int kCoarseColumns = 16;  // 40 x 40 pixel cells on a 640 x 480 image
constexpr int kCoarseRows = 12;

double OccupiedShare(const ExtractedFeatures& features, const PinholeCamera& camera) {
  const FeatureGrid coarse(features.undistorted, features.Levels(), UndistortedImageBounds(camera),
                           kCoarseColumns, kCoarseRows);
  return static_cast<double>(coarse.OccupiedCells()) / (kCoarseColumns * kCoarseRows);
}

// Share of the textured cells (those where FAST finds any corner at the lenient
// threshold, 20 pixels or more from the border) that hold a keypoint. Real frames have
// blank walls and dark corners; no extractor can populate those.
double TexturedCellsShare(const cv::Mat& image, const ExtractedFeatures& features,
                          int fast_threshold) {
  std::vector<cv::KeyPoint> corners;
  cv::FAST(image, corners, fast_threshold, true);
  const double cell_width = static_cast<double>(image.cols) / kCoarseColumns;
  const double cell_height = static_cast<double>(image.rows) / kCoarseRows;
  auto cell_of = [&](const cv::Point2f& p) {
    return std::min(kCoarseRows - 1, static_cast<int>(p.y / cell_height)) * kCoarseColumns +
           std::min(kCoarseColumns - 1, static_cast<int>(p.x / cell_width));
  };
  std::vector<char> textured(kCoarseColumns * kCoarseRows, 0);
  std::vector<char> occupied(kCoarseColumns * kCoarseRows, 0);
  for (const cv::KeyPoint& k : corners) {
    if (k.pt.x < 20 || k.pt.y < 20 || k.pt.x >= image.cols - 20 || k.pt.y >= image.rows - 20) {
      continue;
    }
    textured[static_cast<std::size_t>(cell_of(k.pt))] = 1;
  }
  for (const cv::KeyPoint& k : features.keypoints)
    occupied[static_cast<std::size_t>(cell_of(k.pt))] = 1;
  int textured_cells = 0;
  int populated = 0;
  for (std::size_t i = 0; i < textured.size(); ++i) {
    textured_cells += textured[i];
    populated += textured[i] && occupied[i] ? 1 : 0;
  }
  return textured_cells == 0 ? 1.0 : static_cast<double>(populated) / textured_cells;
}

void ExpectWellFormed(const ExtractedFeatures& f, const OrbExtractor& extractor,
                      const cv::Size& size) {
  ASSERT_EQ(f.keypoints.size(), f.descriptors.size());
  ASSERT_EQ(f.keypoints.size(), f.undistorted.size());
  for (const cv::KeyPoint& k : f.keypoints) {
    ASSERT_GE(k.octave, 0);
    ASSERT_LT(k.octave, extractor.options().levels);
    const double scale = extractor.pyramid().scale[static_cast<std::size_t>(k.octave)];
    EXPECT_NEAR(k.size, 31.0 * scale, 1e-3);
    EXPECT_GE(k.angle, 0.0f);
    EXPECT_LT(k.angle, 360.0f);
    // The BRIEF patch must fit in the level image.
    EXPECT_GE(k.pt.x, 19.0 * scale - 1e-3);
    EXPECT_GE(k.pt.y, 19.0 * scale - 1e-3);
    EXPECT_LE(k.pt.x, size.width - 19.0 * scale + scale);
    EXPECT_LE(k.pt.y, size.height - 19.0 * scale + scale);
  }
}

TEST(OrbExtractor, SplitsFeaturesGeometricallyOverLevels) {
  OrbExtractorOptions options;
  const OrbExtractor extractor(options);
  const std::vector<int>& per_level = extractor.FeaturesPerLevel();
  ASSERT_EQ(per_level.size(), 8u);
  int total = 0;
  for (std::size_t level = 0; level < per_level.size(); ++level) {
    total += per_level[level];
    if (level > 0 && level + 1 < per_level.size()) {
      EXPECT_NEAR(per_level[level - 1] / static_cast<double>(per_level[level]), 1.2, 0.02);
    }
  }
  EXPECT_EQ(total, 1000);
  EXPECT_EQ(per_level[0], 217);  // 1000 * (1 - 1/1.2) / (1 - 1.2^-8), rounded
}

TEST(OrbExtractor, RejectsImpossibleOptionsAndImages) {
  OrbExtractorOptions options;
  options.minimum_fast_threshold = 30;
  try {
    OrbExtractor extractor(options);
    FAIL() << "expected OptionError";
  } catch (const OptionError& error) {
    EXPECT_NE(std::string(error.what()).find("ORBextractor.minThFAST"), std::string::npos);
  }
  OrbExtractor extractor{OrbExtractorOptions{}};
  PinholeCamera camera;
  EXPECT_THROW(extractor.Extract(cv::Mat(), camera), std::invalid_argument);
  try {
    extractor.Extract(cv::Mat(100, 100, CV_8UC1, cv::Scalar(0)), camera);
    FAIL() << "expected invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("Camera.width"), std::string::npos);
  }
}

TEST(OrbExtractor, TexturedImageGivesTheRequestedCountSpreadOverTheImage) {
  OrbExtractor extractor{OrbExtractorOptions{}};
  const PinholeCamera camera;
  const cv::Mat image = testing::TexturedImage(7);
  const ExtractedFeatures f = extractor.Extract(image, camera);
  ExpectWellFormed(f, extractor, image.size());
  EXPECT_NEAR(static_cast<double>(f.size()), 1000.0, 50.0);
  EXPECT_GE(OccupiedShare(f, camera), 0.8);
  // Every level contributes.
  std::vector<int> per_level(8, 0);
  for (const cv::KeyPoint& k : f.keypoints) per_level[static_cast<std::size_t>(k.octave)]++;
  for (const int count : per_level) EXPECT_GT(count, 0);
}

// Images larger than the 640 x 480 the extractor was first written for: before the FAST
// cells tiled each level exactly, every one of these aborted in cv::FAST at frame 0.
TEST(OrbExtractor, ExtractsFromLargeImagesOnEveryLevel) {
  OrbExtractor extractor{OrbExtractorOptions{}};
  const cv::Mat tile = testing::TexturedImage(11);
  for (const cv::Size size : {cv::Size(1920, 1080), cv::Size(1600, 1200), cv::Size(2560, 1920),
                              cv::Size(4000, 3000), cv::Size(1888, 1061)}) {
    SCOPED_TRACE(::testing::Message() << size);
    cv::Mat image;
    cv::repeat(tile, (size.height + tile.rows - 1) / tile.rows,
               (size.width + tile.cols - 1) / tile.cols, image);
    image = image(cv::Rect({0, 0}, size)).clone();
    PinholeCamera camera;
    camera.width = size.width;
    camera.height = size.height;
    camera.cx = size.width / 2.0;
    camera.cy = size.height / 2.0;
    const ExtractedFeatures f = extractor.Extract(image, camera);
    ExpectWellFormed(f, extractor, image.size());
    EXPECT_NEAR(static_cast<double>(f.size()), 1000.0, 50.0);
    std::vector<int> per_level(8, 0);
    for (const cv::KeyPoint& k : f.keypoints) per_level[static_cast<std::size_t>(k.octave)]++;
    for (const int count : per_level) EXPECT_GT(count, 0);
    EXPECT_GE(OccupiedShare(f, camera), 0.8);
  }
}

TEST(OrbExtractor, IsDeterministic) {
  OrbExtractor first{OrbExtractorOptions{}};
  OrbExtractor second{OrbExtractorOptions{}};
  const cv::Mat image = testing::TexturedImage(3);
  const PinholeCamera camera;
  const ExtractedFeatures a = first.Extract(image, camera);
  const ExtractedFeatures b = second.Extract(image, camera);
  first.Extract(testing::TexturedImage(4), camera);  // buffers reused in between
  const ExtractedFeatures c = first.Extract(image, camera);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.size(), c.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.keypoints[i].pt, b.keypoints[i].pt);
    EXPECT_EQ(a.keypoints[i].angle, c.keypoints[i].angle);
    EXPECT_EQ(a.descriptors[i], b.descriptors[i]);
    EXPECT_EQ(a.descriptors[i], c.descriptors[i]);
  }
}

TEST(OrbExtractor, UndistortsKeypointsWithTheCameraModel) {
  PinholeCamera camera;
  camera.k1 = -0.28;
  camera.k2 = 0.07;
  camera.p1 = 0.0002;
  OrbExtractor extractor{OrbExtractorOptions{}};
  const ExtractedFeatures f = extractor.Extract(testing::TexturedImage(5), camera);
  ASSERT_GT(f.size(), 900u);
  double largest_shift = 0.0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    const Eigen::Vector2d raw(f.keypoints[i].pt.x, f.keypoints[i].pt.y);
    const Eigen::Vector2d expected = camera.UndistortPixel(raw);
    EXPECT_LT((f.undistorted[i] - expected).norm(), 1e-6);
    largest_shift = std::max(largest_shift, (f.undistorted[i] - raw).norm());
  }
  EXPECT_GT(largest_shift, 10.0);  // the corners of the image move a lot
}

TEST(OrbExtractor, QuadtreeSpreadsCornersAndKeepsTheStrongestOfEachNode) {
  // 400 equally strong corners crowded in one 20x20 patch, and 8 lone ones along a line:
  // a ranking by response could keep any 12; the quadtree must keep all the lone ones.
  std::vector<cv::KeyPoint> candidates;
  for (int i = 0; i < 400; ++i) {
    candidates.emplace_back(
        cv::Point2f(5.0f + static_cast<float>(i % 20), 5.0f + static_cast<float>(i / 20)), 7.0f,
        -1.0f, 10.0f);
  }
  for (int i = 0; i < 8; ++i) {
    candidates.emplace_back(cv::Point2f(100.0f + 60.0f * static_cast<float>(i), 300.0f), 7.0f,
                            -1.0f, 10.0f);
  }
  const std::vector<int> spread =
      DistributeByQuadtree(candidates, {0.0f, 0.0f}, {600.0f, 400.0f}, 12);
  ASSERT_EQ(spread.size(), 12u);
  int lone = 0;
  for (const int index : spread) lone += index >= 400 ? 1 : 0;
  EXPECT_EQ(lone, 8);
  // Plenty of candidates: exactly the number wanted.
  EXPECT_EQ(DistributeByQuadtree(candidates, {0.0f, 0.0f}, {600.0f, 400.0f}, 100).size(), 100u);
  // Fewer candidates than wanted: all of them.
  EXPECT_EQ(DistributeByQuadtree(candidates, {0.0f, 0.0f}, {600.0f, 400.0f}, 1000).size(),
            candidates.size());
  // One node: the strongest corner in it.
  std::vector<cv::KeyPoint> pair = {cv::KeyPoint(cv::Point2f(10.0f, 10.0f), 7.0f, -1.0f, 5.0f),
                                    cv::KeyPoint(cv::Point2f(12.0f, 11.0f), 7.0f, -1.0f, 9.0f),
                                    cv::KeyPoint(cv::Point2f(11.0f, 13.0f), 7.0f, -1.0f, 2.0f)};
  const std::vector<int> strongest = DistributeByQuadtree(pair, {0.0f, 0.0f}, {50.0f, 50.0f}, 1);
  ASSERT_EQ(strongest.size(), 1u);
  EXPECT_EQ(strongest[0], 1);
}

TEST(OrbExtractor, IntensityCentroidPointsTowardsTheBrightSide) {
  const std::vector<int> circle = CircleHalfWidths(15);
  cv::Mat ramp(64, 64, CV_8UC1);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) ramp.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(2 * x);
  }
  EXPECT_NEAR(IntensityCentroidAngle(ramp, {32.0f, 32.0f}, circle), 0.0f, 1.0f);
  cv::Mat down;
  cv::rotate(ramp, down, cv::ROTATE_90_CLOCKWISE);  // brighter towards +y (image down)
  EXPECT_NEAR(IntensityCentroidAngle(down, {32.0f, 32.0f}, circle), 90.0f, 1.0f);
  cv::Mat left;
  cv::flip(ramp, left, 1);
  EXPECT_NEAR(IntensityCentroidAngle(left, {32.0f, 32.0f}, circle), 180.0f, 1.0f);
}

TEST(OrbExtractorRealFrames, TumFramesGiveTheRequestedCountOverTheImage) {
  const std::vector<cv::Mat> frames = testing::TumFrames();
  if (frames.empty()) GTEST_SKIP() << testing::SharedDataSkipMessage();
  OrbExtractor extractor{OrbExtractorOptions{}};
  PinholeCamera camera;  // fr3: ORB-SLAM2's TUM3.yaml, no distortion
  camera.fx = 535.4;
  camera.fy = 539.2;
  camera.cx = 320.1;
  camera.cy = 247.6;
  double worst_share = 1.0;
  for (const cv::Mat& frame : frames) {
    const ExtractedFeatures f = extractor.Extract(frame, camera);
    ExpectWellFormed(f, extractor, frame.size());
    EXPECT_NEAR(static_cast<double>(f.size()), 1000.0, 50.0);
    const double share = TexturedCellsShare(frame, f, 7);
    worst_share = std::min(worst_share, share);
    EXPECT_GE(share, 0.8);
  }
  std::cout << "TUM fr3 long_office: " << frames.size()
            << " frames, worst share of textured cells populated " << worst_share << "\n";
}

TEST(OrbExtractorRealFrames, EurocFramesGiveTheRequestedCountAndRepeat) {
  PinholeCamera camera;
  const std::vector<cv::Mat> frames = testing::EurocFrames(&camera);
  if (frames.empty()) GTEST_SKIP() << testing::SharedDataSkipMessage();
  OrbExtractor extractor{OrbExtractorOptions{}};
  std::vector<ExtractedFeatures> features;
  double worst_share = 1.0;
  for (const cv::Mat& frame : frames) {
    features.push_back(extractor.Extract(frame, camera));
    EXPECT_NEAR(static_cast<double>(features.back().size()), 1000.0, 50.0);
    const double share = TexturedCellsShare(frame, features.back(), 7);
    worst_share = std::min(worst_share, share);
    EXPECT_GE(share, 0.8);
  }
  std::cout << "EuRoC V1_01: " << frames.size()
            << " frames, worst share of textured cells populated " << worst_share << "\n";
  // Repeatability between consecutive frames (50 ms apart): the share of keypoints that
  // find a partner with a similar descriptor consistent with the epipolar geometry.
  double worst = 1.0;
  double total = 0.0;
  for (std::size_t i = 0; i + 1 < features.size(); i += 5) {
    const ExtractedFeatures& a = features[i];
    const ExtractedFeatures& b = features[i + 1];
    const std::vector<int> matches = MatchBruteForce(a.descriptors, b.descriptors, 0.8, 64);
    std::vector<cv::Point2f> pa, pb;
    for (std::size_t k = 0; k < matches.size(); ++k) {
      if (matches[k] == kNoMatch) continue;
      pa.emplace_back(static_cast<float>(a.undistorted[k].x()),
                      static_cast<float>(a.undistorted[k].y()));
      const Eigen::Vector2d& q = b.undistorted[static_cast<std::size_t>(matches[k])];
      pb.emplace_back(static_cast<float>(q.x()), static_cast<float>(q.y()));
    }
    ASSERT_GE(pa.size(), 8u);
    cv::Mat inlier_mask;
    cv::findFundamentalMat(pa, pb, cv::FM_RANSAC, 1.0, 0.999, inlier_mask);
    const double share = cv::countNonZero(inlier_mask) / static_cast<double>(a.size());
    worst = std::min(worst, share);
    total += share;
  }
  std::cout << "EuRoC V1_01: repeatable share worst " << worst << ", mean "
            << total / ((features.size() + 3) / 5) << "\n";
  EXPECT_GE(worst, 0.4);
}

}  // namespace
}  // namespace ocg
