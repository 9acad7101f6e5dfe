#include "ocg/features/matcher.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>

#include "ocg/core/options.h"
#include "ocg/core/settings_file.h"

namespace ocg {
namespace {

struct Proposal {
  int query;
  int target;
  int distance;
};

// One-to-one matches from proposals: closest pairs first (ties: smaller query index).
std::vector<int> ResolveConflicts(std::vector<Proposal> proposals, std::size_t queries,
                                  std::size_t targets) {
  std::sort(proposals.begin(), proposals.end(), [](const Proposal& a, const Proposal& b) {
    return a.distance != b.distance ? a.distance < b.distance : a.query < b.query;
  });
  std::vector<int> matches(queries, kNoMatch);
  std::vector<char> taken(targets, 0);
  for (const Proposal& p : proposals) {
    if (matches[static_cast<std::size_t>(p.query)] != kNoMatch ||
        taken[static_cast<std::size_t>(p.target)]) {
      continue;
    }
    matches[static_cast<std::size_t>(p.query)] = p.target;
    taken[static_cast<std::size_t>(p.target)] = 1;
  }
  return matches;
}

// Best and second best distance among candidates.
struct Nearest {
  int best = INT_MAX;
  int second = INT_MAX;
  int index = kNoMatch;
  int best_level = -1;
  int second_level = -1;

  void Offer(int distance, int candidate, int level) {
    if (distance < best) {
      second = best;
      second_level = best_level;
      best = distance;
      index = candidate;
      best_level = level;
    } else if (distance < second) {
      second = distance;
      second_level = level;
    }
  }
  bool PassesRatio(double ratio) const {
    return second == INT_MAX || static_cast<double>(best) < ratio * static_cast<double>(second);
  }
};

// Drops matches outside the three most popular rotation bins (rotation_of(i) in degrees
// for match i, or a negative value for matches the filter must leave alone).
template <typename RotationOf>
void KeepConsistentRotations(int bins, RotationOf rotation_of, std::vector<int>* matches) {
  std::vector<std::vector<int>> histogram(static_cast<std::size_t>(bins));
  const double per_degree = bins / 360.0;
  for (std::size_t i = 0; i < matches->size(); ++i) {
    if ((*matches)[i] == kNoMatch) continue;
    double rotation = rotation_of(i);
    if (std::isnan(rotation)) continue;
    rotation = std::fmod(rotation, 360.0);
    if (rotation < 0.0) rotation += 360.0;
    int bin = static_cast<int>(std::lround(rotation * per_degree));
    if (bin >= bins) bin = 0;
    histogram[static_cast<std::size_t>(bin)].push_back(static_cast<int>(i));
  }
  std::array<int, 3> top = {-1, -1, -1};
  auto count = [&](int bin) {
    return bin < 0 ? 0 : static_cast<int>(histogram[static_cast<std::size_t>(bin)].size());
  };
  for (int bin = 0; bin < bins; ++bin) {
    if (count(bin) > count(top[0])) {
      top = {bin, top[0], top[1]};
    } else if (count(bin) > count(top[1])) {
      top = {top[0], bin, top[1]};
    } else if (count(bin) > count(top[2])) {
      top[2] = bin;
    }
  }
  // A rigid motion rotates all keypoints alike; the runners-up bins only survive when
  // they are not mere noise next to the winner.
  const int winner = count(top[0]);
  if (count(top[1]) < 0.1 * winner) top[1] = -1;
  if (count(top[2]) < 0.1 * winner) top[2] = -1;
  for (int bin = 0; bin < bins; ++bin) {
    if (bin == top[0] || bin == top[1] || bin == top[2]) continue;
    for (const int i : histogram[static_cast<std::size_t>(bin)]) {
      (*matches)[static_cast<std::size_t>(i)] = kNoMatch;
    }
  }
}

}  // namespace

void MatcherOptions::Check() const {
  CheckOptionFields(*this);
  RequireOption(loose_distance >= strict_distance, "Matcher.looseDistance",
                "must be in [Matcher.strictDistance, 256]");
}

void ReadSettings(const SettingsFile& file, MatcherOptions* options) {
  ReadOptionFields(file, options);
}

void FilterByRotationConsistency(const std::vector<cv::KeyPoint>& keypoints_a,
                                 const std::vector<cv::KeyPoint>& keypoints_b, int bins,
                                 std::vector<int>* matches_a_to_b) {
  KeepConsistentRotations(
      bins,
      [&](std::size_t i) {
        return static_cast<double>(
            keypoints_b[static_cast<std::size_t>((*matches_a_to_b)[i])].angle -
            keypoints_a[i].angle);
      },
      matches_a_to_b);
}

std::vector<int> MatchBruteForce(const std::vector<Descriptor>& a, const std::vector<Descriptor>& b,
                                 double ratio, int max_distance) {
  std::vector<Proposal> proposals;
  for (std::size_t i = 0; i < a.size(); ++i) {
    Nearest nearest;
    for (std::size_t j = 0; j < b.size(); ++j) {
      nearest.Offer(HammingDistance(a[i], b[j]), static_cast<int>(j), 0);
    }
    if (nearest.best <= max_distance && nearest.PassesRatio(ratio)) {
      proposals.push_back({static_cast<int>(i), nearest.index, nearest.best});
    }
  }
  return ResolveConflicts(std::move(proposals), a.size(), b.size());
}

std::vector<int> MatchInWindow(const ExtractedFeatures& a, const ExtractedFeatures& b,
                               const std::vector<Eigen::Vector2d>& predicted,
                               const MatcherOptions& options) {
  std::vector<Proposal> proposals;
  for (std::size_t i = 0; i < a.size(); ++i) {
    // Every level, each against its neighbours (the views share one scale, give or take
    // a level): level 0 alone left too few matches to keep a first view through a fast
    // turn with blur.
    const int level = a.keypoints[i].octave;
    if (!options.initialization_all_levels && level > 0) continue;
    const Eigen::Vector2d& p = predicted[i];
    Nearest nearest;
    const int min_level = options.initialization_all_levels ? std::max(0, level - 1) : 0;
    const int max_level = options.initialization_all_levels ? level + 1 : 0;
    for (const int j :
         b.grid.InArea(p.x(), p.y(), options.initialization_window, min_level, max_level)) {
      nearest.Offer(HammingDistance(a.descriptors[i], b.descriptors[static_cast<std::size_t>(j)]),
                    j, 0);
    }
    if (nearest.best <= options.strict_distance &&
        nearest.PassesRatio(options.initialization_ratio)) {
      proposals.push_back({static_cast<int>(i), nearest.index, nearest.best});
    }
  }
  std::vector<int> matches = ResolveConflicts(std::move(proposals), a.size(), b.size());
  if (options.check_orientation) {
    FilterByRotationConsistency(a.keypoints, b.keypoints, options.orientation_bins, &matches);
  }
  return matches;
}

std::vector<int> SearchByProjection(const ExtractedFeatures& frame,
                                    const std::vector<ProjectedPoint>& points,
                                    const std::vector<bool>* taken, double ratio, int max_distance,
                                    const MatcherOptions& options) {
  std::vector<Proposal> proposals;
  for (std::size_t q = 0; q < points.size(); ++q) {
    const ProjectedPoint& point = points[q];
    Nearest nearest;
    for (const int j : frame.grid.InArea(point.pixel.x(), point.pixel.y(), point.radius,
                                         point.min_level, point.max_level)) {
      if (taken != nullptr && (*taken)[static_cast<std::size_t>(j)]) continue;
      nearest.Offer(
          HammingDistance(point.descriptor, frame.descriptors[static_cast<std::size_t>(j)]), j,
          frame.keypoints[static_cast<std::size_t>(j)].octave);
    }
    if (nearest.best > max_distance) continue;
    // Two close candidates on the same level are ambiguous; on different levels they
    // are usually the same corner seen at two scales.
    if (ratio > 0.0 && nearest.best_level == nearest.second_level && !nearest.PassesRatio(ratio)) {
      continue;
    }
    proposals.push_back({static_cast<int>(q), nearest.index, nearest.best});
  }
  std::vector<int> matches = ResolveConflicts(std::move(proposals), points.size(), frame.size());
  if (options.check_orientation) {
    KeepConsistentRotations(
        options.orientation_bins,
        [&](std::size_t q) {
          if (points[q].source_angle < 0.0f) return std::nan("");
          return static_cast<double>(frame.keypoints[static_cast<std::size_t>(matches[q])].angle -
                                     points[q].source_angle);
        },
        &matches);
  }
  return matches;
}

std::vector<int> SearchByBow(const BowFeatures& a, const BowFeatures& b,
                             const MatcherOptions& options) {
  const std::size_t size_a = a.descriptors->size();
  const std::size_t size_b = b.descriptors->size();
  std::vector<Proposal> proposals;
  ForEachSharedNode(
      *a.feature_vector, *b.feature_vector,
      [&](NodeId, const std::vector<int>& in_a, const std::vector<int>& in_b) {
        for (const int i : in_a) {
          if (a.usable != nullptr && !(*a.usable)[static_cast<std::size_t>(i)]) {
            continue;
          }
          Nearest nearest;
          for (const int j : in_b) {
            if (b.usable != nullptr && !(*b.usable)[static_cast<std::size_t>(j)]) {
              continue;
            }
            nearest.Offer(HammingDistance((*a.descriptors)[static_cast<std::size_t>(i)],
                                          (*b.descriptors)[static_cast<std::size_t>(j)]),
                          j, 0);
          }
          if (nearest.best <= options.strict_distance && nearest.PassesRatio(options.bow_ratio)) {
            proposals.push_back({i, nearest.index, nearest.best});
          }
        }
      });
  std::vector<int> matches = ResolveConflicts(std::move(proposals), size_a, size_b);
  if (options.check_orientation && a.keypoints != nullptr && b.keypoints != nullptr) {
    FilterByRotationConsistency(*a.keypoints, *b.keypoints, options.orientation_bins, &matches);
  }
  return matches;
}

}  // namespace ocg
