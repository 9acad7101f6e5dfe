#pragma once
// An inverted index from vocabulary words to the images (keyframes) that hold them, for
// place recognition: which stored images look like this one?
//
// Thread safety: every member function locks an internal mutex, so tracking
// (relocalization queries), local mapping (Add) and loop closing (queries, Erase) may
// call it concurrently.

#include <cstddef>
#include <mutex>
#include <unordered_map>
#include <vector>

#include "ocg/features/vocabulary.h"

namespace ocg {

struct BowQueryResult {
  int id = -1;
  double score = 0.0;    // ScoreL1 with the query
  int shared_words = 0;  // words both hold
};

class BowDatabase {
 public:
  explicit BowDatabase(std::size_t word_count);

  // Adds (or replaces) the entry of an image id.
  void Add(int id, const BowVector& bow);
  void Erase(int id);
  void Clear();
  std::size_t size() const;

  // The stored images sharing at least min_shared_words words with the query (but
  // excluding ids listed in exclude), best score first (ties: smaller id first), at most
  // max_results of them (0: all).
  std::vector<BowQueryResult> Query(const BowVector& query, std::size_t max_results,
                                    int min_shared_words = 1,
                                    const std::vector<int>& exclude = {}) const;

 private:
  // Removes id's entry and postings; the caller holds mutex_.
  void RemovePostingsLocked(int id);

  struct Posting {
    int id;
    double weight;
  };
  mutable std::mutex mutex_;
  std::vector<std::vector<Posting>> postings_;  // per word
  std::unordered_map<int, BowVector> entries_;
};

}  // namespace ocg
