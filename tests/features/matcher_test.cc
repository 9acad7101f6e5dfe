#include "ocg/features/matcher.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <random>

#include "feature_test_images.h"
#include "ocg/core/options.h"
#include "test_support.h"

namespace ocg {
namespace {

struct WarpedPair {
  ExtractedFeatures original;
  ExtractedFeatures warped;
  cv::Size size;
  double degrees;
  double scale;
};

WarpedPair MakePair(const cv::Mat& image, double degrees, double scale) {
  OrbExtractor extractor{OrbExtractorOptions{}};
  const PinholeCamera camera;
  WarpedPair pair;
  pair.original = extractor.Extract(image, camera);
  pair.warped = extractor.Extract(testing::RotateAndScale(image, degrees, scale), camera);
  pair.size = image.size();
  pair.degrees = degrees;
  pair.scale = scale;
  return pair;
}

// Matches whose partner lies within tolerance (level-0 pixels, scaled by the keypoint's
// pyramid scale) of where the known warp sends the keypoint.
struct MatchQuality {
  int matches = 0;
  int correct = 0;
  double Precision() const { return matches == 0 ? 0.0 : static_cast<double>(correct) / matches; }
};

MatchQuality Judge(const WarpedPair& pair, const std::vector<int>& matches, double tolerance) {
  MatchQuality quality;
  for (std::size_t i = 0; i < matches.size(); ++i) {
    if (matches[i] == kNoMatch) continue;
    ++quality.matches;
    const cv::KeyPoint& a = pair.original.keypoints[i];
    const cv::Point2f expected = testing::WarpPoint(a.pt, pair.size, pair.degrees, pair.scale);
    const cv::Point2f found = pair.warped.keypoints[static_cast<std::size_t>(matches[i])].pt;
    const double allowed = tolerance * a.size / 31.0 * pair.scale;
    if (cv::norm(found - expected) <= allowed) ++quality.correct;
  }
  return quality;
}

TEST(Hamming, PopCountOfExtremeAndSparseWords) {
  EXPECT_EQ(PopCount(0), 0);
  EXPECT_EQ(PopCount(~std::uint64_t{0}), 64);  // every byte 8: the multiplication's top byte
  EXPECT_EQ(PopCount(0x5555555555555555ULL), 32);
  EXPECT_EQ(PopCount(0xFF00000000000000ULL), 8);
  for (int bit = 0; bit < 64; ++bit) {
    EXPECT_EQ(PopCount(std::uint64_t{1} << bit), 1) << bit;
    EXPECT_EQ(PopCount(~(std::uint64_t{1} << bit)), 63) << bit;
  }
}

TEST(Hamming, CountsDifferingBits) {
  std::mt19937_64 rng(1);
  for (int trial = 0; trial < 100; ++trial) {
    Descriptor a{rng(), rng(), rng(), rng()};
    Descriptor b{rng(), rng(), rng(), rng()};
    int expected = 0;
    for (int bit = 0; bit < kDescriptorBits; ++bit) {
      expected += DescriptorBit(a, bit) != DescriptorBit(b, bit) ? 1 : 0;
    }
    EXPECT_EQ(HammingDistance(a, b), expected);
  }
  std::uint8_t bytes[kDescriptorBytes];
  for (int i = 0; i < kDescriptorBytes; ++i) bytes[i] = static_cast<std::uint8_t>(i * 7 + 1);
  std::uint8_t back[kDescriptorBytes];
  DescriptorToBytes(DescriptorFromBytes(bytes), back);
  EXPECT_EQ(std::memcmp(bytes, back, kDescriptorBytes), 0);
  EXPECT_TRUE(DescriptorBit(DescriptorFromBytes(bytes), 0));  // byte 0 = 1: bit 0 set
  EXPECT_FALSE(DescriptorBit(DescriptorFromBytes(bytes), 1));
}

TEST(Majority, TakesTheMoreCommonValueOfEveryBit) {
  const Descriptor a{0b1100, 0, ~0ull, 0};
  const Descriptor b{0b1010, 0, ~0ull, 1};
  const Descriptor c{0b1001, 0, 0, 1};
  const Descriptor centre = MajorityDescriptor({&a, &b, &c});
  EXPECT_EQ(centre[0], 0b1000u);
  EXPECT_EQ(centre[2], ~0ull);
  EXPECT_EQ(centre[3], 1u);
}

TEST(Matcher, BruteForceFindsTheCorrespondencesOfARotatedScaledCopy) {
  const WarpedPair pair = MakePair(testing::TexturedImage(11), 30.0, 1.2);
  MatcherOptions options;
  std::vector<int> matches =
      MatchBruteForce(pair.original.descriptors, pair.warped.descriptors, 0.8, 64);
  FilterByRotationConsistency(pair.original.keypoints, pair.warped.keypoints,
                              options.orientation_bins, &matches);
  const MatchQuality quality = Judge(pair, matches, 2.0);
  EXPECT_GE(quality.matches, 250);
  EXPECT_GE(quality.Precision(), 0.95);
  // The rotation filter removed what disagrees with the common rotation of 30 degrees.
  for (std::size_t i = 0; i < matches.size(); ++i) {
    if (matches[i] == kNoMatch) continue;
    double rotation = pair.warped.keypoints[static_cast<std::size_t>(matches[i])].angle -
                      pair.original.keypoints[i].angle;
    rotation = std::fmod(rotation + 720.0, 360.0);
    EXPECT_LT(std::min(std::abs(rotation - 330.0), std::abs(rotation + 30.0)), 24.0);
  }
}

TEST(Matcher, RealFrameAndItsRotatedCopy) {
  const std::vector<cv::Mat> frames = testing::TumFrames();
  if (frames.empty()) GTEST_SKIP() << testing::SharedDataSkipMessage();
  const WarpedPair pair = MakePair(frames[3], -20.0, 0.9);
  std::vector<int> matches =
      MatchBruteForce(pair.original.descriptors, pair.warped.descriptors, 0.8, 64);
  FilterByRotationConsistency(pair.original.keypoints, pair.warped.keypoints, 30, &matches);
  const MatchQuality quality = Judge(pair, matches, 2.0);
  std::cout << "TUM frame rotated -20 deg, scaled 0.9: " << quality.matches << " matches, "
            << quality.correct << " correct\n";
  EXPECT_GE(quality.matches, 200);
  EXPECT_GE(quality.Precision(), 0.95);
}

TEST(Matcher, RotationFilterDropsMatchesThatTurnTheWrongWay) {
  std::vector<cv::KeyPoint> a(100), b(100);
  std::vector<int> matches(100);
  for (int i = 0; i < 100; ++i) {
    a[static_cast<std::size_t>(i)].angle = static_cast<float>(i * 3);
    // 80 rotate by 45 degrees, 20 by 180.
    b[static_cast<std::size_t>(i)].angle =
        std::fmod(static_cast<float>(i * 3) + (i < 80 ? 45.0f : 180.0f), 360.0f);
    matches[static_cast<std::size_t>(i)] = i;
  }
  FilterByRotationConsistency(a, b, 30, &matches);
  for (int i = 0; i < 100; ++i) {
    EXPECT_EQ(matches[static_cast<std::size_t>(i)] != kNoMatch, true) << i;
  }
  // With 5 of the 100 turning the wrong way (under a tenth of the winner), those go.
  for (int i = 0; i < 100; ++i) {
    b[static_cast<std::size_t>(i)].angle =
        std::fmod(static_cast<float>(i * 3) + (i < 95 ? 45.0f : 180.0f), 360.0f);
    matches[static_cast<std::size_t>(i)] = i;
  }
  FilterByRotationConsistency(a, b, 30, &matches);
  for (int i = 0; i < 100; ++i) {
    EXPECT_EQ(matches[static_cast<std::size_t>(i)] != kNoMatch, i < 95) << i;
  }
}

TEST(Matcher, SearchByProjectionFindsPointsWhereTheWarpSendsThem) {
  const WarpedPair pair = MakePair(testing::TexturedImage(12), 10.0, 1.0);
  std::vector<ProjectedPoint> points;
  for (std::size_t i = 0; i < pair.original.size(); ++i) {
    const cv::KeyPoint& k = pair.original.keypoints[i];
    const cv::Point2f predicted = testing::WarpPoint(k.pt, pair.size, pair.degrees, pair.scale);
    ProjectedPoint point;
    point.pixel = {predicted.x, predicted.y};
    point.radius = 4.0 * k.size / 31.0;
    point.min_level = std::max(0, k.octave - 1);
    point.max_level = k.octave + 1;
    point.descriptor = pair.original.descriptors[i];
    point.source_angle = k.angle;
    points.push_back(point);
  }
  const MatcherOptions options;
  const std::vector<int> matches = SearchByProjection(
      pair.warped, points, nullptr, options.projection_ratio, options.loose_distance, options);
  const MatchQuality quality = Judge(pair, matches, 4.0);
  EXPECT_GE(quality.matches, 350);  // about 43 % of the keypoints repeat after the warp
  EXPECT_GE(quality.Precision(), 0.98);
  // Features marked as taken are never returned.
  std::vector<bool> taken(pair.warped.size(), false);
  for (std::size_t i = 0; i < taken.size(); i += 2) taken[i] = true;
  const std::vector<int> rest = SearchByProjection(pair.warped, points, &taken, 0.8, 100, options);
  for (const int m : rest) {
    if (m != kNoMatch) {
      EXPECT_FALSE(taken[static_cast<std::size_t>(m)]);
    }
  }
  // One-to-one.
  std::vector<int> seen(pair.warped.size(), 0);
  for (const int m : matches) {
    if (m != kNoMatch) {
      EXPECT_EQ(++seen[static_cast<std::size_t>(m)], 1);
    }
  }
}

TEST(Matcher, WindowSearchFollowsASmallShift) {
  const cv::Mat image = testing::TexturedImage(13);
  cv::Mat shifted;
  const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, 7, 0, 1, -4);
  cv::warpAffine(image, shifted, shift, image.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT_101);
  OrbExtractor extractor{OrbExtractorOptions{}};
  const PinholeCamera camera;
  const ExtractedFeatures a = extractor.Extract(image, camera);
  const ExtractedFeatures b = extractor.Extract(shifted, camera);
  MatcherOptions options;
  options.initialization_window = 20;
  options.initialization_all_levels = false;
  // Predicted: where the feature was (no motion assumed), as at initialization.
  const std::vector<int> matches = MatchInWindow(a, b, a.undistorted, options);
  int found = 0;
  int correct = 0;
  int level0 = 0;
  for (std::size_t i = 0; i < matches.size(); ++i) {
    if (a.keypoints[i].octave == 0) ++level0;
    if (matches[i] == kNoMatch) continue;
    EXPECT_EQ(a.keypoints[i].octave, 0);
    ++found;
    const Eigen::Vector2d moved = b.undistorted[static_cast<std::size_t>(matches[i])];
    if ((moved - a.undistorted[i] - Eigen::Vector2d(7, -4)).norm() < 1.5) ++correct;
  }
  EXPECT_GE(found, level0 / 2);
  EXPECT_GE(correct, found * 95 / 100);
}

TEST(MatcherOptions, ChecksNameTheKey) {
  MatcherOptions options;
  options.loose_distance = 10;
  try {
    options.Check();
    FAIL() << "expected OptionError";
  } catch (const OptionError& error) {
    EXPECT_NE(std::string(error.what()).find("Matcher.looseDistance"), std::string::npos);
  }
}

}  // namespace
}  // namespace ocg
