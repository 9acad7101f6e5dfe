// Parts of the object map, tested directly: the evidence sources (evidence_provider.h),
// each filling the one field of the keyframe observation it names from what the object map
// shows it at the keyframe, and the candidates (candidate_tracker.h).

#include <gtest/gtest.h>

#include <memory>
#include <set>
#include <string>
#include <vector>

#include "ocg/objects/candidate_tracker.h"
#include "ocg/objects/evidence_provider.h"
#include "ocg/objects/point_evidence.h"
#include "test_support.h"

namespace ocg {
namespace {

// The members of an observation that hold something (their names in observation.h).
std::set<std::string> FilledFields(const KeyframeObservation& observation) {
  std::set<std::string> fields;
  if (!observation.observed.empty()) fields.insert("observed");
  if (!observation.updates.empty()) fields.insert("updates");
  if (!observation.present_by_points.empty()) fields.insert("present_by_points");
  if (!observation.forgotten.empty()) fields.insert("forgotten");
  if (!observation.restored.empty()) fields.insert("restored");
  return fields;
}

// Three map objects in front of a camera at the origin: 1 detected in this session (frame
// 12), 2 detected only in the previous session's last frames (frame 8; this one started
// at 10), 3 not detected but tracked by its own points. 1 and 3 changed geometry.
struct Scene {
  ObjectsOptions options;
  PinholeCamera camera = testing::TestCamera(525.0, 319.5, 239.5);
  Eigen::Matrix3d R_wg = Eigen::Matrix3d::Identity();
  SE3 T_cw;
  std::map<ObjectId, MapObject> objects;
  std::map<ObjectId, std::int64_t> detected = {{1, 12}, {2, 8}};
  std::map<ObjectId, bool> geometry_changed = {{1, true}, {3, true}};
  std::vector<PointObservation> tracked;

  Scene() {
    for (ObjectId id : {1, 2, 3}) {
      MapObject& object = objects[id];
      object.id = id;
      object.class_id = 40 + static_cast<int>(id);
      object.has_cuboid = true;
      object.cuboid.centre = Eigen::Vector3d(0.3 * static_cast<double>(id - 2), 0.0, 1.5);
      object.cuboid.size = Eigen::Vector3d(0.1, 0.2, 0.3);
    }
    for (std::uint64_t point = 0; point < 6; ++point) {
      objects[3].points.Vote(
          point, 3,
          objects[3].cuboid.centre +
              Eigen::Vector3d(0.01 * static_cast<double>(point) - 0.025, 0.0, 0.0));
      const ObjectPoint& own = objects[3].points.at(point);
      tracked.push_back({point, Eigen::Vector2d::Zero(), own.position});
    }
  }
  KeyframeObservation Fill(EvidenceProvider& provider) const {
    provider.AddFrame(&tracked);
    const ObjectMapContext context{options, camera, R_wg};
    const KeyframeEvidence keyframe{objects, detected, geometry_changed, 10,
                                    T_cw,    nullptr,  context};
    KeyframeObservation observation;
    provider.Fill(keyframe, &observation);
    return observation;
  }
};

TEST(EvidenceProvider, EachFillsTheFieldItNamesAndNoOther) {
  const Scene scene;
  std::vector<std::unique_ptr<EvidenceProvider>> providers;
  providers.push_back(std::make_unique<DetectionEvidence>());
  providers.push_back(std::make_unique<GeometryEvidence>());
  providers.push_back(std::make_unique<PointPresenceEvidence>());
  std::set<std::string> named;
  for (const auto& provider : providers) {
    SCOPED_TRACE(provider->Field());
    const KeyframeObservation observation = scene.Fill(*provider);
    EXPECT_EQ(FilledFields(observation), std::set<std::string>{provider->Field()});
    EXPECT_TRUE(named.insert(provider->Field()).second) << "two providers of one field";
  }
}

// One list of the sources: what the OCG's modes turn on is asked, and nothing else.
TEST(EvidenceProvider, TheModesChooseTheSources) {
  const auto fields = [](const OcgModes& modes) {
    std::vector<std::string> names;
    for (const auto& provider : EvidenceProvidersFor(modes)) names.push_back(provider->Field());
    return names;
  };
  EXPECT_EQ(fields(ParseOcgMode("paper")), (std::vector<std::string>{"observed", "updates"}));
  EXPECT_EQ(fields(ParseOcgMode("view+points")),
            (std::vector<std::string>{"observed", "present_by_points", "updates"}));
}

TEST(EvidenceProvider, EachReadsWhatTheMapShowsIt) {
  const Scene scene;
  DetectionEvidence detections;
  // Object 2's detections were made in the previous session, after its last keyframe.
  EXPECT_EQ(scene.Fill(detections).observed, std::vector<ObjectId>{1});
  GeometryEvidence geometry;
  const KeyframeObservation updates = scene.Fill(geometry);
  ASSERT_EQ(updates.updates.size(), 2u);
  EXPECT_EQ(*updates.updates.at(3).class_id, 43);
  EXPECT_TRUE(updates.updates.at(3).size->isApprox(Eigen::Vector3d(0.1, 0.2, 0.3)));
  PointPresenceEvidence points;
  // Objects 1 and 2 were detected (no question of their presence); 3 shows its points.
  EXPECT_EQ(scene.Fill(points).present_by_points, std::vector<ObjectId>{3});
  points.AddFrame(nullptr);  // a frame without a SLAM map: nothing tracked
  const ObjectMapContext context{scene.options, scene.camera, scene.R_wg};
  KeyframeObservation observation;
  points.Fill(
      {scene.objects, scene.detected, scene.geometry_changed, 10, scene.T_cw, nullptr, context},
      &observation);
  EXPECT_TRUE(observation.present_by_points.empty());
}

// A candidate (candidate_tracker.h) waits for another box for
// Objects.candidate_max_missed_frames frames or candidate_gap_seconds, the longer, and is
// handed on only when detected in the frame and its rays meet.
TEST(CandidateTracker, ACandidateWaitsTheLongerOfItsFramesAndSecondsThenEnds) {
  const Scene scene;
  const ObjectMapContext context{scene.options, scene.camera, scene.R_wg};
  std::map<ObjectId, MapObject> candidates;
  ObjectId next_id = -1;
  CandidateTracker tracker(&candidates, &next_id, context);
  ObjectSighting sighting;
  sighting.class_id = 41;
  sighting.box = {300, 200, 340, 260};
  tracker.Start(sighting, {});
  ASSERT_EQ(candidates.size(), 1u);
  EXPECT_EQ(candidates.begin()->first, -1);
  EXPECT_EQ(next_id, -2);
  int handed_on = 0;
  const auto ready = [&handed_on](MapObject&) { return ++handed_on > 0; };
  tracker.Update(10, 1.0, ready);   // 10 frames, 1 s
  tracker.Update(20, 20.0, ready);  // past its frames (15), within its seconds (30)
  EXPECT_EQ(candidates.size(), 1u);
  tracker.Update(40, 31.0, ready);
  EXPECT_TRUE(candidates.empty());
  // Detected in the frame, but one box's ray meets nothing: not handed on.
  tracker.Start(sighting, {});
  tracker.Update(0, 0.0, ready);
  EXPECT_EQ(candidates.size(), 1u);
  EXPECT_EQ(handed_on, 0);
}

}  // namespace
}  // namespace ocg
