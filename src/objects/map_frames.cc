#include "ocg/objects/map_frames.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <vector>

namespace ocg {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Same-class pairs tried as the two that fix a transform: all of them up to this many
// (a transform is tried per two pairs, each counting every pair of objects).
constexpr std::size_t kMaxPairs = 400;

// An object's class, centre and largest extent, in its map's gravity frame (z up) or
// world frame.
struct Placed {
  int class_id = 0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double extent = 0.0;
};

std::vector<Placed> Objects(const SavedObjectMap& map, bool gravity_frame) {
  const Eigen::Matrix3d R_wg = gravity_frame ? GravityFrame(map.up) : Eigen::Matrix3d::Identity();
  std::vector<Placed> placed;
  for (const ObjectRecord& record : map.objects)
    placed.push_back({record.class_id, R_wg.transpose() * record.cuboid.centre,
                      std::max(record.cuboid.size.maxCoeff(), 1e-6)});
  return placed;
}

// p -> scale * R_z(turn) * p + shift.
struct Similarity {
  double scale = 1.0;
  double turn = 0.0;
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
  Eigen::Vector3d operator*(const Eigen::Vector3d& p) const {
    return scale * (Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ()) * p) + shift;
  }
};

// How many of after's objects, moved by transform, are at the place of a before object
// of their class.
int SamePlace(const std::vector<Placed>& before, const std::vector<Placed>& after,
              const Similarity& transform, double factor) {
  int count = 0;
  for (const Placed& a : after) {
    const Eigen::Vector3d centre = transform * a.centre;
    for (const Placed& b : before) {
      if (b.class_id != a.class_id) continue;
      if ((centre - b.centre).norm() <= factor * std::max(b.extent, transform.scale * a.extent)) {
        ++count;
        break;
      }
    }
  }
  return count;
}

// The transform putting after's a1 and a2 on before's b1 and b2: scale and turn from the
// horizontal vectors between them, shift from the first pair. None when either pair of
// centres is one above the other.
std::optional<Similarity> FromTwoPairs(const Placed& a1, const Placed& a2, const Placed& b1,
                                       const Placed& b2) {
  const Eigen::Vector2d from = (a2.centre - a1.centre).head<2>();
  const Eigen::Vector2d to = (b2.centre - b1.centre).head<2>();
  if (from.norm() < 1e-9 || to.norm() < 1e-9) return std::nullopt;
  Similarity transform;
  transform.scale = to.norm() / from.norm();
  transform.turn = std::atan2(to.y(), to.x()) - std::atan2(from.y(), from.x());
  transform.shift =
      b1.centre -
      transform.scale * (Eigen::AngleAxisd(transform.turn, Eigen::Vector3d::UnitZ()) * a1.centre);
  return transform;
}

struct Aligned {
  Similarity transform;
  int same_place = 0;
};

Aligned BestAlignment(const std::vector<Placed>& before, const std::vector<Placed>& after,
                      double factor) {
  std::vector<std::pair<std::size_t, std::size_t>> pairs;  // (after, before), same class
  for (std::size_t a = 0; a < after.size(); ++a) {
    for (std::size_t b = 0; b < before.size(); ++b)
      if (after[a].class_id == before[b].class_id) pairs.emplace_back(a, b);
  }
  // Many objects of few classes: every stride-th pair, the same ones on every run.
  const std::size_t stride = (pairs.size() + kMaxPairs - 1) / kMaxPairs;
  std::vector<std::pair<std::size_t, std::size_t>> tried;
  for (std::size_t i = 0; i < pairs.size(); i += std::max<std::size_t>(stride, 1))
    tried.push_back(pairs[i]);
  Aligned best;
  for (std::size_t i = 0; i < tried.size(); ++i) {
    for (std::size_t j = i + 1; j < tried.size(); ++j) {
      const auto [a1, b1] = tried[i];
      const auto [a2, b2] = tried[j];
      if (a1 == a2 || b1 == b2) continue;
      const std::optional<Similarity> transform =
          FromTwoPairs(after[a1], after[a2], before[b1], before[b2]);
      if (!transform) continue;
      const int same_place = SamePlace(before, after, *transform, factor);
      if (same_place > best.same_place) best = {*transform, same_place};
    }
  }
  return best;
}

std::string Format(const char* format, double a, double b, double c) {
  char text[160];
  std::snprintf(text, sizeof(text), format, a, b, c);
  return text;
}

}  // namespace

void FrameCheckOptions::Check() const {
  if (!(same_place_factor > 0))
    throw std::invalid_argument("frame check: same_place_factor must be positive");
  if (min_aligned < 2) throw std::invalid_argument("frame check: min_aligned must be at least 2");
  if (!(aligned_ratio > 1)) throw std::invalid_argument("frame check: aligned_ratio must be > 1");
}

FrameCheck CheckOneFrame(const SavedObjectMap& before, const SavedObjectMap& after,
                         const FrameCheckOptions& options) {
  options.Check();
  FrameCheck check;
  if (before.run && after.run && ContinuesMapOf(*after.run, *before.run)) {
    check.evidence = "'" + after.run->folder + "' continued the map file '" +
                     after.run->map_loaded + "' that '" + before.run->folder +
                     "' saved (their run.json)";
    return check;
  }
  check.same_place_as_given = SamePlace(Objects(before, false), Objects(after, false), Similarity{},
                                        options.same_place_factor);
  const std::vector<Placed> before_g = Objects(before, true), after_g = Objects(after, true);
  const Aligned best = BestAlignment(before_g, after_g, options.same_place_factor);
  check.same_place_aligned = best.same_place;
  // The transform in world frames, to tell one near the identity.
  const Eigen::Matrix3d rotation =
      GravityFrame(before.up) *
      Eigen::AngleAxisd(best.transform.turn, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
      GravityFrame(after.up).transpose();
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double extent = 0.0;
  for (const Placed& object : after_g) {
    centroid += object.centre;
    extent += object.extent;
  }
  if (!after_g.empty()) {
    centroid /= static_cast<double>(after_g.size());
    extent /= static_cast<double>(after_g.size());
  }
  check.scale = best.transform.scale;
  check.turn = Eigen::AngleAxisd(rotation).angle();
  // How far the transform carries the later map's middle, in the world frames.
  check.shift =
      (GravityFrame(before.up) * (best.transform * centroid) - GravityFrame(after.up) * centroid)
          .norm();
  const bool near_identity = std::abs(check.scale - 1) <= 0.05 && check.turn <= 3 * kPi / 180 &&
                             check.shift <= std::max(extent, 1e-6);
  check.one_frame = near_identity || best.same_place < options.min_aligned ||
                    best.same_place < options.aligned_ratio * check.same_place_as_given;
  const std::string as_given = std::to_string(check.same_place_as_given) + " of " +
                               std::to_string(after.objects.size()) +
                               " objects of the later map stand where one of their class "
                               "stands in the earlier map as given";
  if (check.one_frame) {
    check.evidence =
        as_given + (near_identity
                        ? ", and the best transform found is the identity"
                        : "; no transform of the later map puts " +
                              std::to_string(std::max(
                                  options.min_aligned,
                                  static_cast<int>(std::ceil(options.aligned_ratio *
                                                             check.same_place_as_given)))) +
                              " there");
  } else {
    check.evidence =
        "only " + as_given + ", " + std::to_string(check.same_place_aligned) +
        Format(
            " once it is scaled by %.3f, turned %.1f degrees about up and shifted %.3f map "
            "units",
            check.scale, check.turn * 180 / kPi, check.shift);
  }
  return check;
}

}  // namespace ocg
