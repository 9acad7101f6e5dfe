#include <gtest/gtest.h>

#include <cstring>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

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

// A value unlike the default for each type a field of the observation has; `n` makes the
// fields of one type differ from each other. A field of a new type fails to compile here
// until the test knows it.
void SetSample(std::int64_t* value, int n) { *value = 1000 + n; }
void SetSample(int* value, int n) { *value = 40 + n; }
void SetSample(double* value, int n) { *value = 0.375 + n; }
void SetSample(SE3* value, int n) { *value = testing::LookAt({1.0 + n, 2, 3}, {0, 0.5, 0}); }
void SetSample(PinholeCamera* camera, int n) {
  int k = n;
  VisitCameraFields([&k](const ObservationField&, auto& member) { SetSample(&member, ++k); },
                    *camera);
  camera->cx = 300, camera->cy = 200, camera->width = 640, camera->height = 480;
}
void SetSample(std::vector<ObjectId>* ids, int n) { *ids = {n, 2 * n + 1}; }
void SetSample(std::optional<Eigen::Vector3d>* vector, int n) {
  *vector = Eigen::Vector3d(0.5 * n, 0.25, 1.125);
}
void SetSample(std::optional<int>* value, int n) { *value = 40 + n; }

bool Same(const SE3& a, const SE3& b) { return a.Matrix().isApprox(b.Matrix(), 1e-12); }
bool Same(const PinholeCamera& a, const PinholeCamera& b) {
  bool same = true;
  VisitCameraFields(
      [&same](const ObservationField&, const auto& x, const auto& y) { same = same && x == y; }, a,
      b);
  return same;
}
template <typename Value>
bool Same(const Value& a, const Value& b) {
  return a == b;
}

// Every field VisitObservationFields and VisitObjectUpdateFields list, each set, comes
// back from a replay line: what a new field gets from the one list without more code.
TEST(ReplayFormat, EveryListedFieldRoundTrips) {
  KeyframeObservation observation;
  int n = 0;
  VisitObservationFields([&n](const ObservationField&, auto& member) { SetSample(&member, ++n); },
                         observation);
  for (const ObjectId id : {3, 7}) {
    VisitObjectUpdateFields(
        [&n](const ObservationField&, auto& member) { SetSample(&member, ++n); },
        observation.updates[id]);
  }
  const std::string line = ObservationToJson(observation);
  const KeyframeObservation parsed = ParseObservationJson(line);

  std::set<std::string> names;
  VisitObservationFields(
      [&names](const ObservationField& field, const auto& written, const auto& read) {
        names.insert(field.name);
        EXPECT_TRUE(Same(written, read)) << field.name;
      },
      observation, parsed);
  ASSERT_EQ(parsed.updates.size(), 2u);
  for (const ObjectId id : {3, 7}) {
    VisitObjectUpdateFields(
        [&names, id](const ObservationField& field, const auto& written, const auto& read) {
          names.insert(field.name);
          ASSERT_TRUE(read.has_value()) << field.name << " of object " << id;
          EXPECT_EQ(*written, *read) << field.name << " of object " << id;
        },
        observation.updates.at(id), parsed.updates.at(id));
  }
  // Each under its own name: the line holds exactly the listed fields.
  std::set<std::string> keys;
  const nlohmann::json written = nlohmann::json::parse(line);
  for (const auto& [key, value] : written.items()) keys.insert(key);
  EXPECT_EQ(keys, names);
  EXPECT_EQ(ObservationToJson(parsed), line);
}

// The error a line gives, or "accepted".
std::string ErrorOf(const nlohmann::json& line) {
  try {
    ParseObservationJson(line.dump());
  } catch (const ReplayFormatError& error) {
    return error.what();
  }
  return "accepted";
}

TEST(ReplayFormat, UnknownFieldIsAnErrorNamingIt) {
  nlohmann::json root = nlohmann::json::parse(kLine);
  EXPECT_NO_THROW(ParseObservationJson(root.dump()));
  nlohmann::json misspelt = root;
  misspelt["present_by_point"] = nlohmann::json::array({3});
  EXPECT_NE(ErrorOf(misspelt).find("unknown field \"present_by_point\""), std::string::npos)
      << ErrorOf(misspelt);
  EXPECT_NE(ErrorOf(misspelt).find("present_by_points"), std::string::npos);  // the known ones
  nlohmann::json camera = root;
  camera["camera"]["k4"] = 0.1;
  EXPECT_NE(ErrorOf(camera).find("unknown field \"k4\" in \"camera\""), std::string::npos)
      << ErrorOf(camera);
}

TEST(ReplayFormat, FieldErrorsNameTheField) {
  nlohmann::json root = nlohmann::json::parse(kLine);
  nlohmann::json negative = root;
  negative["sizes"] = {{"3", {0.1, -0.2, 0.3}}};
  EXPECT_NE(ErrorOf(negative).find("size of object 3 must be non-negative"), std::string::npos)
      << ErrorOf(negative);
  nlohmann::json last_row = root;
  last_row["T_cw"][12] = 1.0;
  EXPECT_NE(ErrorOf(last_row).find("\"T_cw\" last row must be [0, 0, 0, 1]"), std::string::npos)
      << ErrorOf(last_row);
  nlohmann::json not_a_map = root;
  not_a_map["classes"] = nlohmann::json::array({41});
  EXPECT_NE(ErrorOf(not_a_map).find("\"classes\" must be an object {object id: class}"),
            std::string::npos)
      << ErrorOf(not_a_map);
  nlohmann::json timestamp = root;
  timestamp["timestamp"] = "noon";
  EXPECT_NE(ErrorOf(timestamp).find("\"timestamp\" must be a number"), std::string::npos)
      << ErrorOf(timestamp);
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
