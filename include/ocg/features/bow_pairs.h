#pragma once
// How well bag-of-words scores tell frames of the same place from frames of other places,
// measured on an ordered sequence of frames that never comes back to a place (a drive, a
// short hand-held clip): frames at most `near` apart see the same place (true pairs), frames
// at least `far` apart do not (false pairs). Used to compare vocabularies on real video
// (ocg_vocab pairs); a vocabulary that places true pairs above false ones serves loop
// detection and relocalization.

#include <cstddef>
#include <vector>

#include "ocg/features/vocabulary.h"

namespace ocg {

struct BowPairOptions {
  int near = 5;        // frames 1..near apart are true pairs
  int far = 30;        // frames at least this far apart are false pairs (> near)
  void Check() const;  // throws std::invalid_argument
};

struct BowPairStats {
  std::size_t true_pairs = 0;
  std::size_t false_pairs = 0;
  double mean_true = 0.0;   // mean ScoreL1 of the true pairs
  double mean_false = 0.0;  // mean ScoreL1 of the false pairs
  // Probability that a true pair scores above a false pair (ties count half): 1 separates
  // them perfectly, 0.5 is chance. NaN without pairs of both kinds.
  double auc = 0.0;
  // The same, for the true pairs exactly d frames apart alone (index d - 1).
  std::vector<double> auc_by_gap;
  // Share of frames i (among those with a false pair) whose score with frame i - near
  // beats every false pair of i: the place seen `near` frames ago is recognized among all
  // the other places of the sequence.
  double recall_at_near = 0.0;
};

// bows: one BoW vector per frame, in time order.
BowPairStats CompareBowPairs(const std::vector<BowVector>& bows, const BowPairOptions& options);

// Probability that a score of `positives` exceeds one of `negatives` (ties half); NaN when
// either is empty.
double SeparationAuc(std::vector<double> positives, std::vector<double> negatives);

}  // namespace ocg
