#include "ocg/features/bow_database.h"

#include <algorithm>
#include <unordered_set>

namespace ocg {

BowDatabase::BowDatabase(std::size_t word_count) : postings_(word_count) {}

void BowDatabase::RemovePostingsLocked(int id) {
  const auto existing = entries_.find(id);
  if (existing == entries_.end()) return;
  for (const auto& [word, weight] : existing->second.entries) {
    auto& list = postings_[word];
    list.erase(
        std::remove_if(list.begin(), list.end(), [id](const Posting& p) { return p.id == id; }),
        list.end());
  }
  entries_.erase(existing);
}

void BowDatabase::Add(int id, const BowVector& bow) {
  std::lock_guard<std::mutex> lock(mutex_);
  RemovePostingsLocked(id);
  for (const auto& [word, weight] : bow.entries) {
    if (word >= postings_.size()) postings_.resize(word + 1);
    postings_[word].push_back({id, weight});
  }
  entries_[id] = bow;
}

void BowDatabase::Erase(int id) {
  std::lock_guard<std::mutex> lock(mutex_);
  RemovePostingsLocked(id);
}

void BowDatabase::Clear() {
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto& list : postings_) list.clear();
  entries_.clear();
}

std::size_t BowDatabase::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return entries_.size();
}

std::vector<BowQueryResult> BowDatabase::Query(const BowVector& query, std::size_t max_results,
                                               int min_shared_words,
                                               const std::vector<int>& exclude) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::unordered_set<int> excluded(exclude.begin(), exclude.end());
  // For L1-normalized vectors the score is the sum over shared words of the smaller
  // weight, so it accumulates word by word from the postings.
  std::unordered_map<int, BowQueryResult> found;
  for (const auto& [word, weight] : query.entries) {
    if (word >= postings_.size()) continue;
    for (const Posting& posting : postings_[word]) {
      if (excluded.count(posting.id) != 0) continue;
      BowQueryResult& result = found[posting.id];
      result.id = posting.id;
      result.score += std::min(weight, posting.weight);
      ++result.shared_words;
    }
  }
  std::vector<BowQueryResult> results;
  results.reserve(found.size());
  for (const auto& [id, result] : found) {
    if (result.shared_words >= min_shared_words) results.push_back(result);
  }
  std::sort(results.begin(), results.end(), [](const BowQueryResult& a, const BowQueryResult& b) {
    return a.score != b.score ? a.score > b.score : a.id < b.id;
  });
  if (max_results > 0 && results.size() > max_results) results.resize(max_results);
  return results;
}

}  // namespace ocg
