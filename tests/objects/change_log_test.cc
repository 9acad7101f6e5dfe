// changes.json revised: moves linked, additions of a later session, session and time.

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>

#include "ocg/io/text_lines.h"
#include "ocg/objects/box_appearance.h"
#include "ocg/objects/change_log.h"
#include "ocg/objects/object_map.h"
#include "ocg/objects/session_appearance.h"

namespace ocg {
namespace {

constexpr int kCup = 41, kBook = 73, kMouse = 64;

ObjectChange Removed(ObjectId id, int class_id, double x, double removed_at, double last_seen) {
  ObjectChange change;
  change.type = "removed";
  change.object_id = id;
  change.class_id = class_id;
  change.timestamp = removed_at;
  change.last_seen = last_seen;
  change.cuboid.centre = Eigen::Vector3d(x, 0, 0.8);
  change.cuboid.size = Eigen::Vector3d(0.1, 0.1, 0.1);
  change.sightings = 20;
  return change;
}

ObjectRecord Live(ObjectId id, int class_id, double x, double first_seen, int first_session = 0) {
  ObjectRecord record;
  record.id = id;
  record.class_id = class_id;
  record.cuboid.centre = Eigen::Vector3d(x, 0, 0.8);
  record.cuboid.size = Eigen::Vector3d(0.1, 0.1, 0.1);
  record.first_seen = first_seen;
  record.last_seen = first_seen + 5;
  record.first_session = first_session;
  return record;
}

using Changes = std::vector<ObjectChange>;
using Objects = std::vector<ObjectRecord>;

// changes.json of the revised log.
nlohmann::json Revise(const Changes& changes, const Objects& live,
                      const ChangeLogContext& context) {
  return nlohmann::json::parse(ChangeLogJson(ReviseChangeLog(changes, live, context)));
}

// A cup removed at x = 0 and a cup that appeared at x = 0.4 after the first one's last
// sighting; a book removed with no book near; a merged duplicate; a mouse first seen at
// 1025 and a cup seen since 900 (in session 0).
struct Log {
  Changes changes;
  Objects objects;
};
// Every change made in the given session.
Log Constructed(int session = 0) {
  ObjectChange merged = Removed(5, kCup, 2.0, 1012, 1011);
  merged.type = "merged";
  merged.merged_into = 11;
  std::vector<ObjectChange> list = {Removed(3, kCup, 0.0, 1030, 1010),
                                    Removed(4, kBook, 1.0, 1031, 1012), merged};
  for (ObjectChange& change : list) change.session = session;
  return {list,
          {Live(9, kCup, 0.4, 1020, session), Live(10, kMouse, -1.0, 1025, session),
           Live(11, kCup, 2.0, 900)}};
}

TEST(ChangeLog, AMoveIsOneEntryWithBothObjectsAndEveryEntryHasSessionAndTime) {
  const Log log = Constructed();
  ChangeLogContext context;
  context.session_start = 1000;
  const nlohmann::json revised = Revise(log.changes, log.objects, context);
  const nlohmann::json& changes = revised.at("changes");
  ASSERT_EQ(changes.size(), 3u) << revised.dump(1);  // no additions in a first session
  const nlohmann::json& move = changes[0];
  EXPECT_EQ(move["type"], "moved");
  EXPECT_EQ(move["object_id"], 3);
  EXPECT_EQ(move["cuboid"]["centre"][0], 0.0);  // from
  EXPECT_EQ(move["to"]["object_id"], 9);
  EXPECT_EQ(move["to"]["cuboid"]["centre"][0], 0.4);
  EXPECT_NEAR(move["distance"].get<double>(), 0.4, 1e-12);
  EXPECT_EQ(changes[1]["type"], "removed");  // nothing of its class near
  EXPECT_EQ(changes[1]["object_id"], 4);
  EXPECT_EQ(changes[2]["type"], "merged");
  for (const nlohmann::json& entry : changes) {
    EXPECT_EQ(entry["session"], 0);
    EXPECT_NEAR(entry["time"].get<double>(), entry["timestamp"].get<double>() - 1000, 1e-9);
  }
  EXPECT_NEAR(move["time"].get<double>(), 30.0, 1e-9);
}

TEST(ChangeLog, ALaterSessionAddsWhatItFirstSawThatIsNoMove) {
  const Log log = Constructed(1);
  ChangeLogContext context;
  context.session = 1;
  context.session_start = 1015;
  const nlohmann::json changes = Revise(log.changes, log.objects, context).at("changes");
  std::vector<ObjectId> added;
  for (const nlohmann::json& entry : changes) {
    EXPECT_EQ(entry["session"], 1);
    EXPECT_FALSE(entry["time"].is_null());
    if (entry["type"] == "added") added.push_back(entry["object_id"].get<ObjectId>());
  }
  // The mouse; not the cup the move went to (1020), nor the one seen since 900.
  EXPECT_EQ(added, std::vector<ObjectId>{10});
  EXPECT_EQ(changes[0]["type"], "moved");
}

// A map file keeps the change log: what session 0 removed stays session 0's, with no time
// on session 1's clock.
TEST(ChangeLog, ChangesOfAnEarlierSessionKeepTheirSession) {
  const Log log = Constructed(0);
  ChangeLogContext context;
  context.session = 1;
  context.session_start = 5000;
  const nlohmann::json changes = Revise(log.changes, log.objects, context).at("changes");
  int earlier = 0;
  for (const nlohmann::json& entry : changes) {
    if (entry["type"] == "added") {
      EXPECT_EQ(entry["session"], 1);
      continue;
    }
    ++earlier;
    EXPECT_EQ(entry["session"], 0);
    EXPECT_TRUE(entry["time"].is_null());
  }
  EXPECT_EQ(earlier, 3);
}

// Between visits an object may have been carried anywhere: a cup last seen in session 0,
// removed in session 1, and a cup first seen in session 1 across the room (30 extents
// away) are one move (within a session too: InASessionAMoveHasNoReach).
TEST(ChangeLog, BetweenSessionsAMoveHasNoDistanceLimit) {
  ObjectChange gone = Removed(3, kCup, 0.0, 2010, 1010);
  gone.session = 1;
  const Changes changes{gone};
  const Objects objects = Objects{Live(9, kCup, 3.0, 2005, 1)};
  ChangeLogContext context;
  context.session = 1;
  context.session_start = 2000;
  nlohmann::json revised = Revise(changes, objects, context);
  ASSERT_EQ(revised["changes"].size(), 1u) << revised.dump(1);
  EXPECT_EQ(revised["changes"][0]["type"], "moved");
  EXPECT_EQ(revised["changes"][0]["to"]["object_id"], 9);
}

// A move's reason says which rule linked it: between sessions, where the object was last
// seen, where its new place was found and how far it is.
TEST(ChangeLog, AMoveBetweenSessionsSaysWhatHappened) {
  ObjectChange gone = Removed(3, kCup, 0.0, 2010, 1010);
  gone.session = 1;
  ObjectChange here = Removed(4, kBook, 5.0, 2020, 2008);
  here.session = 1;
  const Objects objects = Objects{Live(9, kCup, 3.0, 2005, 1), Live(12, kBook, 5.4, 2012, 1)};
  ChangeLogContext context;
  context.session = 1;
  context.session_start = 2000;
  const nlohmann::json changes = Revise(Changes{gone, here}, objects, context)["changes"];
  ASSERT_EQ(changes.size(), 2u) << changes.dump(1);
  EXPECT_EQ(changes[0]["type"], "moved");
  EXPECT_EQ(changes[0]["reason"],
            "removed from its place, last seen before session 1; same class first seen in "
            "session 1, 3.00 away (map units)");
  EXPECT_EQ(changes[1]["type"], "moved");  // the book: seen in session 1, in-session rule
  EXPECT_EQ(changes[1]["reason"],
            "removed here; same class first seen after its last sighting, 0.40 away (map units)");
}

// A removal is paired by the session that made it, once. Session 0 removed a cup (no move
// then); session 1 finds a cup 0.4 m away, first seen after the removed one's last
// sighting. The in-session rule would link them, but session 1 did not remove that cup:
// it stays session 0's removal, and the new cup is an addition of session 1.
TEST(ChangeLog, AnEarlierSessionsRemovalIsNotPairedAgain) {
  const Changes changes{Removed(3, kCup, 0.0, 1030, 1010)};
  const Objects objects = Objects{Live(9, kCup, 0.4, 5005, 1)};
  ChangeLogContext context;
  context.session = 1;
  context.session_start = 5000;
  const nlohmann::json changes_1 = Revise(changes, objects, context)["changes"];
  ASSERT_EQ(changes_1.size(), 2u) << changes_1.dump(1);
  EXPECT_EQ(changes_1[0]["type"], "removed");
  EXPECT_EQ(changes_1[0]["session"], 0);
  EXPECT_EQ(changes_1[1]["type"], "added");
  EXPECT_EQ(changes_1[1]["object_id"], 9);
  // Session 0's own revision (its live cup first seen at 1020) still links its removal.
  const Objects objects_0 = Objects{Live(9, kCup, 0.4, 1020, 0)};
  ChangeLogContext first;
  first.session_start = 1000;
  EXPECT_EQ(Revise(changes, objects_0, first)["changes"][0]["type"], "moved");
}

TEST(ChangeLog, SeenTogetherIsNoMove) {
  // The nearby cup was first seen while the removed one was still seen: a neighbour.
  const Changes changes{Removed(3, kCup, 0.0, 1030, 1010)};
  const Objects objects = Objects{Live(9, kCup, 0.4, 1005)};
  const nlohmann::json revised = Revise(changes, objects, {});
  EXPECT_EQ(revised["changes"][0]["type"], "removed");
}

// Within a session: a cup removed at 1050, last seen as a cup at 1021 (a false box of
// another class at its emptied place joined it at 1040: its entry's last_seen), and the
// objects that appeared since, as SeenAsClass orders them.
struct InSessionMove {
  Changes changes{Removed(3, kCup, 0.0, 1050, 1040)};
  ChangeLogContext context = [] {
    ChangeLogContext context;
    context.session_start = 1000;
    context.seen_as_class.last[3] = 1021;
    return context;
  }();
  // The revised entry of the removal.
  nlohmann::json Entry(const Objects& live) const {
    return Revise(changes, live, context).at("changes").at(0);
  }
};

TEST(ChangeLog, InASessionANewPlaceSeenBeforeTheRemovalIsAMove) {
  InSessionMove log;
  // First seen at 1033: after the cup was last seen as a cup, before the box of another
  // class that joined it, before the removal.
  log.context.seen_as_class.first[9] = 1034;  // its first box as a cup; the entry keeps 1033
  const nlohmann::json move = log.Entry({Live(9, kCup, 0.4, 1033)});
  EXPECT_EQ(move["type"], "moved");
  EXPECT_EQ(move["to"]["object_id"], 9);
  EXPECT_EQ(move["to"]["first_seen"], 1033);
  log.context.seen_as_class.last.clear();  // by last_seen alone: the box of another class
  EXPECT_EQ(log.Entry({Live(9, kCup, 0.4, 1033)})["type"], "removed");
}

TEST(ChangeLog, InASessionANewPlaceSeenAfterTheRemovalIsAMove) {
  const nlohmann::json move = InSessionMove().Entry({Live(9, kCup, 0.4, 1060)});
  EXPECT_EQ(move["type"], "moved");
  EXPECT_EQ(move["to"]["object_id"], 9);
}

TEST(ChangeLog, InASessionTheMoveGoesToTheObjectThatAppearedSinceNotToANeighbour) {
  InSessionMove log;
  // Cup 8 is nearer but was first seen as a cup before the removed one's last sighting as
  // a cup (its first box was another class's, at 1030): a neighbour. Of the two that
  // appeared since, the nearer.
  log.context.seen_as_class.first[8] = 1015;
  const nlohmann::json move =
      log.Entry({Live(8, kCup, 0.25, 1030), Live(9, kCup, 0.6, 1033), Live(10, kCup, 0.4, 1045)});
  EXPECT_EQ(move["type"], "moved");
  EXPECT_EQ(move["to"]["object_id"], 10);
}

// Within a session nothing bounds how far an object is carried either: a cup taken across
// the table (1.7 m, 17 of its extents) is a move.
TEST(ChangeLog, InASessionAMoveHasNoReach) {
  const nlohmann::json move = InSessionMove().Entry({Live(9, kCup, 1.7, 1060)});
  EXPECT_EQ(move["type"], "moved");
  EXPECT_EQ(move["to"]["object_id"], 9);
  EXPECT_NEAR(move["distance"].get<double>(), 1.7, 1e-9);
}

// Two cups carried past each other within a session: cup 3 (at x = 0, last seen 1021)
// went to x = 0.75, first seen at 1030, while cup 4 (at x = 0.9) was still seen (until
// 1040); cup 4 then went to x = 0.3, first seen at 1060. The nearest pair (3 to the cup
// at 0.3) would leave cup 4 no object that appeared after its last sighting: the pairs are
// chosen together, as many as the times allow.
TEST(ChangeLog, InASessionObjectsCarriedPastEachOtherPairByTheirTimes) {
  InSessionMove log;
  log.changes.push_back(Removed(4, kCup, 0.9, 1055, 1040));
  const nlohmann::json changes =
      Revise(log.changes, {Live(9, kCup, 0.75, 1030), Live(10, kCup, 0.3, 1060)}, log.context)
          .at("changes");
  ASSERT_EQ(changes.size(), 2u) << changes.dump(1);
  EXPECT_EQ(changes[0]["type"], "moved");
  EXPECT_EQ(changes[0]["to"]["object_id"], 9);
  EXPECT_EQ(changes[1]["type"], "moved");
  EXPECT_EQ(changes[1]["to"]["object_id"], 10);
}

// A cup carried (3, red) and a cup taken away (4, green), in one session; cup 9 (blue,
// first seen while 4 was still seen) and cup 10 (red, seen after both) appeared. As many
// pairs as the times allow would give 3 to 9 and 4 to 10 (round_2, seed 1: a cell phone
// taken away took the new place of one carried); colours that share nothing refuse both
// pairs, and 3 goes to 10.
TEST(ChangeLog, InASessionColoursThatShareNothingAreNoMove) {
  InSessionMove log;
  log.changes.push_back(Removed(4, kCup, 2.0, 1052, 1045));
  log.context.seen_as_class.last[4] = 1045;
  const Objects live = {Live(9, kCup, 3.0, 1030), Live(10, kCup, 1.0, 1060)};
  const auto moves = [&](const ChangeLogContext& context) {
    std::map<ObjectId, ObjectId> to;
    const nlohmann::json revised = Revise(log.changes, live, context);
    for (const nlohmann::json& entry : revised.at("changes"))
      if (entry["type"] == "moved")
        to[entry["object_id"].get<ObjectId>()] = entry["to"]["object_id"].get<ObjectId>();
    return to;
  };
  EXPECT_EQ(moves(log.context), (std::map<ObjectId, ObjectId>{{3, 9}, {4, 10}}));
  const auto colour = [](std::size_t bin, std::size_t other_bin, float other_share) {
    ColourHistogram histogram{};
    histogram[bin] = 1.0f - other_share;
    histogram[other_bin] += other_share;
    return histogram;
  };
  log.context.colour = {{3, colour(0, 1, 0.0f)},
                        {4, colour(4, 5, 0.0f)},
                        {9, colour(8, 9, 0.1f)},
                        {10, colour(0, 1, 0.2f)}};
  EXPECT_EQ(moves(log.context), (std::map<ObjectId, ObjectId>{{3, 10}}));
  // Colour weighed without the refusal does not do it: the count of pairs comes first.
  ChangeLogContext weighed_only = log.context;
  weighed_only.appearance_options.min_colour_similarity = 0.0;
  EXPECT_EQ(moves(weighed_only), (std::map<ObjectId, ObjectId>{{3, 9}, {4, 10}}));
  // Descriptors that vouch for a pair keep it whatever the colours say.
  log.context.appearance = {
      {3, {Descriptor{}, Descriptor{}, Descriptor{}, Descriptor{}, Descriptor{}}},
      {9, {Descriptor{}, Descriptor{}, Descriptor{}, Descriptor{}, Descriptor{}}}};
  EXPECT_EQ(moves(log.context), (std::map<ObjectId, ObjectId>{{3, 9}}));
}

// A removal whose place still holds a live object of its class moved nowhere: a duplicate
// of a mouse removed beside it (straight_1, seed 12) took the new place of a mouse carried
// from elsewhere, whose removal then stayed a removal.
TEST(ChangeLog, ARemovalWhosePlaceHoldsAnObjectOfItsClassIsNoMove) {
  InSessionMove log;
  log.changes.push_back(Removed(4, kCup, 1.0, 1055, 1021));  // cup 4: doubled cup 8
  const nlohmann::json changes =
      Revise(log.changes, {Live(8, kCup, 1.05, 1000), Live(9, kCup, 0.6, 1060)}, log.context)
          .at("changes");
  ASSERT_EQ(changes.size(), 2u) << changes.dump(1);
  EXPECT_EQ(changes[0]["type"], "moved");  // cup 3, carried 0.6 away (cup 4 is nearer)
  EXPECT_EQ(changes[0]["to"]["object_id"], 9);
  EXPECT_EQ(changes[1]["type"], "removed");
}

// A neighbour of its class standing beside the removed cup (their cuboids touch, one
// larger extent apart: a smaller cup whose centre is 0.1 from the removed one's) does not
// hold its place: the removal is the move to the cup that appeared 1 away. A cup whose
// cuboid overlaps the place (0.07 away, same size) still does.
TEST(ChangeLog, ANeighbourOfItsClassBesideARemovalDoesNotHoldItsPlace) {
  InSessionMove log;
  ObjectRecord neighbour = Live(7, kCup, 0.1, 900);
  neighbour.cuboid.size = Eigen::Vector3d(0.06, 0.06, 0.06);
  const nlohmann::json move = log.Entry({neighbour, Live(9, kCup, 1.0, 1060)});
  EXPECT_EQ(move["type"], "moved") << move.dump(1);
  EXPECT_EQ(move["to"]["object_id"], 9);
  EXPECT_EQ(log.Entry({Live(7, kCup, 0.07, 900), Live(9, kCup, 1.0, 1060)})["type"], "removed");
}

// A cup seen at its place until 1020.6 is carried across the room at 1022; a stray cup
// box at the new place at 1020.2 (another object's, called a cup) joins the cup that
// comes there, seen from 1022.5 on. The pairing's times are supported ones (the second
// box, the second last): the newcomer was seen after the cup left, a move (by every box's
// time it was seen first, and the cup stayed a removal).
TEST(ChangeLog, OneStrayBoxAtTheNewPlaceDoesNotDateTheNewcomer) {
  std::map<ObjectId, MapObject> live, removed;
  const auto sight = [](MapObject* object, double time) {
    ObjectSighting sighting;
    sighting.frame = static_cast<std::int64_t>(std::lround((time - 1000) * 10));
    sighting.class_id = kCup;
    sighting.timestamp = time;
    object->sightings.Add(sighting, 0);
  };
  MapObject& gone = removed[5];
  gone.id = 5;
  gone.class_id = kCup;
  for (double time = 1010.0; time < 1020.65; time += 0.1) sight(&gone, time);
  MapObject& newcomer = live[9];
  newcomer.id = 9;
  newcomer.class_id = kCup;
  sight(&newcomer, 1020.2);
  for (double time = 1022.5; time < 1048; time += 0.1) sight(&newcomer, time);
  ChangeLogContext context;
  context.session_start = 1000;
  context.seen_as_class = SeenAsClassIn(SessionObjects{live, removed, 0, 0});
  const nlohmann::json move =
      Revise({Removed(5, kCup, 0.0, 1054, 1020.6)}, {Live(9, kCup, 1.27, 1020.2)}, context)
          .at("changes")
          .at(0);
  EXPECT_EQ(move["type"], "moved") << move.dump(1);
  EXPECT_EQ(move["to"]["object_id"], 9);
}

TEST(ChangeLog, InASessionAnObjectOfAnotherClassIsNoMove) {
  EXPECT_EQ(InSessionMove().Entry({Live(9, kBook, 0.4, 1033)})["type"], "removed");
}

// A removal undone by a restore (the object found again at its own place, live with its
// id): it went nowhere, so the cup that appeared across the room in the same session is
// an addition, not where it moved to (issue 19's between-session link must not take it).
TEST(ChangeLog, ARestoredRemovalIsNoMove) {
  ObjectChange gone = Removed(3, kCup, 0.0, 2010, 1010);
  gone.session = 1;
  ObjectChange back = Removed(3, kCup, 0.0, 2020, 1010);
  back.type = "restored";
  back.recreated_as = 12;
  back.removed_at = 2010;
  back.session = 1;
  const Objects objects = Objects{Live(3, kCup, 0.0, 900, 0), Live(9, kCup, 3.0, 2005, 1)};
  ChangeLogContext context;
  context.session = 1;
  context.session_start = 2000;
  // Without the restore, cup 3 is not live at its place: a move.
  const nlohmann::json changes = Revise(Changes{gone}, Objects{objects[1]}, context).at("changes");
  ASSERT_EQ(changes[0]["type"], "moved") << "without the restore, the case is a move";
  const nlohmann::json revised = Revise(Changes{gone, back}, objects, context).at("changes");
  ASSERT_EQ(revised.size(), 3u) << revised.dump(1);
  EXPECT_EQ(revised[0]["type"], "removed");
  EXPECT_EQ(revised[1]["type"], "restored");
  EXPECT_EQ(revised[1]["recreated_as"], 12);
  EXPECT_EQ(revised[1]["reason"], "detected again at its place");
  EXPECT_EQ(revised[2]["type"], "added");
  EXPECT_EQ(revised[2]["object_id"], 9);
}

// objects.json holding these live objects.
ChangeLogContext Session(int session, double start) {
  ChangeLogContext context;
  context.session = session;
  context.session_start = start;
  return context;
}

// Textures as ORB sees them: `count` random descriptors (seeded), and the same patches seen
// again from another view (a few bits flipped in each).
std::vector<Descriptor> Texture(std::uint64_t seed, int count) {
  std::mt19937_64 random(seed);
  std::vector<Descriptor> descriptors(static_cast<std::size_t>(count));
  for (Descriptor& descriptor : descriptors) {
    for (std::uint64_t& word : descriptor) word = random();
  }
  return descriptors;
}
std::vector<Descriptor> SeenAgain(std::vector<Descriptor> descriptors, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  for (Descriptor& descriptor : descriptors) {
    for (int flip = 0; flip < 12; ++flip) {
      const auto bit = static_cast<int>(random() % kDescriptorBits);
      descriptor[static_cast<std::size_t>(bit / 64)] ^= std::uint64_t{1} << (bit % 64);
    }
  }
  return descriptors;
}

// Session 1 removed cups 3 and 4 (last seen in session 0) and found cups 9 and 10, each
// 0.2 from the other's old place: carried past each other (pair 2's remotes and pair 3's
// cell phones of issue 19). Distance pairs them crosswise; their points' descriptors tell
// which is which.
TEST(ChangeLog, BetweenSessionsTwoObjectsOfAClassPairByAppearanceNotDistance) {
  std::vector<ObjectChange> gone = {Removed(3, kCup, 0.0, 2010, 1010),
                                    Removed(4, kCup, 1.0, 2011, 1010)};
  for (ObjectChange& change : gone) change.session = 1;
  const Objects objects = Objects{Live(9, kCup, 1.2, 2005, 1), Live(10, kCup, -0.2, 2006, 1)};
  ChangeLogContext context = Session(1, 2000);
  const auto moved_to = [&](const ChangeLogContext& with) {
    std::map<ObjectId, ObjectId> to;
    const nlohmann::json revised = Revise(gone, objects, with);
    for (const nlohmann::json& entry : revised.at("changes")) {
      if (entry["type"] == "moved")
        to[entry["object_id"].get<ObjectId>()] = entry["to"]["object_id"].get<ObjectId>();
    }
    return to;
  };
  EXPECT_EQ(moved_to(context), (std::map<ObjectId, ObjectId>{{3, 10}, {4, 9}}))
      << "without appearance, the nearer pairs";
  const std::vector<Descriptor> first = Texture(1, 30), second = Texture(2, 30);
  context.appearance = {
      {3, first}, {4, second}, {9, SeenAgain(first, 3)}, {10, SeenAgain(second, 4)}};
  EXPECT_EQ(moved_to(context), (std::map<ObjectId, ObjectId>{{3, 9}, {4, 10}}));
}

// A bowl last seen in session 0 is removed; session 1 found a spurious bowl (a few
// sightings, too few points for an appearance) 0.3 from its old place and the bowl itself,
// with its texture, 1.4 away. Nearest first gave the spurious one the move (pair 1 of issue
// 19); the one that looks like the removed bowl takes it, and the other is an addition.
TEST(ChangeLog, ASpuriousAdditionNearTheOldPlaceDoesNotTakeTheMove) {
  ObjectChange gone = Removed(3, kCup, 0.0, 2010, 1010);
  gone.session = 1;
  const Objects objects = Objects{Live(9, kCup, 0.3, 2005, 1), Live(10, kCup, 1.4, 2006, 1)};
  ChangeLogContext context = Session(1, 2000);
  const std::vector<Descriptor> texture = Texture(5, 25);
  context.appearance = {{3, texture}, {9, Texture(6, 3)}, {10, SeenAgain(texture, 7)}};
  const nlohmann::json changes = Revise(Changes{gone}, objects, context)["changes"];
  ASSERT_EQ(changes.size(), 2u) << changes.dump(1);
  EXPECT_EQ(changes[0]["type"], "moved");
  EXPECT_EQ(changes[0]["to"]["object_id"], 10);
  EXPECT_EQ(changes[0]["appearance"]["compared"], 25);
  EXPECT_EQ(changes[0]["appearance"]["matched"], 25);
  EXPECT_EQ(changes[1]["type"], "added");
  EXPECT_EQ(changes[1]["object_id"], 9);
  // Its evidence lists both: the spurious bowl without an appearance (3 descriptors).
  ASSERT_EQ(changes[0]["candidates"].size(), 2u);
  EXPECT_FALSE(changes[0]["candidates"][0].contains("appearance"));
}

TEST(ChangeLog, AppearanceMatchCountsTheSmallerSetsDescriptorsWithANearOne) {
  const std::vector<Descriptor> texture = Texture(8, 20);
  std::vector<Descriptor> half(texture.begin(), texture.begin() + 10);
  const std::vector<Descriptor> stranger = Texture(9, 10);
  half.insert(half.end(), stranger.begin(), stranger.end());
  const AppearanceMatch match = MatchAppearance(SeenAgain(texture, 10), half, 50);
  EXPECT_EQ(match.compared, 20);
  EXPECT_EQ(match.matched, 10);
  EXPECT_LE(MatchAppearance(SeenAgain(texture, 11), texture, 50).median_distance, 24)
      << "12 bits flipped in each";
  const AppearanceMatch strangers = MatchAppearance(texture, stranger, 50);
  EXPECT_EQ(strangers.matched, 0) << "random 256-bit descriptors are about 128 bits apart";
  EXPECT_GT(strangers.median_distance, 90);
  EXPECT_EQ(MatchAppearance(texture, {}, 50).compared, 0);
}

// A map file keeps the change log as the session that saved it revised it: the next
// session lists that session's move as a move (not as the plain removal the object map
// holds), with its reason, and no time on its own clock.
TEST(ChangeLog, AnEarlierSessionsMoveStaysAMove) {
  ObjectChange gone = Removed(3, kCup, 0.0, 2010, 1010);
  gone.session = 1;
  const Objects objects_1 = Objects{Live(9, kCup, 3.0, 2005, 1)};
  ChangeLogContext first = Session(1, 2000);
  const nlohmann::json log_1 = Revise(Changes{gone}, objects_1, first);
  ASSERT_EQ(log_1["changes"][0]["type"], "moved");
  // Session 2 removes cup 9 again (last seen in session 1) and finds nothing of its class.
  ObjectChange again = Removed(9, kCup, 3.0, 3010, 2030);
  again.session = 2;
  const Objects objects_2 = Objects{};
  ChangeLogContext second = Session(2, 3000);
  const Changes changes{gone, again};
  EXPECT_EQ(Revise(changes, objects_2, second)["changes"][0]["type"], "removed")
      << "without the saved log, the object map's removal";
  // As a map file keeps it: the text without times, read back.
  second.earlier_changes = ParseChangeLog(
      ChangeLogJson(ReviseChangeLog(Changes{gone}, objects_1, first), /*with_time=*/false),
      "log_1");
  const nlohmann::json revised = Revise(changes, objects_2, second)["changes"];
  ASSERT_EQ(revised.size(), 2u) << revised.dump(1);
  EXPECT_EQ(revised[0]["type"], "moved");
  EXPECT_EQ(revised[0]["session"], 1);
  EXPECT_EQ(revised[0]["to"]["object_id"], 9);
  EXPECT_EQ(revised[0]["reason"], log_1["changes"][0]["reason"]);
  EXPECT_TRUE(revised[0]["time"].is_null());
  EXPECT_EQ(revised[1]["type"], "removed");
  EXPECT_EQ(revised[1]["session"], 2);
  EXPECT_EQ(revised[1]["object_id"], 9);
}

// The log is written once, at the edge, and a map file's copy read back: every kind of
// entry (a move between sessions with its evidence, a restore, a merge, a drop, an
// addition) reads back as it was written, byte for byte; a key no entry has is an error
// naming it, not a field silently lost.
TEST(ChangeLog, TheWrittenLogReadsBackAsItWasWritten) {
  ObjectChange gone = Removed(3, kCup, 0.0, 2010, 1010);
  ObjectChange merged = Removed(5, kCup, 2.0, 2012, 2011);
  merged.type = "merged";
  merged.merged_into = 11;
  ObjectChange dropped = Removed(6, kBook, 1.0, 2013, 2012);
  dropped.type = "dropped";
  ObjectChange back = Removed(7, kMouse, -1.0, 2020, 2015);
  back.type = "restored";
  back.recreated_as = 12;
  back.removed_at = 2014;
  Changes changes = {gone, merged, dropped, Removed(7, kMouse, -1.0, 2014, 2013), back};
  for (ObjectChange& change : changes) change.session = 1;
  ChangeLogContext context = Session(1, 2000);
  const std::vector<Descriptor> texture = Texture(40, 20);
  context.appearance = {{3, texture}, {9, SeenAgain(texture, 41)}};
  const std::vector<ChangeEntry> entries = ReviseChangeLog(
      changes,
      {Live(9, kCup, 0.7, 2005, 1), Live(10, kCup, 3.0, 2006, 1), Live(14, kBook, 5, 2007, 1)},
      context);
  const std::string text = ChangeLogJson(entries, /*with_time=*/false);
  const nlohmann::json json = nlohmann::json::parse(text);
  ASSERT_EQ(json["changes"][0]["type"], "moved") << text;
  ASSERT_EQ(json["changes"][0]["candidates"].size(), 2u) << text;
  EXPECT_TRUE(json["changes"][0].contains("appearance"));
  EXPECT_EQ(json["changes"].back()["type"], "added");
  EXPECT_EQ(ChangeLogJson(ParseChangeLog(text, "log"), false), text);
  EXPECT_EQ(ChangeLogJson(ParseChangeLog(ChangeLogJson(entries), "log")), ChangeLogJson(entries));
  nlohmann::json extra = json;
  extra["changes"][2]["colour"] = "red";
  try {
    ParseChangeLog(extra.dump(), "log");
    ADD_FAILURE() << "an unknown key was read";
  } catch (const ParseError& error) {
    EXPECT_NE(std::string(error.what()).find("entry 2: unknown key \"colour\""), std::string::npos)
        << error.what();
  }
}

// Box appearance (box_appearance.h). A camera at the origin looking along +z; objects 0.2 m
// across at 2 or 2.5 m. Keypoints are placed on the pixels a patch of texture projects to.
struct Patch {
  double x = 0.0, depth = 2.0;  // world; pixels at y = 0
  std::vector<Descriptor> descriptors;
  std::optional<Eigen::Vector3d> point;  // the map point every keypoint of it holds
};
PinholeCamera LookingAlongZ() {
  PinholeCamera camera;
  camera.fx = camera.fy = 525.0;
  camera.cx = 319.5;
  camera.cy = 239.5;
  return camera;
}
KeyframeFeatures Keyframe(std::int64_t frame, const std::vector<Patch>& patches) {
  KeyframeFeatures keyframe;
  keyframe.frame = frame;
  const PinholeCamera camera = LookingAlongZ();
  for (const Patch& patch : patches) {
    for (const Descriptor& descriptor : patch.descriptors) {
      keyframe.pixels.push_back(
          camera.ProjectUndistorted(Eigen::Vector3d(patch.x, 0, patch.depth)));
      keyframe.descriptors.push_back(descriptor);
      keyframe.points.push_back(patch.point);
    }
  }
  return keyframe;
}
Cuboid CuboidAt(double x, double depth) {
  Cuboid cuboid;
  cuboid.centre = Eigen::Vector3d(x, 0, depth);
  cuboid.size = Eigen::Vector3d(0.2, 0.2, 0.2);
  return cuboid;
}
FrameBox BoxOf(std::int64_t frame, const Cuboid& cuboid) {
  return {frame, *ProjectCuboid(cuboid, Eigen::Matrix3d::Identity(), SE3(), LookingAlongZ())};
}

TEST(BoxAppearance, KeypointsInTheBoxesWithoutMapPointsOutsideTheCuboid) {
  const Cuboid cup = CuboidAt(0.0, 2.0);
  const std::vector<Descriptor> own = Texture(20, 10), untracked = Texture(21, 4),
                                wall = Texture(22, 6), beside = Texture(23, 5);
  KeyframeFeatureMap keyframes;
  keyframes[10] = Keyframe(10, {{0.0, 2.0, own, Eigen::Vector3d(0.0, 0.0, 1.95)},
                                {0.02, 2.0, untracked, std::nullopt},
                                {0.0, 2.0, wall, Eigen::Vector3d(0.0, 0.0, 4.0)},  // behind
                                {0.4, 2.0, beside, std::nullopt}});  // outside the box
  BoxAppearanceOptions options;
  // A box at frame 11, which is no keyframe, gives nothing.
  const std::vector<Descriptor> descriptors = BoxDescriptors(
      {BoxOf(10, cup), BoxOf(11, cup)}, cup, Eigen::Matrix3d::Identity(), keyframes, options);
  EXPECT_EQ(descriptors.size(), own.size() + untracked.size());
  EXPECT_EQ(MatchAppearance(descriptors, own, 0).matched, 10);
  EXPECT_EQ(MatchAppearance(descriptors, wall, 0).matched, 0);
  options.cuboid_margin = 10.0;  // the wall 2 m behind is within 10 extents
  EXPECT_EQ(
      BoxDescriptors({BoxOf(10, cup)}, cup, Eigen::Matrix3d::Identity(), keyframes, options).size(),
      own.size() + untracked.size() + wall.size());
}

TEST(BoxAppearance, APlaceShowsTheKeypointsInTheCuboidsProjection) {
  const std::vector<Descriptor> there = Texture(24, 8), elsewhere = Texture(25, 8);
  const KeyframeFeatures keyframe =
      Keyframe(10, {{-0.5, 2.0, there, std::nullopt}, {0.5, 2.0, elsewhere, std::nullopt}});
  const std::vector<Descriptor> place = PlaceDescriptors(
      CuboidAt(-0.5, 2.0), Eigen::Matrix3d::Identity(), LookingAlongZ(), {&keyframe}, {});
  EXPECT_EQ(place.size(), there.size());
  EXPECT_EQ(MatchAppearance(place, there, 0).matched, 8);
  // What the place showed is left out of an object's descriptors; the rest stays.
  std::vector<Descriptor> object = SeenAgain(there, 26);
  const std::vector<Descriptor> own = Texture(27, 5);
  object.insert(object.end(), own.begin(), own.end());
  const std::vector<Descriptor> kept = WithoutBackground(object, place, 50);
  EXPECT_EQ(kept.size(), own.size());
  EXPECT_EQ(MatchAppearance(kept, own, 0).matched, 5);
}

// Two objects of one class carried past each other between sessions: A from x = -0.5 (2 m
// deep) to 0.5 (2.5 m deep), B the other way. Each box holds its object's texture and, more
// of it, the table behind it: the same table patch is in A's old box and in B's new one
// (x = -0.51, 2.3 m deep), another in B's old box and A's new one. Whole boxes pair by the
// table, crosswise, even against distance; without what each place shows in the other
// session, the objects' own textures decide, even against distance.
TEST(BoxAppearance, ATableSharedByTheBoxesDoesNotDecideThePairing) {
  const std::vector<Descriptor> a = Texture(30, 10), b = Texture(31, 10), left = Texture(32, 30),
                                right = Texture(33, 30);
  const Cuboid a_before = CuboidAt(-0.5, 2.0), b_before = CuboidAt(0.5, 2.0);
  const Cuboid a_after = CuboidAt(0.5, 2.5), b_after = CuboidAt(-0.5, 2.5);
  KeyframeFeatureMap keyframes;
  keyframes[10] = Keyframe(10, {{-0.5, 2.0, a, std::nullopt},
                                {0.5, 2.0, b, std::nullopt},
                                {-0.51, 2.3, left, std::nullopt},
                                {0.51, 2.3, right, std::nullopt}});
  keyframes[110] = Keyframe(110, {{0.5, 2.5, SeenAgain(a, 34), std::nullopt},
                                  {-0.5, 2.5, SeenAgain(b, 35), std::nullopt},
                                  {-0.51, 2.3, SeenAgain(left, 36), std::nullopt},
                                  {0.51, 2.3, SeenAgain(right, 37), std::nullopt}});
  const std::vector<const KeyframeFeatures*> session_0 = {&keyframes[10]},
                                             session_1 = {&keyframes[110]};
  const Eigen::Matrix3d R_wg = Eigen::Matrix3d::Identity();
  const BoxAppearanceOptions options;
  const auto look = [&](const Cuboid& cuboid, std::int64_t frame,
                        const std::vector<const KeyframeFeatures*>& absent, bool whole_boxes) {
    const std::vector<Descriptor> in_boxes =
        BoxDescriptors({BoxOf(frame, cuboid)}, cuboid, R_wg, keyframes, options);
    if (whole_boxes) return in_boxes;
    return WithoutBackground(in_boxes,
                             PlaceDescriptors(cuboid, R_wg, LookingAlongZ(), absent, options), 50);
  };
  // Removed: cups 3 (A) and 4 (B), last seen in session 0; found: 9 (A) and 10 (B), at
  // x = new_a and -new_a in the object map.
  std::vector<ObjectChange> gone = {Removed(3, kCup, -0.5, 2010, 1010),
                                    Removed(4, kCup, 0.5, 2011, 1010)};
  for (ObjectChange& change : gone) change.session = 1;
  const auto moved_to = [&](bool whole_boxes, double new_a) {
    ChangeLogContext context = Session(1, 2000);
    context.box_appearance = {{3, look(a_before, 10, session_1, whole_boxes)},
                              {4, look(b_before, 10, session_1, whole_boxes)},
                              {9, look(a_after, 110, session_0, whole_boxes)},
                              {10, look(b_after, 110, session_0, whole_boxes)}};
    const Objects objects = Objects{Live(9, kCup, new_a, 2005, 1), Live(10, kCup, -new_a, 2006, 1)};
    std::map<ObjectId, ObjectId> to;
    const nlohmann::json revised = Revise(gone, objects, context);
    for (const nlohmann::json& entry : revised.at("changes")) {
      if (entry["type"] == "moved") {
        to[entry["object_id"].get<ObjectId>()] = entry["to"]["object_id"].get<ObjectId>();
        EXPECT_EQ(entry["appearance"]["from"], "boxes");
      }
    }
    return to;
  };
  const std::map<ObjectId, ObjectId> right_pairs = {{3, 9}, {4, 10}}, crosswise = {{3, 10}, {4, 9}};
  EXPECT_EQ(moved_to(true, -0.8), crosswise) << "the table decides, though distance does not";
  EXPECT_EQ(moved_to(false, 0.8), right_pairs) << "the textures decide, though distance does not";
  EXPECT_EQ(moved_to(false, -0.8), right_pairs);
}

}  // namespace
}  // namespace ocg
