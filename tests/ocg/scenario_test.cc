// The paper's Fig. 4/5 story and the cases the improved modes fix, as keyframe scripts.

#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <sstream>

#include "ocg/ocg/change_detector.h"
#include "ocg/ocg/observability.h"
#include "ocg_test_scene.h"

namespace ocg {
namespace {

using testing::LookAt;
using testing::MakeObservation;
using S = ObjectState;

// Objects 1-4 on a table at the origin, 5-6 on a shelf ten metres away.
const std::map<ObjectId, Eigen::Vector3d> kPlaces = {
    {1, {0.0, 0.0, 0.0}},  {2, {0.3, 0.2, 0.0}},  {3, {-0.3, 0.2, 0.0}}, {4, {0.0, -0.3, 0.0}},
    {5, {10.0, 0.0, 0.0}}, {6, {10.0, 0.4, 0.0}}, {7, {0.1, 0.1, 0.0}}};

class Story : public ::testing::Test {
 protected:
  explicit Story(const std::string& mode = "paper") : detector_(Options(mode)) {}
  static OcgOptions Options(const std::string& mode) {
    OcgOptions options;
    options.mode = mode;
    return options;
  }
  // The camera looks at the table (from 2 m) or at the shelf (with the table behind it).
  KeyframeResult AtTable(std::vector<ObjectId> seen) {
    return Step(LookAt({-2, 0, 0.8}, {0, 0, 0}), seen);
  }
  KeyframeResult AtShelf(std::vector<ObjectId> seen) {
    return Step(LookAt({8, 0, 0.8}, {10, 0, 0}), seen);
  }
  KeyframeResult Step(const SE3& T_cw, const std::vector<ObjectId>& seen,
                      const std::vector<ObjectId>& restored = {}) {
    KeyframeObservation observation = MakeObservation(keyframe_++, T_cw, seen);
    observation.restored = restored;
    for (ObjectId id : seen) {
      observation.updates[id].centroid = kPlaces.at(id);
      observation.updates[id].class_id = 41;
    }
    return detector_.Process(observation);
  }
  S StateOf(ObjectId id) const { return detector_.Status(id)->state; }
  double DoubtOf(ObjectId id) const { return detector_.Status(id)->doubt; }

  ObjectChangeDetector detector_;
  std::int64_t keyframe_ = 0;
};

TEST_F(Story, MovedObjectIsSuspectedThenRemoved) {
  for (int i = 0; i < 3; ++i) AtTable({1, 2, 3, 4});
  EXPECT_EQ(StateOf(1), S::kObserved);
  AtShelf({5, 6});  // the camera leaves the table's observable region
  EXPECT_EQ(StateOf(1), S::kUnknown);
  AtShelf({5, 6});
  // Object 1 is taken away while the camera looks at the shelf. The camera comes back:
  AtTable({2, 3, 4});
  EXPECT_EQ(StateOf(1), S::kSuspicious);
  EXPECT_EQ(DoubtOf(1), 30.0);  // r = 1: all of its neighbours are seen
  EXPECT_DOUBLE_EQ(detector_.Status(1)->active_edge_rate, 1.0);
  AtTable({2, 3, 4});
  EXPECT_EQ(DoubtOf(1), 60.0);
  const KeyframeResult leaving = AtShelf({5, 6});
  ASSERT_EQ(leaving.removed.size(), 1u);
  const RemovalEvent& event = leaving.removed[0];
  EXPECT_EQ(event.object_id, 1);
  EXPECT_EQ(event.keyframe_id, 7);
  EXPECT_DOUBLE_EQ(event.timestamp, 3.5);
  EXPECT_EQ(event.doubt, 60.0);
  EXPECT_EQ(event.class_id, 41);
  EXPECT_TRUE(event.centroid->isApprox(kPlaces.at(1)));
  // Removal deletes the node and its edges.
  EXPECT_FALSE(detector_.Status(1).has_value());
  EXPECT_FALSE(detector_.graph().Contains(1));
  EXPECT_EQ(detector_.graph().EdgeWeight(2, 1), 0u);
  EXPECT_EQ(detector_.graph().WeightSum(2), 5u + 5u);  // 2-3 and 2-4, five keyframes each
  for (ObjectId id : {2, 3, 4, 5, 6}) EXPECT_TRUE(detector_.Status(id).has_value()) << id;
}

TEST_F(Story, ObjectStillThereIsKept) {
  for (int i = 0; i < 3; ++i) AtTable({1, 2, 3, 4});
  AtShelf({5, 6});
  AtTable({1, 2, 3, 4});
  EXPECT_EQ(StateOf(1), S::kObserved);
  AtTable({1, 2, 3, 4});
  const KeyframeResult leaving = AtShelf({5, 6});
  EXPECT_TRUE(leaving.removed.empty());
  EXPECT_EQ(StateOf(1), S::kUnknown);
  EXPECT_EQ(DoubtOf(1), 0.0);
}

TEST_F(Story, SingleMissedDetectionKeepsTheObject) {
  for (int i = 0; i < 3; ++i) AtTable({1, 2, 3, 4});
  AtTable({2, 3, 4});  // missed while the camera stays: recently observed, not suspicious
  EXPECT_EQ(StateOf(1), S::kRecentlyObserved);
  AtTable({1, 2, 3, 4});
  AtShelf({5, 6});
  AtTable({2, 3, 4});  // missed right after coming back
  EXPECT_EQ(StateOf(1), S::kSuspicious);
  AtTable({1, 2, 3, 4});
  EXPECT_EQ(StateOf(1), S::kObserved);
  EXPECT_TRUE(AtShelf({5, 6}).removed.empty());
  EXPECT_TRUE(detector_.Status(1).has_value());
}

TEST_F(Story, RedundantDuplicateSeenOnceIsRemoved) {
  AtTable({1, 2, 3, 4, 7});  // 7: a duplicate of 1 created by a detector hiccup
  AtTable({1, 2, 3, 4});
  EXPECT_EQ(StateOf(7), S::kRecentlyObserved);
  AtShelf({5, 6});
  EXPECT_EQ(StateOf(7), S::kUnknown);
  AtTable({1, 2, 3, 4});
  AtTable({1, 2, 3, 4});
  EXPECT_EQ(StateOf(7), S::kSuspicious);
  const KeyframeResult leaving = AtShelf({5, 6});
  ASSERT_EQ(leaving.removed.size(), 1u);
  EXPECT_EQ(leaving.removed[0].object_id, 7);
}

TEST_F(Story, ReobservedAfterRemovalReentersAsNewNode) {
  AtTable({1, 7});
  AtShelf({5, 6});
  AtTable({1});
  AtTable({1});
  ASSERT_EQ(AtShelf({5, 6}).removed.size(), 1u);
  AtTable({7, 2});
  EXPECT_EQ(StateOf(7), S::kObserved);
  EXPECT_EQ(detector_.graph().EdgeWeight(7, 1), 0u);  // old edges are gone
  EXPECT_EQ(detector_.graph().EdgeWeight(7, 2), 1u);
  EXPECT_EQ(detector_.Status(7)->observations, 1u);
}

TEST_F(Story, NeighbourlessObjectIsNeverJudgedInPaperMode) {
  AtTable({1});  // seen alone, once
  AtShelf({5, 6});
  for (int i = 0; i < 5; ++i) AtTable({});
  EXPECT_TRUE(AtShelf({5, 6}).removed.empty());
  EXPECT_EQ(StateOf(1), S::kUnknown);
  EXPECT_EQ(DoubtOf(1), 0.0);
}

TEST_F(Story, RemovalsDoNotChangeOtherRatesInTheSameKeyframe) {
  AtTable({1, 7});
  AtTable({7, 2});
  AtShelf({5, 6});
  AtTable({7});
  AtTable({7});  // 1 is suspicious with doubt 60
  const KeyframeResult result = AtTable({2});
  ASSERT_EQ(result.removed.size(), 1u);
  EXPECT_EQ(result.removed[0].object_id, 1);
  // 7 was judged on the graph that still held 1: E(7,2) / (E(7,1) + E(7,2)) = 0.5, not 1.
  EXPECT_DOUBLE_EQ(detector_.Status(7)->active_edge_rate, 0.5);
}

TEST_F(Story, ObjectsThatVanishTogetherAreRemovedTogether) {
  AtTable({1, 7, 2});
  AtShelf({5, 6});
  for (int i = 0; i < 3; ++i) AtTable({2});  // r = 0.5 for both: 20 per keyframe
  const KeyframeResult leaving = AtShelf({5, 6});
  ASSERT_EQ(leaving.removed.size(), 2u);
  EXPECT_EQ(leaving.removed[0].object_id, 1);
  EXPECT_EQ(leaving.removed[1].object_id, 7);
}

// Object 1 is missed at the table until the OCG removes it; then the object map finds it
// again at its place and says so (observation.restored).
class RestoreStory : public Story {
 protected:
  explicit RestoreStory(const std::string& mode = "restore") : Story(mode) {}
  void RemoveObjectOne() {
    for (int i = 0; i < 3; ++i) AtTable({1, 2, 3, 4});
    AtShelf({5, 6});
    AtTable({2, 3, 4});
    AtTable({2, 3, 4});
    const KeyframeResult leaving = AtShelf({5, 6});
    ASSERT_EQ(leaving.removed.size(), 1u);
    ASSERT_FALSE(detector_.graph().Contains(1));
  }
  void FoundAgain() { Step(LookAt({-2, 0, 0.8}, {0, 0, 0}), {1, 2, 3, 4}, {1}); }
};

TEST_F(RestoreStory, RestoredObjectComesBackWithItsEdgesAndNoDoubt) {
  RemoveObjectOne();
  FoundAgain();
  EXPECT_EQ(StateOf(1), S::kObserved);
  EXPECT_EQ(DoubtOf(1), 0.0);
  // Three keyframes with 2 before the removal, one now: its co-visibility is kept.
  EXPECT_EQ(detector_.graph().EdgeWeight(1, 2), 4u);
  EXPECT_EQ(detector_.graph().WeightSum(2), 4u + 6u + 6u);  // with 1, 3 and 4
  EXPECT_EQ(detector_.Status(1)->observations, 4u);
  EXPECT_EQ(detector_.Status(1)->first_keyframe, 0);
  // Judged as before: missed again at the table with its neighbours seen, it is suspicious.
  AtTable({2, 3, 4});
  EXPECT_EQ(StateOf(1), S::kRecentlyObserved);
  AtShelf({5, 6});
  AtTable({2, 3, 4});
  EXPECT_EQ(StateOf(1), S::kSuspicious);
  EXPECT_EQ(DoubtOf(1), 30.0);
}

TEST_F(RestoreStory, OnlyAnObjectItRemovedComesBack) {
  RemoveObjectOne();
  EXPECT_FALSE(detector_.Restore(2)) << "in the graph";
  EXPECT_FALSE(detector_.Restore(9)) << "never known";
  EXPECT_TRUE(detector_.Forget(2));
  EXPECT_FALSE(detector_.Restore(2)) << "forgotten (merged), not removed";
  EXPECT_TRUE(detector_.Restore(1));
  EXPECT_FALSE(detector_.Restore(1)) << "restored already";
  EXPECT_EQ(detector_.graph().EdgeWeight(1, 2), 0u);  // 2 is gone
  EXPECT_EQ(detector_.graph().EdgeWeight(1, 3), 3u);
}

// Paper mode keeps no removed objects: a restore request is ignored and the object re-enters
// as a new node, as SPEC 3 says.
TEST_F(Story, RestoreRequestIsIgnoredInPaperMode) {
  for (int i = 0; i < 3; ++i) AtTable({1, 2, 3, 4});
  AtShelf({5, 6});
  AtTable({2, 3, 4});
  AtTable({2, 3, 4});
  ASSERT_EQ(AtShelf({5, 6}).removed.size(), 1u);
  Step(LookAt({-2, 0, 0.8}, {0, 0, 0}), {1, 2, 3, 4}, {1});
  EXPECT_EQ(StateOf(1), S::kObserved);
  EXPECT_EQ(detector_.graph().EdgeWeight(1, 2), 1u);
  EXPECT_EQ(detector_.Status(1)->observations, 1u);
}

class FallbackStory : public Story {
 protected:
  FallbackStory() : Story("fallback") {}
};

TEST_F(FallbackStory, NeighbourlessObjectIsJudgedGeometrically) {
  AtTable({1});
  AtShelf({5, 6});
  EXPECT_EQ(StateOf(1), S::kUnknown);
  AtTable({});
  EXPECT_EQ(StateOf(1), S::kSuspicious);
  EXPECT_TRUE(detector_.Status(1)->judged_by_geometry);
  EXPECT_EQ(DoubtOf(1), 20.0);  // isolated_rate 0.5 -> the [0.5, 1) band
  AtTable({});
  AtTable({});
  ASSERT_EQ(AtShelf({5, 6}).removed.size(), 1u);
}

TEST_F(FallbackStory, TooFarToBeDetectedIsNotVisible) {
  AtTable({1});  // seen from about 2.2 m
  AtShelf({5, 6});
  Step(LookAt({-8, 0, 0.8}, {0, 0, 0}), {});  // 8 m away, beyond distance_slack x 2.2 m
  EXPECT_EQ(StateOf(1), S::kUnknown);
}

class OffStory : public Story {
 protected:
  OffStory() : Story("off") {}
};

TEST_F(OffStory, MovedObjectIsNeverRemoved) {
  for (int i = 0; i < 3; ++i) AtTable({1, 2, 3, 4});
  AtShelf({5, 6});
  for (int i = 0; i < 5; ++i) AtTable({2, 3, 4});  // paper mode removes 1 on leaving
  EXPECT_TRUE(AtShelf({5, 6}).removed.empty());
  EXPECT_EQ(StateOf(1), S::kRecentlyObserved);
  EXPECT_EQ(DoubtOf(1), 0.0);
  EXPECT_EQ(detector_.graph().EdgeWeight(1, 2), 3u);  // the graph is still kept
}

class VisibilityStory : public Story {
 protected:
  VisibilityStory() : Story("visibility") {}
};

TEST_F(VisibilityStory, RemovedAfterEnoughVisibleKeyframesWithoutDetection) {
  AtTable({1});  // no neighbours needed
  AtShelf({5, 6});
  EXPECT_EQ(StateOf(1), S::kRecentlyObserved);  // not visible from the shelf: no count
  EXPECT_EQ(DoubtOf(1), 0.0);
  for (int i = 1; i < 5; ++i) {
    EXPECT_TRUE(AtTable({}).removed.empty());
    EXPECT_EQ(StateOf(1), S::kSuspicious);
    EXPECT_EQ(DoubtOf(1), i);
  }
  const KeyframeResult fifth = AtTable({});
  ASSERT_EQ(fifth.removed.size(), 1u);
  EXPECT_EQ(fifth.removed[0].object_id, 1);
}

TEST_F(VisibilityStory, DetectionResetsTheCount) {
  AtTable({1});
  for (int i = 0; i < 4; ++i) AtTable({});
  AtTable({1});
  EXPECT_EQ(StateOf(1), S::kObserved);
  EXPECT_EQ(DoubtOf(1), 0.0);
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(AtTable({}).removed.empty());
}

class InImageStory : public Story {
 protected:
  InImageStory() : Story("in_image") {}
};

TEST_F(InImageStory, IncrementScaledByTheBoxFractionInsideTheImage) {
  for (int i = 0; i < 2; ++i) AtTable({1, 2, 3, 4});
  AtShelf({5, 6});
  KeyframeObservation observation =
      MakeObservation(keyframe_++, LookAt({-2, 0, 0.8}, {0, 0, 0}), {2, 3, 4});
  observation.updates[1].size = Eigen::Vector3d(0.2, 0.2, 0.2);
  detector_.Process(observation);
  EXPECT_EQ(StateOf(1), S::kSuspicious);
  EXPECT_DOUBLE_EQ(DoubtOf(1), 30.0);  // the whole box is in the image
  // A camera that sees object 1 in the image corner, at pixel (620, 465): the centroid is
  // inside, but most of a 1 m box is not.
  const Eigen::Vector3d eye(-2, 0, 0.8);
  const Eigen::Quaterniond R_cw = Eigen::Quaterniond::FromTwoVectors(
      (kPlaces.at(1) - eye).normalized(), Eigen::Vector3d(0.6, 0.45, 1.0).normalized());
  observation.keyframe_id = keyframe_++;
  observation.updates.clear();
  observation.updates[1].size = Eigen::Vector3d(1.0, 1.0, 1.0);
  observation.T_cw = SE3(R_cw, -(R_cw * eye));
  detector_.Process(observation);
  EXPECT_EQ(StateOf(1), S::kSuspicious);
  EXPECT_DOUBLE_EQ(DoubtOf(1), 30.0) << "box mostly outside: P = 0, no increment";
  // Near the right border, at pixel (570, 240): most of the box is inside, and the
  // increment is scaled by that fraction.
  const Eigen::Quaterniond R_side = Eigen::Quaterniond::FromTwoVectors(
      (kPlaces.at(1) - eye).normalized(), Eigen::Vector3d(0.5, 0.0, 1.0).normalized());
  observation.keyframe_id = keyframe_++;
  observation.T_cw = SE3(R_side, -(R_side * eye));
  const double fraction = BoxFractionInImage(kPlaces.at(1), Eigen::Vector3d(1, 1, 1),
                                             observation.T_cw, observation.camera);
  ASSERT_GT(fraction, 0.5);
  ASSERT_LT(fraction, 0.95);
  detector_.Process(observation);
  EXPECT_NEAR(DoubtOf(1), 30.0 + 30.0 * fraction, 1e-9);
}

class GuardStory : public Story {
 protected:
  GuardStory() : Story("guard") {}
};

TEST_F(GuardStory, OneDetectedNeighbourGrantsNoIncrement) {
  for (int i = 0; i < 5; ++i) AtTable({1, 2});  // heavy edge 1-2
  AtTable({1, 3});                              // light edges 1-3, 1-4
  AtTable({1, 4});
  AtShelf({5, 6});
  AtTable({2});  // only neighbour 2 detected: r = 5/7 > tau, but a single neighbour
  EXPECT_EQ(StateOf(1), S::kSuspicious);
  EXPECT_EQ(DoubtOf(1), 0.0);
  AtTable({2, 3});
  EXPECT_EQ(DoubtOf(1), 20.0);  // r = 6/7: two neighbours now
}

TEST(Detector, JsonExportImportRestoresTheGraphAndStates) {
  OcgOptions options;
  options.mode = "fallback+guard";
  options.tau_doubt = 40;
  ObjectChangeDetector detector(options);
  KeyframeObservation observation = MakeObservation(0, LookAt({-2, 0, 0.8}, {0, 0, 0}), {1, 2, 3});
  observation.updates[1].centroid = Eigen::Vector3d(0, 0, 0);
  observation.updates[1].size = Eigen::Vector3d(0.1, 0.2, 0.3);
  detector.Process(observation);
  observation.keyframe_id = 1;
  observation.observed = {1, 2};
  detector.Process(observation);
  const ObjectChangeDetector restored = ObjectChangeDetector::FromJson(detector.ToJson());
  EXPECT_EQ(restored.ToJson(), detector.ToJson());
  EXPECT_EQ(restored.options().tau_doubt, 40.0);
  EXPECT_EQ(restored.graph().EdgeWeight(1, 2), 2u);
  EXPECT_EQ(restored.Status(3)->state, S::kRecentlyObserved);
  EXPECT_TRUE(restored.Status(1)->geometry.size->isApprox(Eigen::Vector3d(0.1, 0.2, 0.3)));
  EXPECT_THROW(ObjectChangeDetector::FromJson("{\"format\": \"other\"}"), std::invalid_argument);
  EXPECT_THROW(ObjectChangeDetector::FromJson("[1, 2"), std::invalid_argument);
}

}  // namespace
}  // namespace ocg

namespace ocg {
namespace {

TEST(Detector, ForgetDropsAnObjectWithoutAChangeLogEntry) {
  ObjectChangeDetector detector{testing::PaperOptions()};
  detector.Process(MakeObservation(0, LookAt({-2, 0, 0.8}, {0, 0, 0}), {1, 2, 3}));
  EXPECT_TRUE(detector.Forget(2));
  EXPECT_FALSE(detector.Forget(2));
  EXPECT_FALSE(detector.Status(2).has_value());
  EXPECT_EQ(detector.graph().WeightSum(1), 1u);  // only 1-3 left
  const KeyframeResult next =
      detector.Process(MakeObservation(1, LookAt({8, 0, 0.8}, {10, 0, 0}), {5}));
  EXPECT_TRUE(next.removed.empty());
}

}  // namespace
}  // namespace ocg

namespace ocg {
namespace {

// Issue 16: a centroid given before the object's first observation is kept (SPEC 3.1),
// so the object can gather doubt once it goes missing.
TEST(Detector, CentroidGivenBeforeTheFirstObservationIsKept) {
  ObjectChangeDetector detector{testing::PaperOptions()};
  const SE3 at_table = LookAt({-2, 0, 0.8}, {0, 0, 0});
  const SE3 at_shelf = LookAt({8, 0, 0.8}, {10, 0, 0});
  KeyframeObservation first = MakeObservation(0, at_table, {1, 2});
  for (ObjectId id : {1, 2, 3}) first.updates[id].centroid = kPlaces.at(id);
  first.updates[3].class_id = 41;
  detector.Process(first);
  EXPECT_FALSE(detector.Status(3).has_value());
  ASSERT_TRUE(detector.PendingGeometry(3).has_value());
  detector.Process(MakeObservation(1, at_table, {1, 2, 3}));
  EXPECT_FALSE(detector.PendingGeometry(3).has_value());
  ASSERT_TRUE(detector.Status(3)->geometry.centroid.has_value());
  EXPECT_TRUE(detector.Status(3)->geometry.centroid->isApprox(kPlaces.at(3)));
  EXPECT_EQ(detector.Status(3)->class_id, 41);
  detector.Process(MakeObservation(2, at_shelf, {4}));
  EXPECT_EQ(detector.Status(3)->state, S::kUnknown);
  detector.Process(MakeObservation(3, at_table, {1, 2}));
  EXPECT_EQ(detector.Status(3)->state, S::kSuspicious);
  EXPECT_DOUBLE_EQ(detector.Status(3)->active_edge_rate, 1.0);
  EXPECT_EQ(detector.Status(3)->doubt, 30.0);
}

TEST(Detector, PendingGeometrySurvivesTheJsonRoundTripAndForget) {
  ObjectChangeDetector detector{testing::PaperOptions()};
  KeyframeObservation observation = MakeObservation(0, LookAt({-2, 0, 0.8}, {0, 0, 0}), {1});
  observation.updates[7].centroid = Eigen::Vector3d(1, 2, 3);
  observation.updates[8].size = Eigen::Vector3d(0.1, 0.2, 0.3);
  detector.Process(observation);
  const ObjectChangeDetector restored = ObjectChangeDetector::FromJson(detector.ToJson());
  EXPECT_EQ(restored.ToJson(), detector.ToJson());
  ASSERT_TRUE(restored.PendingGeometry(7).has_value());
  EXPECT_TRUE(restored.PendingGeometry(7)->centroid->isApprox(Eigen::Vector3d(1, 2, 3)));
  EXPECT_FALSE(restored.PendingGeometry(7)->size.has_value());
  EXPECT_TRUE(restored.PendingGeometry(8)->size->isApprox(Eigen::Vector3d(0.1, 0.2, 0.3)));
  EXPECT_FALSE(detector.Forget(7));  // not in the graph, but its geometry is dropped
  EXPECT_FALSE(detector.PendingGeometry(7).has_value());
}

}  // namespace
}  // namespace ocg

namespace ocg {
namespace {

// Object 1 stands in front of a partition; its neighbours 2-4 are tall enough to be seen
// over it from both sides. The camera detects everything from the front, then walks
// round to the back, where 1 is hidden and the detector finds only 2-4, then leaves.
std::vector<RemovalEvent> BehindThePartition(const std::string& mode) {
  OcgOptions options;
  options.mode = mode;
  ObjectChangeDetector detector(options);
  std::vector<RemovalEvent> removed;
  std::int64_t keyframe = 0;
  const auto step = [&](const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                        const std::vector<ObjectId>& seen) {
    KeyframeObservation observation = MakeObservation(keyframe++, LookAt(eye, target), seen);
    for (ObjectId id : seen) observation.updates[id].centroid = kPlaces.at(id);
    for (const RemovalEvent& event : detector.Process(observation).removed)
      removed.push_back(event);
  };
  for (int i = 0; i < 3; ++i) step({-2, 0, 0.8}, {0, 0, 0}, {1, 2, 3, 4});
  step({8, 0, 0.8}, {10, 0, 0}, {5, 6});
  for (int i = 0; i < 3; ++i) step({2, 0.3, 0.8}, {0, 0, 0}, {2, 3, 4});  // from the back
  step({8, 0, 0.8}, {10, 0, 0}, {5, 6});
  return removed;
}

TEST(ViewMode, HiddenFromASideItWasNeverDetectedFromIsKept) {
  const std::vector<RemovalEvent> paper = BehindThePartition("paper");
  ASSERT_EQ(paper.size(), 1u) << "the paper takes the hidden object for a moved one";
  EXPECT_EQ(paper[0].object_id, 1);
  EXPECT_TRUE(BehindThePartition("view").empty());
  EXPECT_TRUE(BehindThePartition("improved").empty());
}

// Object 1 (20 cm) stands on the table with 2-4; box 8 (60 cm) stands at `occluder`. The
// camera detects everything from high up, looking down at the table, and leaves; 1 is
// not detected when it comes back lower down (25 degrees lower, within "view"'s 30) and
// leaves again. With 8 between that place and 1, 8 hides 1 there; with 8 behind the table,
// 1 is in plain sight and was moved.
std::vector<RemovalEvent> MissedFromBehindABox(const std::string& mode,
                                               const Eigen::Vector3d& occluder) {
  OcgOptions options;
  options.mode = mode;
  ObjectChangeDetector detector(options);
  std::map<ObjectId, Eigen::Vector3d> places = kPlaces;
  places[8] = occluder;
  std::vector<RemovalEvent> removed;
  std::int64_t keyframe = 0;
  const auto step = [&](const SE3& T_cw, const std::vector<ObjectId>& seen) {
    KeyframeObservation observation = MakeObservation(keyframe++, T_cw, seen);
    for (ObjectId id : seen) {
      observation.updates[id].centroid = places.at(id);
      observation.updates[id].size = Eigen::Vector3d::Constant(id == 8 ? 0.6 : 0.2);
    }
    for (const RemovalEvent& event : detector.Process(observation).removed)
      removed.push_back(event);
  };
  const SE3 above = LookAt({-2, 0, 2.2}, {0, 0, 0});
  const SE3 low = LookAt({-2, 0, 0.8}, {0, 0, 0});
  const SE3 shelf = LookAt({8, 0, 0.8}, {10, 0, 0});
  for (int i = 0; i < 3; ++i) step(above, {1, 2, 3, 4, 8});
  step(shelf, {5, 6});
  for (int i = 0; i < 3; ++i) step(low, {2, 3, 4, 8});
  step(shelf, {5, 6});
  return removed;
}

const Eigen::Vector3d kBetweenCameraAndObject1(-1.0, 0.0, 0.3);
const Eigen::Vector3d kBehindTheTable(1.2, 0.0, 0.3);

TEST(Occlusion, HiddenBehindANearerMappedObjectIsKept) {
  const std::string without_occlusion = "fallback+in_image+guard+view+restore+dropout";
  for (const std::string& mode : {std::string("paper"), without_occlusion}) {
    const std::vector<RemovalEvent> removed = MissedFromBehindABox(mode, kBetweenCameraAndObject1);
    ASSERT_EQ(removed.size(), 1u) << mode << " takes the hidden object for a moved one";
    EXPECT_EQ(removed[0].object_id, 1);
  }
  EXPECT_TRUE(MissedFromBehindABox("occlusion", kBetweenCameraAndObject1).empty());
  EXPECT_TRUE(MissedFromBehindABox("improved", kBetweenCameraAndObject1).empty());
}

TEST(Occlusion, MissedInPlainSightIsRemoved) {
  for (const std::string mode : {"paper", "occlusion", "improved"}) {
    const std::vector<RemovalEvent> removed = MissedFromBehindABox(mode, kBehindTheTable);
    ASSERT_EQ(removed.size(), 1u) << mode;
    EXPECT_EQ(removed[0].object_id, 1);
  }
}

ImageFootprint Rectangle(double min_x, double min_y, double max_x, double max_y,
                         double centre_depth, double far_depth) {
  return FootprintOf({{min_x, min_y}, {max_x, min_y}, {max_x, max_y}, {min_x, max_y}}, centre_depth,
                     far_depth);
}

TEST(Occlusion, OnlyOutlinesWhollyInFrontOfTheObjectCover) {
  const PinholeCamera camera = testing::TestCamera();
  const ImageFootprint object = Rectangle(100, 100, 200, 200, 3.0, 3.1);
  const ImageFootprint left_half = Rectangle(0, 0, 150, 480, 1.0, 1.5);
  EXPECT_NEAR(OccludedShare(object, {left_half}, camera), 0.5, 1e-9);
  const ImageFootprint right_half = Rectangle(150, 0, 640, 480, 1.0, 1.5);
  EXPECT_NEAR(OccludedShare(object, {left_half, right_half, object}, camera), 1.0, 1e-9)
      << "its own outline never covers it";
  // A table under the object: its near edge is nearer, its far edge is not; a neighbour
  // beside it, overlapping it in depth; something behind it.
  EXPECT_EQ(OccludedShare(object, {Rectangle(0, 0, 640, 480, 2.5, 4.0)}, camera), 0.0);
  EXPECT_EQ(OccludedShare(object, {Rectangle(0, 0, 640, 480, 2.8, 3.05)}, camera), 0.0);
  EXPECT_EQ(OccludedShare(object, {Rectangle(0, 0, 640, 480, 4.0, 4.2)}, camera), 0.0);
  // Only the part inside the image counts: half of it is outside, all of the rest covered.
  const ImageFootprint border_cover = Rectangle(500, 0, 640, 480, 1.0, 1.5);
  EXPECT_NEAR(OccludedShare(Rectangle(540, 100, 740, 200, 3.0, 3.1), {border_cover}, camera), 1.0,
              1e-9);
  EXPECT_EQ(OccludedShare(Rectangle(700, 100, 800, 200, 3.0, 3.1), {border_cover}, camera), 0.0);
  // The outline, not its bounding rectangle: a triangle over the lower left half of the
  // object's square covers half of it, though its rectangle covers all of it.
  const ImageFootprint triangle = FootprintOf({{90, 90}, {90, 210}, {210, 210}}, 1.0, 1.5);
  EXPECT_NEAR(OccludedShare(object, {triangle}, camera), 0.5, 0.07);
}

// A cell phone lying on the desk 0.3 m behind a laptop, seen from 2 m and 0.8 m up: the
// laptop lies flat and hides nothing of it; a box of the laptop's footprint 0.3 m tall
// hides it.
TEST(Occlusion, AFlatObjectInFrontHidesNothingBehindIt) {
  const PinholeCamera camera = testing::TestCamera();
  const SE3 T_cw = LookAt({-2, 0, 0.8}, {0, 0, 0});
  const auto phone = ProjectBox({0, 0, 0.005}, {0.08, 0.04, 0.01}, T_cw, camera);
  const auto laptop = ProjectBox({-0.3, 0, 0.015}, {0.23, 0.33, 0.03}, T_cw, camera);
  const auto box = ProjectBox({-0.3, 0, 0.15}, {0.23, 0.33, 0.3}, T_cw, camera);
  ASSERT_TRUE(phone && laptop && box);
  EXPECT_EQ(OccludedShare(*phone, {*laptop}, camera), 0.0);
  EXPECT_EQ(OccludedShare(*phone, {*box}, camera), 1.0);
}

// Sessions: session 0 maps the table and leaves; between the sessions object 1 is
// carried away; session 1 comes back and looks at the table until it ends, without ever
// leaving its observable region, so the paper's rule (an outlier on leaving) never fires.
class SessionStory : public Story {
 protected:
  SessionStory() : Story("improved") {}
  void FirstSession() {
    for (int i = 0; i < 3; ++i) AtTable({1, 2, 3, 4});
    AtShelf({5, 6});
  }
};

TEST_F(SessionStory, GoneSinceTheLastSessionIsRemovedWhenTheSessionEndsInItsRegion) {
  FirstSession();
  detector_.StartSession();
  AtTable({2, 3, 4});
  AtTable({2, 3, 4});
  EXPECT_EQ(StateOf(1), S::kSuspicious);
  EXPECT_GT(DoubtOf(1), detector_.options().tau_doubt);
  const KeyframeResult end = detector_.EndSession();
  ASSERT_EQ(end.removed.size(), 1u);
  EXPECT_EQ(end.removed[0].object_id, 1);
  EXPECT_EQ(end.removed[0].keyframe_id, 5);  // the session's last keyframe
  EXPECT_DOUBLE_EQ(end.removed[0].timestamp, 2.5);
  // Its reason says what happened, with the doubt and the threshold it passed (a removal on
  // leaving the region keeps the generic "outlier").
  std::ostringstream reason;
  reason << std::fixed << std::setprecision(1)
         << "session ended: not observed in this session while its neighbours were "
            "(suspicious), doubt "
         << end.removed[0].doubt << " > tau_doubt " << detector_.options().tau_doubt;
  EXPECT_EQ(end.removed[0].reason, reason.str());
  EXPECT_EQ(RemovalEvent{}.reason, "outlier");
  EXPECT_FALSE(detector_.Status(1).has_value());
  for (ObjectId id : {2, 3, 4, 5, 6}) EXPECT_TRUE(detector_.Status(id).has_value()) << id;
  EXPECT_TRUE(detector_.EndSession().removed.empty());  // nothing left to remove
}

TEST_F(SessionStory, DetectedInThisSessionAndMissedAtItsEndIsKept) {
  // The same doubt within one session (or after a detection in this one) is a static
  // object the detector misses from where the camera stopped. Objects 5 and 6 are of its
  // class and first seen after it, but in another region (no neighbour shared): no
  // successor.
  FirstSession();
  detector_.StartSession();
  AtTable({1, 2, 3, 4});
  AtShelf({5, 6});
  AtTable({2, 3, 4});
  AtTable({2, 3, 4});
  EXPECT_GT(DoubtOf(1), detector_.options().tau_doubt);
  EXPECT_TRUE(detector_.EndSession().removed.empty());
  EXPECT_EQ(StateOf(1), S::kSuspicious);

  ObjectChangeDetector one_session(Options("improved"));
  std::swap(detector_, one_session);
  keyframe_ = 0;
  FirstSession();
  AtTable({2, 3, 4});
  AtTable({2, 3, 4});
  EXPECT_GT(DoubtOf(1), detector_.options().tau_doubt);
  EXPECT_TRUE(detector_.EndSession().removed.empty());
}

// One session: object 1 is carried across the table while the camera looks at the shelf;
// back at the table the camera sees its old neighbours and a new object of its class (7)
// among them, and the run ends there, before the camera leaves again.
TEST_F(SessionStory, MissedAtTheEndWithANewObjectOfItsClassAmongItsNeighboursIsMoved) {
  const auto end_of_story = [&](const std::string& mode, bool seen_together,
                                ObjectChangeDetector::SuccessorCheck check = {}) {
    ObjectChangeDetector detector(Options(mode));
    std::swap(detector_, detector);
    keyframe_ = 0;
    for (int i = 0; i < 3; ++i) AtTable({1, 2, 3, 4});
    if (seen_together) AtTable({1, 2, 3, 4, 7});
    AtShelf({5, 6});
    AtTable({2, 3, 4, 7});
    AtTable({2, 3, 4, 7});
    EXPECT_EQ(StateOf(1), S::kSuspicious);
    EXPECT_GT(DoubtOf(1), detector_.options().tau_doubt);
    return detector_.EndSession(check);
  };
  const KeyframeResult moved = end_of_story("improved", false);
  ASSERT_EQ(moved.removed.size(), 1u);
  EXPECT_EQ(moved.removed[0].object_id, 1);
  EXPECT_EQ(moved.removed[0].keyframe_id, 5);  // the run's last keyframe
  EXPECT_NE(moved.removed[0].reason.find("object 7 of its class, never seen with it, entered "
                                         "after its last observation"),
            std::string::npos)
      << moved.removed[0].reason;
  EXPECT_FALSE(detector_.Status(1).has_value());
  EXPECT_TRUE(detector_.Status(7).has_value());
  // Seen together with 1 once: another object, which says nothing of 1.
  EXPECT_TRUE(end_of_story("improved", true).removed.empty());
  // The paper's rule alone waits for the camera to leave.
  EXPECT_TRUE(end_of_story("paper", false).removed.empty());
  // The caller's evidence (an object map's colours) says 7 is another object.
  std::vector<std::pair<ObjectId, ObjectId>> asked;
  const auto another_object = [&](ObjectId object, ObjectId successor) {
    asked.push_back({object, successor});
    return false;
  };
  EXPECT_TRUE(end_of_story("improved", false, another_object).removed.empty());
  EXPECT_EQ(asked, (std::vector<std::pair<ObjectId, ObjectId>>{{1, 7}}));
}

TEST_F(SessionStory, DoubtOfTheEarlierSessionAloneRemovesNothing) {
  // Session 0 ends with 1 suspicious above tau_doubt; session 1 never relocalizes (no
  // keyframe): it gathered no evidence of its own.
  for (int i = 0; i < 3; ++i) AtTable({1, 2, 3, 4});
  AtShelf({5, 6});
  AtTable({2, 3, 4});
  AtTable({2, 3, 4});
  ASSERT_GT(DoubtOf(1), detector_.options().tau_doubt);
  detector_.StartSession();
  EXPECT_TRUE(detector_.EndSession().removed.empty());
  EXPECT_TRUE(detector_.Status(1).has_value());
}

class ViewStory : public Story {
 protected:
  ViewStory() : Story("view") {}
};

TEST_F(ViewStory, MovedObjectSeenFromWhereItWasDetectedIsRemoved) {
  for (int i = 0; i < 3; ++i) AtTable({1, 2, 3, 4});
  AtShelf({5, 6});
  AtTable({2, 3, 4});  // 1 was moved; the camera is where it detected 1 before
  AtTable({2, 3, 4});
  EXPECT_EQ(DoubtOf(1), 60.0);
  const KeyframeResult leaving = AtShelf({5, 6});
  ASSERT_EQ(leaving.removed.size(), 1u);
  EXPECT_EQ(leaving.removed[0].object_id, 1);
}

TEST_F(ViewStory, FartherThanEverDetectedGivesNoIncrement) {
  for (int i = 0; i < 3; ++i) AtTable({1, 2, 3, 4});  // detected from 2.15 m
  AtShelf({5, 6});
  // The same direction from 4.3 m: 1 would be too small for the detector; its
  // neighbours (big ones) are still found.
  Step(LookAt({-4, 0, 1.6}, {0, 0, 0}), {2, 3, 4});
  EXPECT_EQ(StateOf(1), S::kSuspicious);
  EXPECT_EQ(DoubtOf(1), 0.0);
  AtTable({2, 3, 4});  // back at 2 m: now the absence counts
  EXPECT_EQ(DoubtOf(1), 30.0);
}

using Looks = std::vector<std::pair<SE3, std::vector<ObjectId>>>;

// A detector in `mode` fed one keyframe per look: the camera pose and the ids detected,
// at their kPlaces. Returns the removals, in order.
std::vector<RemovalEvent> RunLooks(const std::string& mode, const Looks& looks) {
  OcgOptions options;
  options.mode = mode;
  ObjectChangeDetector detector(options);
  std::vector<RemovalEvent> removed;
  std::int64_t keyframe = 0;
  for (const auto& [T_cw, seen] : looks) {
    KeyframeObservation observation = MakeObservation(keyframe++, T_cw, seen);
    for (ObjectId id : seen) observation.updates[id].centroid = kPlaces.at(id);
    for (const RemovalEvent& event : detector.Process(observation).removed)
      removed.push_back(event);
  }
  return removed;
}

const SE3 kAtTable = LookAt({-2, 0, 0.8}, {0, 0, 0});
const SE3 kAtShelf = LookAt({8, 0, 0.8}, {10, 0, 0});

// Visits to the table, each followed by a look at the shelf: at each visit the detector
// finds 2-4 and, as `found_one` says, 1 (found_one[i] false: 1 is missed once and the
// camera looks again); the last visit misses 1 twice. Returns the removals.
std::vector<RemovalEvent> TableVisits(const std::string& mode, const std::vector<bool>& found_one) {
  Looks looks;
  for (const bool found : found_one) {
    looks.push_back({kAtTable, {1, 2, 3, 4}});
    looks.push_back({kAtShelf, {5, 6}});
    if (!found) {
      looks.push_back({kAtTable, {2, 3, 4}});
      looks.push_back({kAtTable, {1, 2, 3, 4}});
      looks.push_back({kAtShelf, {5, 6}});
    }
  }
  looks.push_back({kAtTable, {2, 3, 4}});
  looks.push_back({kAtTable, {2, 3, 4}});
  looks.push_back({kAtShelf, {5, 6}});
  return RunLooks(mode, looks);
}

// Object 1 is a hard one: the detector missed it at every other visit. Two misses say
// little about it, so "reliability" (and "improved+reliability") keep it where the paper
// and the other improvements, blind to the detector's record on this object, remove it.
TEST(Reliability, AnObjectTheDetectorOftenMissesIsKeptAfterTwoMisses) {
  const std::vector<bool> every_other = {true, false, true, false, true, false, true, false};
  ASSERT_EQ(TableVisits("paper", every_other).size(), 1u);
  ASSERT_EQ(TableVisits("improved", every_other).size(), 1u);
  EXPECT_TRUE(TableVisits("reliability", every_other).empty());
  EXPECT_TRUE(TableVisits("improved+reliability", every_other).empty());
}

// Object 1 was found at every one of ten visits, then taken away: its misses are unlikely
// under its record, they weigh fully, and it is removed as in the paper.
TEST(Reliability, AReliablyDetectedObjectThatMovedIsRemoved) {
  const std::vector<bool> always(10, true);
  ASSERT_EQ(TableVisits("paper", always).size(), 1u);
  const std::vector<RemovalEvent> removed = TableVisits("reliability", always);
  ASSERT_EQ(removed.size(), 1u);
  EXPECT_EQ(removed[0].object_id, 1);
  EXPECT_EQ(TableVisits("improved+reliability", always).size(), 1u);
}

TEST(Reliability, MissWeightFollowsTheDetectionRecord) {
  OcgOptions options;
  ObjectGeometry geometry;
  geometry.detected_keyframes = 98;  // p = 99/100 >= 0.9: full weight
  geometry.missed_keyframes = 0;
  EXPECT_DOUBLE_EQ(MissWeight(geometry, options), 1.0);
  geometry.detected_keyframes = 8;  // p = 0.9 exactly
  EXPECT_NEAR(MissWeight(geometry, options), 1.0, 1e-12);
  geometry.detected_keyframes = 4;  // p = 5/10 = 0.5: ln 0.5 / ln 0.1
  geometry.missed_keyframes = 4;
  EXPECT_NEAR(MissWeight(geometry, options), std::log(0.5) / std::log(0.1), 1e-12);
  geometry.missed_keyframes = 40;  // rarely found: a miss is nearly no evidence
  EXPECT_LT(MissWeight(geometry, options), 0.05);
  EXPECT_GT(MissWeight(geometry, options), 0.0);
}

TEST(Reliability, DetectionRecordSurvivesJson) {
  OcgOptions options;
  options.mode = "reliability";
  ObjectChangeDetector detector(options);
  const SE3 table = LookAt({-2, 0, 0.8}, {0, 0, 0});
  const SE3 shelf = LookAt({8, 0, 0.8}, {10, 0, 0});
  std::int64_t keyframe = 0;
  for (const auto& [T_cw, seen] : std::vector<std::pair<SE3, std::vector<ObjectId>>>{
           {table, {1, 2, 3, 4}}, {shelf, {5, 6}}, {table, {2, 3, 4}}}) {
    KeyframeObservation observation = MakeObservation(keyframe++, T_cw, seen);
    for (ObjectId id : seen) observation.updates[id].centroid = kPlaces.at(id);
    detector.Process(observation);
  }
  ASSERT_EQ(detector.Status(1)->geometry.detected_keyframes, 1u);
  ASSERT_EQ(detector.Status(1)->geometry.missed_keyframes, 1u);
  const ObjectChangeDetector restored = ObjectChangeDetector::FromJson(detector.ToJson());
  EXPECT_EQ(restored.ToJson(), detector.ToJson());
  EXPECT_EQ(restored.Status(1)->geometry.missed_keyframes, 1u);
}

// The table holds 1, 2, 3, 4 and 7, always found together; the camera turns to the shelf
// and back. Then three looks at the table in which the detector finds only `found`, and a
// look at the shelf (leaving the table: objects with doubt above tau_doubt go). Returns
// the ids removed.
std::vector<ObjectId> TableAfterLooks(const std::string& mode, const std::vector<ObjectId>& found) {
  Looks looks(3, {kAtTable, {1, 2, 3, 4, 7}});
  looks.push_back({kAtShelf, {5, 6}});
  for (int i = 0; i < 3; ++i) looks.push_back({kAtTable, found});
  looks.push_back({kAtShelf, {5, 6}});
  std::vector<ObjectId> removed;
  for (const RemovalEvent& event : RunLooks(mode, looks)) removed.push_back(event.object_id);
  return removed;
}

// A whole-view dropout: the detector finds 2 of the table's five objects in three looks.
// For 1, 4 and 7 half of their in-view neighbours' weight was found (r = 0.5: 20 a
// keyframe, 60 in all, above tau_doubt), so the paper and the other improvements remove
// the three static objects; with "dropout" each miss weighs ln(0.5) / ln(0.3) = 0.58 (35
// in all) and they stay.
TEST(Dropout, MissesInAWholeViewDropoutDoNotRemoveStaticObjects) {
  const std::vector<ObjectId> all_three = {1, 4, 7};
  EXPECT_EQ(TableAfterLooks("paper", {2, 3}), all_three);
  EXPECT_EQ(TableAfterLooks("fallback+in_image+guard+view+restore", {2, 3}), all_three);
  EXPECT_TRUE(TableAfterLooks("dropout", {2, 3}).empty());
  EXPECT_TRUE(TableAfterLooks("improved", {2, 3}).empty());
}

// 1 moved away: the detector finds every other object of the table, so the miss weighs
// fully and 1 is removed, alone, in every mode.
TEST(Dropout, AnObjectMissedWhileItsNeighboursAreFoundIsRemoved) {
  const std::vector<ObjectId> one = {1};
  EXPECT_EQ(TableAfterLooks("paper", {2, 3, 4, 7}), one);
  EXPECT_EQ(TableAfterLooks("dropout", {2, 3, 4, 7}), one);
  EXPECT_EQ(TableAfterLooks("improved", {2, 3, 4, 7}), one);
}

TEST(Dropout, MissWeightFollowsTheDetectedShareOfNeighboursInView) {
  OcgOptions options;  // dropout_full_share 0.7
  EXPECT_DOUBLE_EQ(DropoutWeight(7, 10, options), 1.0);
  EXPECT_DOUBLE_EQ(DropoutWeight(10, 10, options), 1.0);
  EXPECT_NEAR(DropoutWeight(5, 10, options), std::log(0.5) / std::log(0.3), 1e-12);
  EXPECT_LT(DropoutWeight(1, 10, options), 0.1);  // nearly nothing found: nearly no evidence
  EXPECT_DOUBLE_EQ(DropoutWeight(0, 10, options), 0.0);
  EXPECT_DOUBLE_EQ(DropoutWeight(0, 0, options), 1.0) << "nothing in view tells a dropout";
}

// Neighbours the camera cannot see do not make a dropout: 1 was seen with 2, 3, 4 and
// with the shelf's 5 and 6 (from far away); looking at the table, 2, 3 and 4 are found, 5
// and 6 are behind the camera. r is 0.6 (half the weight is the shelf's), but every
// neighbour in view was found: the miss counts fully, as in the paper.
TEST(Dropout, NeighboursOutOfViewDoNotDiscountAMiss) {
  OcgOptions options;
  options.mode = "dropout";
  ObjectChangeDetector detector(options);
  const SE3 table = LookAt({2, 0, 0.8}, {0, 0, 0});  // the shelf (x = 10) behind the camera
  const SE3 both = LookAt({-12, 0, 0.8}, {5, 0, 0});
  const SE3 away = LookAt({-2, 0, 0.8}, {-10, 0, 0});
  std::int64_t keyframe = 0;
  for (const auto& [T_cw, seen] : std::vector<std::pair<SE3, std::vector<ObjectId>>>{
           {both, {1, 2, 3, 4, 5, 6}}, {away, {}}, {table, {2, 3, 4}}}) {
    KeyframeObservation observation = MakeObservation(keyframe++, T_cw, seen);
    for (ObjectId id : seen) observation.updates[id].centroid = kPlaces.at(id);
    detector.Process(observation);
  }
  // r = 3/5: 20 (ln(0.4) / ln(0.3) = 0.76 of it, 15.2, if the shelf counted as a dropout).
  EXPECT_EQ(detector.Status(1)->state, ObjectState::kSuspicious);
  EXPECT_DOUBLE_EQ(detector.Status(1)->doubt, 20.0);
}

TEST(ViewMode, RecordedDirectionsAreSpacedAndSurviveJson) {
  OcgOptions options;
  options.mode = "view";
  ObjectGeometry geometry;
  geometry.centroid = Eigen::Vector3d::Zero();
  for (int degrees = 0; degrees < 360; ++degrees) {
    const double angle = degrees * M_PI / 180.0;
    RecordDetectedView(geometry, 2.0 * Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.0),
                       options, true);
  }
  // A full circle at one direction per degree: one kept whenever it is more than 10
  // degrees (a third of view_max_angle_deg) from every kept one, so about 33, not 360.
  EXPECT_GE(geometry.view_directions.size(), 30u);
  EXPECT_LE(geometry.view_directions.size(), 36u);
  EXPECT_DOUBLE_EQ(geometry.max_observed_distance, 2.0);

  ObjectChangeDetector detector(options);
  KeyframeObservation observation = MakeObservation(0, LookAt({-2, 0, 0.8}, {0, 0, 0}), {1, 2});
  observation.updates[1].centroid = kPlaces.at(1);
  detector.Process(observation);
  ASSERT_EQ(detector.Status(1)->geometry.view_directions.size(), 1u);
  const ObjectChangeDetector restored = ObjectChangeDetector::FromJson(detector.ToJson());
  EXPECT_EQ(restored.ToJson(), detector.ToJson());
  EXPECT_TRUE(restored.Status(1)->geometry.view_directions[0].isApprox(
      detector.Status(1)->geometry.view_directions[0]));
}

}  // namespace
}  // namespace ocg

namespace ocg {
namespace {

using testing::LookAt;
using testing::MakeObservation;

// "points": the camera visits the table (objects 1-4) and turns to the shelf (5, 6), twice.
// At the second visit the detector misses object 1 for two keyframes while it finds 2-4;
// in those keyframes SLAM tracked object 1's own map points when tracked_by_points.
// Returns the removals.
std::vector<RemovalEvent> MissedAtTheSecondVisit(const std::string& mode, bool tracked_by_points) {
  OcgOptions options;
  options.mode = mode;
  ObjectChangeDetector detector(options);
  const SE3 table = LookAt({-2, 0, 0.8}, {0, 0, 0});
  const SE3 shelf = LookAt({8, 0, 0.8}, {10, 0, 0});
  struct Look {
    SE3 T_cw;
    std::vector<ObjectId> detected;
    std::vector<ObjectId> present_by_points;
  };
  const std::vector<ObjectId> by_points =
      tracked_by_points ? std::vector<ObjectId>{1} : std::vector<ObjectId>{};
  const std::vector<Look> looks = {{table, {1, 2, 3, 4}, {}},
                                   {shelf, {5, 6}, {}},
                                   {table, {2, 3, 4}, by_points},
                                   {table, {2, 3, 4}, by_points},
                                   {shelf, {5, 6}, {}}};
  std::vector<RemovalEvent> removed;
  std::int64_t keyframe = 0;
  for (const Look& look : looks) {
    KeyframeObservation observation = MakeObservation(keyframe++, look.T_cw, look.detected);
    observation.present_by_points = look.present_by_points;
    for (ObjectId id : look.detected) {
      observation.updates[id].centroid = kPlaces.at(id);
      observation.updates[id].size = Eigen::Vector3d(0.1, 0.1, 0.1);
    }
    for (const RemovalEvent& event : detector.Process(observation).removed)
      removed.push_back(event);
  }
  return removed;
}

// The detector missed it, the tracking saw its points where they were: the paper and the
// improvements that only read detections remove it, "points" and "improved+points" keep it.
TEST(Points, AnObjectMissedWhileItsOwnPointsAreTrackedIsKept) {
  ASSERT_EQ(MissedAtTheSecondVisit("paper", true).size(), 1u) << "paper ignores the points";
  ASSERT_EQ(MissedAtTheSecondVisit("fallback+in_image+guard+view+restore+dropout", true).size(), 1u)
      << "improved without points";
  EXPECT_TRUE(MissedAtTheSecondVisit("points", true).empty());
  EXPECT_TRUE(MissedAtTheSecondVisit("improved", true).empty()) << "part of improved";
}

// Carried away, it took its points with it: nothing says it is there, and it is removed
// in every mode.
TEST(Points, AMovedObjectWhosePointsAreNotTrackedIsRemoved) {
  for (const std::string mode : {"paper", "points", "improved+points"}) {
    const std::vector<RemovalEvent> removed = MissedAtTheSecondVisit(mode, false);
    ASSERT_EQ(removed.size(), 1u) << mode;
    EXPECT_EQ(removed[0].object_id, 1) << mode;
  }
}

// Present by its points clears the doubt gathered so far, but makes no edge: only
// detections feed the graph.
TEST(Points, PresenceByPointsClearsTheDoubtAndAddsNoEdge) {
  OcgOptions options;
  options.mode = "points";
  ObjectChangeDetector detector(options);
  const SE3 table = LookAt({-2, 0, 0.8}, {0, 0, 0});
  const SE3 shelf = LookAt({8, 0, 0.8}, {10, 0, 0});
  std::int64_t keyframe = 0;
  const auto step = [&](const SE3& T_cw, const std::vector<ObjectId>& detected,
                        const std::vector<ObjectId>& by_points) {
    KeyframeObservation observation = MakeObservation(keyframe++, T_cw, detected);
    observation.present_by_points = by_points;
    for (ObjectId id : detected) observation.updates[id].centroid = kPlaces.at(id);
    return detector.Process(observation);
  };
  step(table, {1, 2, 3, 4}, {});
  step(shelf, {5, 6}, {});
  step(table, {2, 3, 4}, {});
  ASSERT_GT(detector.Status(1)->doubt, 0.0);
  const std::uint64_t weight = detector.graph().WeightSum(1);
  step(table, {2, 3, 4}, {1});
  EXPECT_EQ(detector.Status(1)->doubt, 0.0);
  EXPECT_EQ(detector.Status(1)->state, ObjectState::kObserved);
  EXPECT_EQ(detector.graph().WeightSum(1), weight);
  EXPECT_EQ(detector.Status(1)->geometry.detected_keyframes, 1u);
}

// SPEC 3.1: an id observed after its removal re-enters as a new node and keeps its last
// centroid. A feeding system sends a centroid only when it is new or changed, so an object
// falsely removed and seen again at its old place must be able to gather doubt again.
// Identity pose, fx = fy = 500, cx 320, cy 240, 640x480; object 1 at (0, 0, 2) in view.
TEST(Reentry, ARemovedObjectSeenAgainKeepsItsCentroidAndGathersDoubtAgain) {
  ObjectChangeDetector detector(testing::PaperOptions());
  const std::vector<std::vector<ObjectId>> seen = {{1, 2}, {2},    {3}, {2}, {2},
                                                   {3},    {1, 2}, {3}, {2}};
  struct Expected {
    S state;
    double doubt;
  };
  const std::vector<Expected> object_1 = {
      {S::kObserved, 0},    {S::kRecentlyObserved, 0}, {S::kUnknown, 0},
      {S::kSuspicious, 30}, {S::kSuspicious, 60},      {S::kOutlier, 0},
      {S::kObserved, 0},    {S::kUnknown, 0},          {S::kSuspicious, 30}};
  for (std::size_t k = 0; k < seen.size(); ++k) {
    KeyframeObservation observation =
        testing::MakeObservation(static_cast<std::int64_t>(k), SE3(), seen[k]);
    if (k == 0) observation.updates[1].centroid = Eigen::Vector3d(0, 0, 2);
    const KeyframeResult result = detector.Process(observation);
    if (k == 5) {
      ASSERT_EQ(result.removed.size(), 1u);
      EXPECT_EQ(result.removed[0].object_id, 1);
      EXPECT_FALSE(detector.Status(1).has_value()) << "removed at keyframe 5";
      continue;
    }
    ASSERT_TRUE(detector.Status(1).has_value()) << "keyframe " << k;
    EXPECT_EQ(detector.Status(1)->state, object_1[k].state) << "keyframe " << k;
    EXPECT_EQ(detector.Status(1)->doubt, object_1[k].doubt) << "keyframe " << k;
  }
  EXPECT_EQ(detector.Status(1)->active_edge_rate, 1.0);
  ASSERT_TRUE(detector.Status(1)->geometry.centroid.has_value());
  EXPECT_EQ(*detector.Status(1)->geometry.centroid, Eigen::Vector3d(0, 0, 2));
  EXPECT_EQ(detector.Status(1)->first_keyframe, 6) << "a new node";
}

// A centroid sent while the object is out of the graph is newer than the one it had.
TEST(Reentry, ACentroidSentAfterTheRemovalWinsOverTheLastOne) {
  ObjectChangeDetector detector(testing::PaperOptions());
  const std::vector<std::vector<ObjectId>> seen = {{1, 2}, {2}, {3}, {2}, {2}, {3}};
  for (std::size_t k = 0; k < seen.size(); ++k) {
    KeyframeObservation observation =
        testing::MakeObservation(static_cast<std::int64_t>(k), SE3(), seen[k]);
    if (k == 0) observation.updates[1].centroid = Eigen::Vector3d(0, 0, 2);
    detector.Process(observation);
  }
  ASSERT_FALSE(detector.Status(1).has_value());
  KeyframeObservation moved = testing::MakeObservation(6, SE3(), {2});
  moved.updates[1].centroid = Eigen::Vector3d(5, 0, 2);
  detector.Process(moved);
  detector.Process(testing::MakeObservation(7, SE3(), {1, 2}));
  EXPECT_EQ(*detector.Status(1)->geometry.centroid, Eigen::Vector3d(5, 0, 2));
}

}  // namespace
}  // namespace ocg
