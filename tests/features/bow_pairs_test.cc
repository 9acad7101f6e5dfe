#include "ocg/features/bow_pairs.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace ocg {
namespace {

// A drive past a row of distinct landmarks: frame i sees words i .. i + window - 1 with
// equal weights, so frames d apart share window - d words and frames at least `window`
// apart none.
std::vector<BowVector> SlidingWindowSequence(int frames, int window) {
  std::vector<BowVector> bows(static_cast<std::size_t>(frames));
  for (int i = 0; i < frames; ++i) {
    for (int w = 0; w < window; ++w) {
      bows[static_cast<std::size_t>(i)].entries.emplace_back(static_cast<WordId>(i + w),
                                                             1.0 / window);
    }
  }
  return bows;
}

TEST(SeparationAuc, CountsOrderedPairsAndTiesHalf) {
  EXPECT_DOUBLE_EQ(SeparationAuc({0.9, 0.8}, {0.1, 0.2, 0.3}), 1.0);
  EXPECT_DOUBLE_EQ(SeparationAuc({0.1}, {0.5, 0.6}), 0.0);
  EXPECT_DOUBLE_EQ(SeparationAuc({0.5}, {0.5}), 0.5);
  // 0.4 beats 0.1 and 0.3, loses to 0.6: 2 of 3.
  EXPECT_DOUBLE_EQ(SeparationAuc({0.4}, {0.6, 0.1, 0.3}), 2.0 / 3.0);
  EXPECT_TRUE(std::isnan(SeparationAuc({}, {0.5})));
  EXPECT_TRUE(std::isnan(SeparationAuc({0.5}, {})));
}

TEST(CompareBowPairs, SeparatesNeighboursOfADriveFromDistantFrames) {
  const BowPairOptions options{5, 30};
  const BowPairStats stats = CompareBowPairs(SlidingWindowSequence(40, 10), options);
  // Gaps 1..5 of 40 frames: 39 + 38 + 37 + 36 + 35; gaps 30..39: 10 + 9 + ... + 1.
  EXPECT_EQ(stats.true_pairs, 185u);
  EXPECT_EQ(stats.false_pairs, 55u);
  EXPECT_DOUBLE_EQ(stats.mean_false, 0.0);
  // Frames d apart share (10 - d) / 10 of their weight: the mean over gaps weighted by count.
  EXPECT_NEAR(stats.mean_true, (39 * 0.9 + 38 * 0.8 + 37 * 0.7 + 36 * 0.6 + 35 * 0.5) / 185, 1e-12);
  EXPECT_DOUBLE_EQ(stats.auc, 1.0);
  ASSERT_EQ(stats.auc_by_gap.size(), 5u);
  for (const double auc : stats.auc_by_gap) EXPECT_DOUBLE_EQ(auc, 1.0);
  EXPECT_DOUBLE_EQ(stats.recall_at_near, 1.0);
}

TEST(CompareBowPairs, ScoresThatCannotTellPlacesApartGiveChance) {
  // Every frame sees the same words: a vocabulary that maps everything to a few words.
  std::vector<BowVector> bows(40);
  for (auto& bow : bows) bow.entries = {{1, 0.5}, {2, 0.5}};
  const BowPairStats stats = CompareBowPairs(bows, BowPairOptions{5, 30});
  EXPECT_DOUBLE_EQ(stats.auc, 0.5);
  EXPECT_DOUBLE_EQ(stats.mean_true, stats.mean_false);
  // A tie is not a recognition: the neighbour must score above every other place.
  EXPECT_DOUBLE_EQ(stats.recall_at_near, 0.0);
}

TEST(CompareBowPairs, RefusesAFarGapInsideTheNearOne) {
  EXPECT_THROW(CompareBowPairs(SlidingWindowSequence(10, 3), BowPairOptions{5, 5}),
               std::invalid_argument);
  EXPECT_THROW(CompareBowPairs(SlidingWindowSequence(10, 3), BowPairOptions{0, 5}),
               std::invalid_argument);
}

}  // namespace
}  // namespace ocg
