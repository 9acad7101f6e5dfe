#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "ocg/ocg/replay_format.h"
#include "ocg_test_scene.h"

namespace ocg {
namespace {

const char* kLine =
    R"({"keyframe": 12, "timestamp": 1.5, "T_cw": [1,0,0,0.5, 0,1,0,0, 0,0,1,2, 0,0,0,1],)"
    R"( "camera": {"fx": 517.3, "fy": 516.5, "cx": 318.6, "cy": 255.3, "width": 640, "height": 480},)"
    R"( "observed": [3, 7, 9], "centroids": {"3": [1, 2, 3], "7": [0, 0, 1]}, "classes": {"3": 41}})";

TEST(ReplayFormat, ParsesTheSpecExample) {
  const KeyframeObservation observation = ParseObservationJson(kLine);
  EXPECT_EQ(observation.keyframe_id, 12);
  EXPECT_DOUBLE_EQ(observation.timestamp, 1.5);
  EXPECT_DOUBLE_EQ(observation.T_cw.translation().x(), 0.5);
  EXPECT_DOUBLE_EQ(observation.T_cw.translation().z(), 2.0);
  EXPECT_DOUBLE_EQ(observation.camera.fx, 517.3);
  EXPECT_EQ(observation.camera.height, 480);
  EXPECT_EQ(observation.observed, (std::vector<ObjectId>{3, 7, 9}));
  ASSERT_EQ(observation.updates.size(), 2u);
  EXPECT_TRUE(observation.updates.at(3).centroid->isApprox(Eigen::Vector3d(1, 2, 3)));
  EXPECT_EQ(*observation.updates.at(3).class_id, 41);
  EXPECT_FALSE(observation.updates.at(7).size.has_value());
}

TEST(ReplayFormat, RoundTrip) {
  KeyframeObservation observation =
      testing::MakeObservation(4, testing::LookAt({1, 2, 3}, {0, 0, 0}), {5, 2});
  observation.camera.k1 = 0.1;
  observation.updates[5].centroid = Eigen::Vector3d(0.5, 0.25, 0.125);
  observation.updates[5].size = Eigen::Vector3d(1, 2, 3);
  observation.forgotten = {8};
  observation.restored = {2};
  const KeyframeObservation parsed = ParseObservationJson(ObservationToJson(observation));
  EXPECT_EQ(parsed.observed, observation.observed);
  EXPECT_EQ(parsed.forgotten, (std::vector<ObjectId>{8}));
  EXPECT_EQ(parsed.restored, (std::vector<ObjectId>{2}));
  EXPECT_TRUE(ParseObservationJson(kLine).restored.empty());
  EXPECT_TRUE(parsed.T_cw.Matrix().isApprox(observation.T_cw.Matrix(), 1e-12));
  EXPECT_DOUBLE_EQ(parsed.camera.k1, 0.1);
  EXPECT_TRUE(parsed.updates.at(5).size->isApprox(Eigen::Vector3d(1, 2, 3)));
}

TEST(ReplayFormat, MalformedLinesSayWhatIsWrong) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{\"keyframe\": 1", "not valid JSON"},
      {"[1, 2]", "expected a JSON object"},
      {R"({"timestamp": 1})", "missing field \"keyframe\""},
      {R"({"keyframe": 1, "T_cw": [1, 0, 0]})", "16 numbers"},
      {R"({"keyframe": 1, "T_cw": [2,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]})", "not a rotation"},
      {R"({"keyframe": 1, "T_cw": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1], "camera": {"fx": 1}})",
       "missing field \"fy\""},
      {R"({"keyframe": 1, "T_cw": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1],
           "camera": {"fx": -1, "fy": 1, "cx": 1, "cy": 1, "width": 4, "height": 4}, "observed": []})",
       "Camera.fx"},
      {R"({"keyframe": 1, "T_cw": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1],
           "camera": {"fx": 1, "fy": 1, "cx": 1, "cy": 1, "width": 4, "height": 4}, "observed": [1],
           "centroids": {"x": [1, 2, 3]}})",
       "not an object id"},
      {R"({"keyframe": 1, "T_cw": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1],
           "camera": {"fx": 1, "fy": 1, "cx": 1, "cy": 1, "width": 4, "height": 4}, "observed": [1],
           "centroids": {"1": [1, 2]}})",
       "centroid of object 1"},
      {R"({"keyframe": "one"})", "wrong type"}};
  for (const auto& [line, expected] : cases) {
    try {
      ParseObservationJson(line);
      FAIL() << "accepted: " << line;
    } catch (const ReplayFormatError& error) {
      EXPECT_NE(std::string(error.what()).find(expected), std::string::npos)
          << "line: " << line << "\nerror: " << error.what();
    }
  }
}

TEST(ReplayFormat, StatesLineAndChangeLog) {
  ObjectStatus status;
  status.id = 3;
  status.state = ObjectState::kSuspicious;
  status.doubt = 30;
  status.active_edge_rate = 0.75;
  RemovalEvent removal;
  removal.keyframe_id = 12;
  removal.timestamp = 1.5;
  removal.object_id = 9;
  removal.class_id = 41;
  removal.centroid = Eigen::Vector3d(1, 2, 3);
  removal.doubt = 60;
  const auto line = nlohmann::json::parse(StatesLineJson(12, {status}, {removal}));
  EXPECT_EQ(line["keyframe"], 12);
  EXPECT_EQ(line["objects"][0]["state"], 4);
  EXPECT_EQ(line["objects"][0]["active_edge_rate"], 0.75);
  EXPECT_EQ(line["removed"], nlohmann::json::array({9}));
  const auto changes = nlohmann::json::parse(ChangeLogJson({removal}));
  EXPECT_EQ(changes["changes"][0]["class"], "cup");
  EXPECT_EQ(changes["changes"][0]["doubt"], 60.0);
  EXPECT_EQ(changes["changes"][0]["centroid"][2], 3.0);
}

}  // namespace
}  // namespace ocg
