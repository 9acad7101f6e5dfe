#include "ocg/features/bow_pairs.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

namespace ocg {

void BowPairOptions::Check() const {
  if (near < 1) throw std::invalid_argument("near must be at least 1, not " + std::to_string(near));
  if (far <= near) {
    throw std::invalid_argument("far (" + std::to_string(far) + ") must exceed near (" +
                                std::to_string(near) + ")");
  }
}

double SeparationAuc(std::vector<double> positives, std::vector<double> negatives) {
  if (positives.empty() || negatives.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(negatives.begin(), negatives.end());
  double wins = 0.0;
  for (const double score : positives) {
    const auto range = std::equal_range(negatives.begin(), negatives.end(), score);
    wins += static_cast<double>(range.first - negatives.begin()) +
            0.5 * static_cast<double>(range.second - range.first);
  }
  return wins / (static_cast<double>(positives.size()) * static_cast<double>(negatives.size()));
}

namespace {

double Mean(const std::vector<double>& values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  return std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
}

}  // namespace

BowPairStats CompareBowPairs(const std::vector<BowVector>& bows, const BowPairOptions& options) {
  options.Check();
  const int n = static_cast<int>(bows.size());
  std::vector<std::vector<double>> true_by_gap(static_cast<std::size_t>(options.near));
  std::vector<double> true_scores, false_scores;
  // Best false score seen by each frame, for the recall at distance `near`.
  std::vector<double> best_false(static_cast<std::size_t>(n), -1.0);
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const int gap = j - i;
      if (gap > options.near && gap < options.far) continue;
      const double score =
          ScoreL1(bows[static_cast<std::size_t>(i)], bows[static_cast<std::size_t>(j)]);
      if (gap <= options.near) {
        true_by_gap[static_cast<std::size_t>(gap - 1)].push_back(score);
        true_scores.push_back(score);
      } else {
        false_scores.push_back(score);
        for (const int k : {i, j}) {
          best_false[static_cast<std::size_t>(k)] =
              std::max(best_false[static_cast<std::size_t>(k)], score);
        }
      }
    }
  }
  BowPairStats stats;
  stats.true_pairs = true_scores.size();
  stats.false_pairs = false_scores.size();
  stats.mean_true = Mean(true_scores);
  stats.mean_false = Mean(false_scores);
  stats.auc = SeparationAuc(true_scores, false_scores);
  for (const auto& scores : true_by_gap)
    stats.auc_by_gap.push_back(SeparationAuc(scores, false_scores));
  int queries = 0, recalled = 0;
  for (int i = options.near; i < n; ++i) {
    if (best_false[static_cast<std::size_t>(i)] < 0.0) continue;
    ++queries;
    const double score = ScoreL1(bows[static_cast<std::size_t>(i)],
                                 bows[static_cast<std::size_t>(i - options.near)]);
    if (score > best_false[static_cast<std::size_t>(i)]) ++recalled;
  }
  stats.recall_at_near = queries == 0 ? std::numeric_limits<double>::quiet_NaN()
                                      : static_cast<double>(recalled) / queries;
  return stats;
}

}  // namespace ocg
