#include "ocg/objects/change_log.h"

#include <algorithm>
#include <iomanip>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "ocg/objects/assignment.h"

namespace ocg {
namespace {

// Two decimals, as a reader wants a distance in a sentence.
std::string Rounded(double value) {
  std::ostringstream text;
  text << std::fixed << std::setprecision(2) << value;
  return text.str();
}

// A removal and a same-class object that appeared since the removed one was last seen,
// as the pairing weighs them.
struct MoveCandidate {
  std::size_t removed = 0, appeared = 0;
  double relative = 0.0;                      // centre distance in larger extents
  std::optional<AppearanceMatch> appearance;  // when both have enough descriptors
  bool from_boxes = false;                    // appearance is the box appearance's
  std::optional<double> colour;               // ColourSimilarity, when both have a colour
};

// Below any difference of appearance that means something (a few matched points of
// tens): distance only decides among pairs that look alike, or have no appearance.
constexpr double kDistanceWeight = 1e-3;

double PairingCost(const MoveCandidate& candidate, const AppearanceOptions& options) {
  const double unlike = candidate.appearance ? 1.0 - candidate.appearance->Share() : 1.0;
  const double unlike_colour = candidate.colour ? 1.0 - *candidate.colour : 1.0;
  return unlike + options.colour_weight * unlike_colour + kDistanceWeight * candidate.relative;
}

// Colours that share next to nothing are two objects, not one carried, unless descriptors
// vouch for the pair: a share of them matched that colour could not outweigh (colour_weight;
// a texture ORB finds again is the stronger evidence). The pair stays among the evidence.
bool ColourRefuses(const MoveCandidate& candidate, const AppearanceOptions& options) {
  if (!candidate.colour || *candidate.colour >= options.min_colour_similarity) return false;
  return !candidate.appearance || candidate.appearance->Share() < options.colour_weight;
}

// Pairs removals with objects that appeared into moves, within a session and between
// sessions alike. A pair: the same class, the new object first seen after the removed one
// was last seen, not at the same place (context.moves.same_place_factor). Nothing bounds
// how far an object is carried, and two objects of one class can be carried past each
// other: the pairs are chosen together (SolveAssignment: as many pairs as the order
// allows, then least total cost), looking alike first, nearer second; not nearest first,
// which lets a near newcomer take the one removal whose times would also fit another.
std::vector<MoveLink> PairMoves(const std::vector<ObjectRecord>& removed,
                                const std::vector<ObjectRecord>& appeared,
                                const ChangeLogContext& context,
                                std::vector<MoveCandidate>* candidates) {
  const auto look_in = [&](const std::map<ObjectId, std::vector<Descriptor>>& looks,
                           ObjectId id) -> const std::vector<Descriptor>* {
    const auto found = looks.find(id);
    if (found == looks.end() ||
        static_cast<int>(found->second.size()) < context.appearance_options.min_points)
      return nullptr;
    return &found->second;
  };
  Eigen::MatrixXd cost =
      Eigen::MatrixXd::Constant(static_cast<Eigen::Index>(removed.size()),
                                static_cast<Eigen::Index>(appeared.size()), kForbiddenCost);
  for (std::size_t r = 0; r < removed.size(); ++r) {
    for (std::size_t a = 0; a < appeared.size(); ++a) {
      const ObjectRecord& from = removed[r];
      const ObjectRecord& to = appeared[a];
      if (from.class_id != to.class_id || !(to.first_seen > from.last_seen)) continue;
      MoveCandidate candidate{r, a, RelativeDistance(from, to), std::nullopt, false, std::nullopt};
      if (candidate.relative <= context.moves.same_place_factor) continue;
      // The box appearance holds far more of an object's texture than its map points.
      const std::vector<Descriptor>* from_look = look_in(context.box_appearance, from.id);
      const std::vector<Descriptor>* to_look = look_in(context.box_appearance, to.id);
      candidate.from_boxes = from_look != nullptr && to_look != nullptr;
      if (!candidate.from_boxes) {
        from_look = look_in(context.appearance, from.id);
        to_look = look_in(context.appearance, to.id);
      }
      // A removal's box appearance holds hundreds of descriptors: the share of them its
      // candidate shows weighs every candidate of a removal on one scale, where the
      // smaller set's share lets a spurious object with a handful, a few by chance alike,
      // look as much like it as its new place does.
      if (from_look != nullptr && to_look != nullptr)
        candidate.appearance =
            candidate.from_boxes
                ? MatchFrom(*from_look, *to_look, context.appearance_options.max_distance)
                : MatchAppearance(*from_look, *to_look, context.appearance_options.max_distance);
      candidate.colour = ColourSimilarityOf(context.colour, from.id, to.id);
      if (candidates != nullptr) candidates->push_back(candidate);
      if (ColourRefuses(candidate, context.appearance_options)) continue;
      cost(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(a)) =
          PairingCost(candidate, context.appearance_options);
    }
  }
  std::vector<MoveLink> moves;
  if (removed.empty() || appeared.empty()) return moves;
  const std::vector<int> assigned = SolveAssignment(cost);
  for (std::size_t r = 0; r < removed.size(); ++r) {
    if (assigned[r] < 0) continue;
    const auto a = static_cast<std::size_t>(assigned[r]);
    if (cost(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(a)) >= kForbiddenCost)
      continue;
    moves.push_back(
        {removed[r], appeared[a], (removed[r].cuboid.centre - appeared[a].cuboid.centre).norm()});
  }
  return moves;
}

// Whether two cuboids can share space: their centres nearer than the mean of their largest
// extents. Farther, they are two objects whatever their orientations (side by side, they
// touch at the mean of their extents along the line between them). The same place by
// same_place_factor (one larger extent) also takes a neighbour standing beside an object:
// two phones side by side, 0.15 apart, one of them estimated 0.09 long.
bool CouldOverlap(const ObjectRecord& a, const ObjectRecord& b) {
  return (a.cuboid.centre - b.cuboid.centre).norm() <
         0.5 * (a.cuboid.size.maxCoeff() + b.cuboid.size.maxCoeff());
}

// times[id] (SeenAsClass's), else fallback.
double TimeOr(const std::map<ObjectId, double>& times, ObjectId id, double fallback) {
  const auto found = times.find(id);
  return found != times.end() ? found->second : fallback;
}

}  // namespace

std::optional<double> ColourSimilarityOf(const std::map<ObjectId, ColourHistogram>& colours,
                                         ObjectId a, ObjectId b) {
  const auto colour_a = colours.find(a);
  const auto colour_b = colours.find(b);
  if (colour_a == colours.end() || colour_b == colours.end()) return std::nullopt;
  return ColourSimilarity(colour_a->second, colour_b->second);
}

AppearanceMatch MatchAppearance(const std::vector<Descriptor>& a, const std::vector<Descriptor>& b,
                                int max_distance) {
  return a.size() <= b.size() ? MatchFrom(a, b, max_distance) : MatchFrom(b, a, max_distance);
}

AppearanceMatch MatchFrom(const std::vector<Descriptor>& from, const std::vector<Descriptor>& to,
                          int max_distance) {
  AppearanceMatch match;
  match.compared = static_cast<int>(from.size());
  std::vector<int> nearest;
  for (const Descriptor& descriptor : from) {
    int best = kDescriptorBits;
    for (const Descriptor& other : to) best = std::min(best, HammingDistance(descriptor, other));
    if (best <= max_distance) ++match.matched;
    nearest.push_back(best);
  }
  if (!nearest.empty()) {
    std::nth_element(nearest.begin(), nearest.begin() + nearest.size() / 2, nearest.end());
    match.median_distance = nearest[nearest.size() / 2];
  }
  return match;
}

void AppearanceOptions::Check() const {
  if (max_distance < 0 || max_distance > kDescriptorBits)
    throw std::invalid_argument("appearance.max_distance must be in [0, 256] bits");
  if (min_points < 1) throw std::invalid_argument("appearance.min_points must be at least 1");
  if (!(colour_weight >= 0.0))
    throw std::invalid_argument("appearance.colour_weight must be at least 0");
  if (min_colour_signatures < 1)
    throw std::invalid_argument("appearance.min_colour_signatures must be at least 1");
  if (!(min_colour_similarity >= 0.0 && min_colour_similarity <= 1.0))
    throw std::invalid_argument("appearance.min_colour_similarity must be in [0, 1]");
}

std::vector<ChangeEntry> ReviseChangeLog(const std::vector<ObjectChange>& changes,
                                         const std::vector<ObjectRecord>& live,
                                         const ChangeLogContext& context) {
  // Each removal is paired once, by the session that made it: an earlier session's
  // removals were paired when that session wrote its changes.json, and pairing them again
  // against a later map linked them to what the later session found (they stay removals
  // here). This session's removals of objects it saw pair by the in-session rule; those of
  // objects last seen in an earlier session by the between-session rule.
  std::vector<ObjectRecord> seen_now, seen_before;
  const std::vector<ChangeEntry> own = EntriesOf(changes);
  // A removal undone by a restore (the object found again at its place) moved nowhere.
  const std::vector<bool> standing = StandingRemovals(own);
  for (std::size_t i = 0; i < own.size(); ++i) {
    const ChangeEntry& entry = own[i];
    if (entry.type != "removed" || !standing[i] || entry.session != context.session) continue;
    ObjectRecord record;
    record.id = entry.object_id;
    record.class_id = entry.class_id;
    record.cuboid = entry.cuboid;
    record.last_seen = entry.last_seen.value_or(entry.timestamp);
    // Nor did one whose place holds a live object of its class (a duplicate removed beside
    // the object it doubled, an object re-created where it stands): it is still there.
    // Not a neighbour of its class standing beside it (two phones side by side).
    const bool still_there = std::any_of(live.begin(), live.end(), [&](const ObjectRecord& o) {
      return o.class_id == record.class_id && CouldOverlap(o, record);
    });
    if (still_there) continue;
    const bool earlier = context.session > 0 && record.last_seen < context.session_start;
    (earlier ? seen_before : seen_now).push_back(record);
  }
  std::map<ObjectId, MoveLink> moves_from;
  std::set<ObjectId> moved_to;
  std::set<ObjectId> between_sessions;  // moves_from's keys linked by the between-session rule
  context.appearance_options.Check();
  context.moves.Check();
  std::vector<ObjectRecord> appeared;
  for (const ObjectRecord& object : live) {
    if (object.first_session == context.session) appeared.push_back(object);
  }
  std::vector<MoveCandidate> candidates;
  for (const MoveLink& move : PairMoves(seen_before, appeared, context, &candidates)) {
    moves_from.emplace(move.from.id, move);
    moved_to.insert(move.to.id);
    between_sessions.insert(move.from.id);
  }
  // The evidence of a between-session removal: every same-class object it could have
  // become, how far and how alike.
  std::map<ObjectId, std::vector<PairingCandidate>> alternatives;
  // (from, to): the appearance evidence of the pair.
  std::map<std::pair<ObjectId, ObjectId>, PairingLook> looks;
  for (const MoveCandidate& candidate : candidates) {
    const ObjectRecord& from = seen_before[candidate.removed];
    const ObjectRecord& to = appeared[candidate.appeared];
    PairingCandidate evidence{to.id, (from.cuboid.centre - to.cuboid.centre).norm(),
                              to.observations, std::nullopt};
    if (candidate.appearance || candidate.colour) {
      evidence.appearance = PairingLook{
          candidate.appearance, candidate.appearance && candidate.from_boxes, candidate.colour};
      looks[{from.id, to.id}] = *evidence.appearance;
    }
    alternatives[from.id].push_back(evidence);
  }
  // In a session, ordered by when each was seen as its class; entries keep their times.
  std::vector<ObjectRecord> removed_as_class = seen_now, rest_live, rest_as_class;
  for (ObjectRecord& record : removed_as_class)
    record.last_seen = TimeOr(context.seen_as_class.last, record.id, record.last_seen);
  for (const ObjectRecord& object : live) {
    if (moved_to.count(object.id) > 0) continue;
    rest_live.push_back(object);
    rest_as_class.push_back(object);
    rest_as_class.back().first_seen =
        TimeOr(context.seen_as_class.first, object.id, object.first_seen);
  }
  const auto original = [](const std::vector<ObjectRecord>& records, ObjectId id) {
    return *std::find_if(records.begin(), records.end(),
                         [id](const ObjectRecord& record) { return record.id == id; });
  };
  for (const MoveLink& move : PairMoves(removed_as_class, rest_as_class, context, nullptr)) {
    moves_from.emplace(move.from.id, MoveLink{original(seen_now, move.from.id),
                                              original(rest_live, move.to.id), move.distance});
    moved_to.insert(move.to.id);
  }
  std::vector<ChangeEntry> revised;
  // Entries kept from a loaded map carry their own session; their clock was another
  // session's, so they get no time.
  const auto stamp = [&](ChangeEntry entry) {
    entry.time = entry.session == context.session
                     ? std::optional<double>(entry.timestamp - context.session_start)
                     : std::nullopt;
    revised.push_back(std::move(entry));
  };
  // The earlier sessions' entries as they revised them: what this session's object map
  // says of them would lose their moves and additions.
  if (context.earlier_changes) {
    for (const ChangeEntry& entry : *context.earlier_changes) {
      if (entry.session < context.session) stamp(entry);
    }
  }
  for (ChangeEntry entry : own) {
    if (context.earlier_changes && entry.session < context.session) continue;
    const auto move = entry.type == "removed" ? moves_from.find(entry.object_id) : moves_from.end();
    if (move != moves_from.end()) {
      const ObjectRecord& to = move->second.to;
      entry.type = "moved";
      entry.reason = between_sessions.count(move->first) > 0
                         ? "removed from its place, last seen before session " +
                               std::to_string(context.session) +
                               "; same class first seen in session " +
                               std::to_string(context.session) + ", " +
                               Rounded(move->second.distance) + " away (map units)"
                         : "removed here; same class first seen after its last sighting, " +
                               Rounded(move->second.distance) + " away (map units)";
      entry.to = MoveDestination{to.id, to.cuboid, to.first_seen};
      entry.distance = move->second.distance;
      const auto look = looks.find({move->first, to.id});
      if (look != looks.end()) entry.appearance = look->second;
    }
    if (entry.type == "removed" || entry.type == "moved") {
      const auto evidence = alternatives.find(entry.object_id);
      if (evidence != alternatives.end() && entry.session == context.session)
        entry.candidates = evidence->second;
    }
    stamp(std::move(entry));
  }
  if (context.session > 0) {
    for (const ObjectRecord& object : live) {
      if (object.first_session != context.session || moved_to.count(object.id) > 0) continue;
      ChangeEntry added;
      added.type = "added";
      added.session = context.session;
      added.timestamp = object.first_seen;
      added.object_id = object.id;
      added.class_id = object.class_id;
      added.cuboid = object.cuboid;
      added.reason = "first seen in session " + std::to_string(context.session);
      stamp(std::move(added));
    }
  }
  return revised;
}

}  // namespace ocg
