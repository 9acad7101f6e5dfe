#include "ocg/objects/sighting_history.h"

#include <algorithm>
#include <iterator>
#include <set>

namespace ocg {
namespace {

// Trailing zero bits of a frame number; 64 for frame 0 (kept at every level).
int TrailingZeros(std::int64_t frame) {
  auto bits = static_cast<std::uint64_t>(frame);
  if (bits == 0) return 64;
  int zeros = 0;
  while ((bits & 1u) == 0) {
    bits >>= 1;
    ++zeros;
  }
  return zeros;
}

}  // namespace

SightingHistory::SightingHistory(std::vector<ObjectSighting> sightings)
    : kept_(std::move(sightings)) {
  for (const ObjectSighting& sighting : kept_) Count(sighting);
}

void SightingHistory::Count(const ObjectSighting& sighting) {
  ++total_;
  if (!sighting.crowded) ++uncrowded_;
  spans_[{sighting.session, sighting.class_id}].Add(sighting.timestamp);
}

void SightingHistory::ClassSpan::Add(double timestamp) {
  ClassSpan one;
  one.count = 1;
  one.first_timestamp = one.last_timestamp = timestamp;
  Merge(one);
}

void SightingHistory::ClassSpan::Merge(const ClassSpan& other) {
  if (other.count == 0) return;
  if (count == 0) {
    *this = other;
    return;
  }
  // The two earliest and the two latest of both are among each side's own.
  std::vector<double> times = Extremes();
  const std::vector<double> theirs = other.Extremes();
  times.insert(times.end(), theirs.begin(), theirs.end());
  std::sort(times.begin(), times.end());
  count += other.count;
  first_timestamp = times.front();
  second_timestamp = times[1];
  last_timestamp = times.back();
  second_last_timestamp = times[times.size() - 2];
}

std::vector<double> SightingHistory::ClassSpan::Extremes() const {
  switch (count) {
    case 0:
      return {};
    case 1:
      return {first_timestamp};
    case 2:
      return {first_timestamp, last_timestamp};
    case 3:  // the middle one is both second and second last
      return {first_timestamp, second_timestamp, last_timestamp};
    default:
      return {first_timestamp, second_timestamp, second_last_timestamp, last_timestamp};
  }
}

void SightingHistory::Add(const ObjectSighting& sighting, std::size_t capacity) {
  Count(sighting);
  kept_.push_back(sighting);
  Bound(capacity);
}

void SightingHistory::Merge(const SightingHistory& other, std::size_t capacity) {
  std::vector<ObjectSighting> merged;
  merged.reserve(kept_.size() + other.kept_.size());
  std::merge(kept_.begin(), kept_.end(), other.kept_.begin(), other.kept_.end(),
             std::back_inserter(merged),
             [](const ObjectSighting& a, const ObjectSighting& b) { return a.frame < b.frame; });
  kept_ = std::move(merged);
  total_ += other.total_;
  uncrowded_ += other.uncrowded_;
  for (const auto& [key, theirs] : other.spans_) {
    spans_[key].Merge(theirs);
  }
  level_ = std::max(level_, other.level_);
  Bound(capacity);
}

void SightingHistory::Bound(std::size_t capacity) {
  if (capacity == 0 || kept_.size() <= capacity) return;
  // Thinned to three quarters of capacity at once, so a history at its bound is thinned
  // once every capacity / 4 sightings, not at every one.
  const std::size_t recent = capacity / 4;
  const std::size_t target = capacity - capacity / 4;
  // The sightings that left the newest quarter since the last time are thinned at the
  // level the others were; the level rises only when that is not enough.
  for (;;) {
    const std::size_t old_end = kept_.size() - recent;
    std::size_t out = 1;  // the first stays
    for (std::size_t i = 1; i < kept_.size(); ++i) {
      if (i >= old_end || TrailingZeros(kept_[i].frame) >= level_) {
        if (out != i) kept_[out] = std::move(kept_[i]);
        ++out;
      }
    }
    kept_.erase(kept_.begin() + static_cast<std::ptrdiff_t>(out), kept_.end());
    if (kept_.size() <= target || level_ >= 64) return;
    ++level_;
  }
}

int SightingHistory::MajorityClass() const {
  std::map<int, std::size_t> votes;
  for (const auto& [key, span] : spans_) votes[key.second] += span.count;
  int best = 0;
  std::size_t best_votes = 0;
  for (const auto& [class_id, count] : votes) {
    if (count > best_votes) {
      best = class_id;
      best_votes = count;
    }
  }
  return best;
}

bool SightingHistory::SharesASessionWith(const SightingHistory& other) const {
  std::set<int> sessions;
  for (const auto& [key, span] : spans_) sessions.insert(key.first);
  return std::any_of(other.spans_.begin(), other.spans_.end(),
                     [&](const auto& entry) { return sessions.count(entry.first.first) > 0; });
}

std::pair<int, int> SightingHistory::SessionRange() const {
  if (spans_.empty()) return {0, 0};
  return {spans_.begin()->first.first, spans_.rbegin()->first.first};
}

void SightingHistory::ForgetSightings(int session) {
  std::vector<ObjectSighting> coloured;
  for (const ObjectSighting& sighting : kept_) {
    if (sighting.colour && sighting.session == session) coloured.push_back(sighting);
  }
  kept_ = std::move(coloured);
}

}  // namespace ocg
