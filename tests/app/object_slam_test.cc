// ObjectSlam, the library entry point: the same outputs as `ocg_slam run` (which must be
// argument parsing around it), and its contract (shutdown, errors).
#include "ocg/app/object_slam.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "ocg/core/file_io.h"
#include "ocg/core/map_file.h"
#include "ocg/core/settings_file.h"
#include "ocg/io/sequence.h"
#include "ocg/sim/generator.h"
#include "ocg/sim/presets.h"
#include "ocg/slam/map_file.h"
#include "run_progress.h"  // src/app: run.json's progress series
#include "session_file.h"  // src/app: the map file's session record
#include "test_support.h"

namespace ocg {
namespace {

constexpr int kFrames = 60;

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in) << "cannot read " << path;
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// A short smoke sequence with detections, generated once for every test.
const std::string& SmokeSequence() {
  static const std::string folder = [] {
    const std::string out = testing::MakeTempDir("object_slam_smoke") + "/smoke";
    sim::GeneratorOptions options;
    options.max_frames = kFrames;
    options.keyframe_interval = 0;
    sim::Generate(sim::MakePreset("smoke", 1), out, options);
    return out;
  }();
  return folder;
}

Settings SmokeSettings() {
  return LoadSettings(SmokeSequence() + "/camera.yaml", CameraNeed::kIntrinsics).settings;
}

// Feeds the sequence as `ocg_slam run` reads it; colour: the frames as BGR.
void RunSequence(ObjectSlam& slam, bool colour) {
  const ImageSequence sequence = ReadTumSequence(SmokeSequence());
  const EaoDetectionFolder detections(SmokeSequence() + "/detections", [&] {
    std::vector<std::string> names;
    for (const TimedImage& image : sequence.images) names.push_back(image.timestamp_text);
    return names;
  }());
  for (const TimedImage& image : sequence.images) {
    cv::Mat pixels = cv::imread(image.path, cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(pixels.empty()) << image.path;
    if (colour) cv::cvtColor(pixels, pixels, cv::COLOR_GRAY2BGR);
    const std::optional<SE3> T_cw =
        slam.Track(pixels, image.timestamp, detections.ForFrame(image.timestamp_text),
                   {image.timestamp_text, image.path});
    EXPECT_EQ(T_cw.has_value(), slam.Pose().has_value());
  }
}

TEST(ObjectSlam, WritesWhatTheToolWrites) {
  const std::string tool_out = testing::MakeTempDir("object_slam_tool");
  const std::string command = std::string(OCG_SLAM_TOOL) + " run --settings " + SmokeSequence() +
                              "/camera.yaml --sequence " + SmokeSequence() + " --detections " +
                              SmokeSequence() + "/detections --snapshots none --out " + tool_out +
                              " --log-level warn > /dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;

  const std::string library_out = testing::MakeTempDir("object_slam_library");
  ObjectSlamOptions options;
  options.snapshots = ParseSnapshotPolicy("none");
  ObjectSlam slam(SmokeSettings(), options);
  RunSequence(slam, false);
  slam.Shutdown();
  const nlohmann::json report =
      slam.Save(library_out, {SmokeSequence(), "camera.yaml", SmokeSequence() + "/detections", 0});
  EXPECT_EQ(report["frames"], kFrames);
  EXPECT_GT(report["frames_tracked"].get<int>(), kFrames / 2);
  ASSERT_TRUE(report.contains("objects"));
  EXPECT_GT(report["objects"]["objects_created"].get<int>(), 0);
  // The objects' colours from the keyframes' images (the sightings at keyframes).
  EXPECT_GT(report["objects"]["colour_signatures"]["keyframe_images"].get<int>(), 0);
  EXPECT_GT(report["objects"]["colour_signatures"]["sightings"].get<int>(), 0);
  for (const char* file : {"KeyFrameTrajectory.txt", "CameraTrajectory.txt", "map_points.ply",
                           "objects.json", "changes.json", "ocg.json", "ocg_observations.jsonl"}) {
    EXPECT_EQ(ReadFile(library_out + "/" + file), ReadFile(tool_out + "/" + file))
        << file << " differs between ObjectSlam and ocg_slam run";
  }
  // The readers give what Save wrote.
  EXPECT_EQ(slam.Objects(), ReadFile(library_out + "/objects.json"));
  EXPECT_EQ(slam.Changes(), ReadFile(library_out + "/changes.json"));
  EXPECT_EQ(slam.KeyFrameTrajectory().size(), report["keyframes"].get<std::size_t>());
}

// One SLAM run feeding object layers in several modes writes, for each mode, what a run of
// its own in that mode writes (SLAM never reads the objects), so tools/object_table.py runs
// SLAM once per sequence. A layer that took the run's own mode would write paper's graph.
TEST(ObjectSlam, AlsoModesWriteWhatRunsOfTheirOwnWrite) {
  const std::string tool_out = testing::MakeTempDir("object_slam_tool_visibility");
  const std::string command = std::string(OCG_SLAM_TOOL) + " run --settings " + SmokeSequence() +
                              "/camera.yaml --sequence " + SmokeSequence() + " --detections " +
                              SmokeSequence() + "/detections --mode visibility --snapshots none " +
                              "--out " + tool_out + " --log-level warn > /dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;

  const std::string paper_out = testing::MakeTempDir("object_slam_paper");
  const std::string visibility_out = testing::MakeTempDir("object_slam_also_visibility");
  Settings settings = SmokeSettings();
  settings.ocg.mode = "paper";
  ObjectSlamOptions options;
  options.snapshots = ParseSnapshotPolicy("none");
  options.also_modes = {{"visibility", visibility_out}};
  ObjectSlam slam(settings, options);
  RunSequence(slam, false);
  slam.Shutdown();
  slam.Save(paper_out, {SmokeSequence(), "camera.yaml", SmokeSequence() + "/detections", 0});
  for (const char* file : {"KeyFrameTrajectory.txt", "CameraTrajectory.txt", "map_points.ply",
                           "objects.json", "changes.json", "ocg.json", "ocg_observations.jsonl"}) {
    EXPECT_EQ(ReadFile(visibility_out + "/" + file), ReadFile(tool_out + "/" + file))
        << file << " of the also-mode differs from a run of its own";
  }
  EXPECT_NE(ReadFile(visibility_out + "/ocg.json"), ReadFile(paper_out + "/ocg.json"));
  const nlohmann::json report = nlohmann::json::parse(ReadFile(visibility_out + "/run.json"));
  EXPECT_EQ(report["objects"]["ocg_mode"], "visibility");
  // Every mode's sightings take their colours from the keyframe images, read once for all.
  const nlohmann::json tool_report = nlohmann::json::parse(ReadFile(tool_out + "/run.json"));
  EXPECT_GT(report["objects"]["colour_signatures"]["sightings"].get<int>(), 0);
  EXPECT_EQ(report["objects"]["colour_signatures"], tool_report["objects"]["colour_signatures"]);
}

TEST(ObjectSlam, AlsoModesNeedObjectsAndSequentialMode) {
  ObjectSlamOptions options;
  options.snapshots = ParseSnapshotPolicy("none");
  options.map_objects = false;
  options.also_modes = {{"off", testing::MakeTempDir("object_slam_no_objects")}};
  EXPECT_THROW(ObjectSlam(SmokeSettings(), options), SettingsError);
  options.map_objects = true;
  Settings threaded = SmokeSettings();
  threaded.system.sequential = false;
  EXPECT_THROW(ObjectSlam(threaded, options), SettingsError);
  options.also_modes = {{"no_such_mode", testing::MakeTempDir("object_slam_bad_mode")}};
  EXPECT_ANY_THROW(ObjectSlam(SmokeSettings(), options));
}

// Grey pixels given as BGR go through the same conversion to grey: the same trajectory.
TEST(ObjectSlam, ColourFramesTrackLikeGrey) {
  std::vector<std::vector<StampedPose>> trajectories;
  for (const bool colour : {false, true}) {
    ObjectSlamOptions options;
    options.snapshots = ParseSnapshotPolicy("none");
    options.map_objects = false;
    ObjectSlam slam(SmokeSettings(), options);
    RunSequence(slam, colour);
    slam.Shutdown();
    trajectories.push_back(slam.KeyFrameTrajectory());
  }
  ASSERT_FALSE(trajectories[0].empty());
  ASSERT_EQ(trajectories[0].size(), trajectories[1].size());
  for (std::size_t i = 0; i < trajectories[0].size(); ++i) {
    EXPECT_EQ(trajectories[0][i].timestamp, trajectories[1][i].timestamp);
    EXPECT_EQ(trajectories[0][i].T_wc.Matrix(), trajectories[1][i].T_wc.Matrix());
  }
}

TEST(ObjectSlam, ShutdownTwiceIsSafeAndTrackAfterwardsThrows) {
  ObjectSlamOptions options;
  options.snapshots = ParseSnapshotPolicy("none");
  ObjectSlam slam(SmokeSettings(), options);
  const cv::Mat frame(480, 640, CV_8UC1, cv::Scalar(128));
  slam.Track(frame, 0.0, {});
  EXPECT_THROW(slam.Save(testing::MakeTempDir("object_slam_early"), {}), std::logic_error);
  slam.Shutdown();
  EXPECT_NO_THROW(slam.Shutdown());
  EXPECT_TRUE(slam.IsShutDown());
  try {
    slam.Track(frame, 0.1, {});
    FAIL() << "Track after Shutdown did not throw";
  } catch (const std::logic_error& error) {
    EXPECT_NE(std::string(error.what()).find("shut down"), std::string::npos) << error.what();
  }
  EXPECT_EQ(slam.FramesGiven(), 1u);
}

TEST(ObjectSlam, RefusesImagesItCannotTrack) {
  ObjectSlamOptions options;
  options.snapshots = ParseSnapshotPolicy("none");
  ObjectSlam slam(SmokeSettings(), options);
  EXPECT_THROW(slam.Track(cv::Mat(), 0.0, {}), std::invalid_argument);
  EXPECT_THROW(slam.Track(cv::Mat(480, 640, CV_32FC1, cv::Scalar(0.5)), 0.0, {}),
               std::invalid_argument);
  EXPECT_THROW(slam.Track(cv::Mat(480, 640, CV_8UC4, cv::Scalar(1, 2, 3, 4)), 0.0, {}),
               std::invalid_argument);
  EXPECT_EQ(slam.FramesGiven(), 0u);
}

// The rule of the frame lists' readers, for every caller (Python feeds Track directly).
TEST(ObjectSlam, RefusesTimesThatAreNotFiniteOrNotLater) {
  ObjectSlamOptions options;
  options.snapshots = ParseSnapshotPolicy("none");
  ObjectSlam slam(SmokeSettings(), options);
  const cv::Mat frame(480, 640, CV_8UC1, cv::Scalar(128));
  EXPECT_EQ(slam.LastFrame().state, TrackingState::kNoImages);
  EXPECT_THROW(slam.Track(frame, std::nan(""), {}), std::invalid_argument);
  EXPECT_THROW(slam.Track(frame, HUGE_VAL, {}), std::invalid_argument);
  slam.Track(frame, 1.0, {});
  EXPECT_EQ(slam.LastFrame().state, TrackingState::kNotInitialized);
  EXPECT_FALSE(slam.LastFrame().T_cw.has_value());
  EXPECT_THROW(slam.Track(frame, 1.0, {}), std::invalid_argument);
  EXPECT_THROW(slam.Track(frame, 0.5, {}), std::invalid_argument);
  EXPECT_EQ(slam.FramesGiven(), 1u);
  slam.Track(frame, 1.5, {});
  EXPECT_EQ(slam.FramesGiven(), 2u);
}

TEST(ObjectSlam, MissingVocabularyIsAFileError) {
  ObjectSlamOptions options;
  options.vocabulary_path = testing::MakeTempDir("object_slam_vocabulary") + "/none.ocgvoc";
  EXPECT_THROW(ObjectSlam(SmokeSettings(), options), FileError);
}

// Map files (docs/sessions.md): the session record, and the rest of the payload (the SLAM
// map and the object layer's state) as bytes.
std::pair<app_detail::SessionRecord, std::string> ReadSessionMap(const std::string& path) {
  PayloadStream in(ReadMapFile(path, app_detail::kMapFileKind, app_detail::kMapFileVersion));
  const app_detail::SessionRecord record = app_detail::LoadSessionRecord(in);
  EXPECT_EQ(record.orb.levels, SmokeSettings().orb.levels);
  return {record, in.payload().substr(static_cast<std::size_t>(in.tellg()))};
}

std::string MapFileErrorOf(const Settings& settings, const ObjectSlamOptions& options) {
  try {
    ObjectSlam slam(settings, options);
  } catch (const MapFileError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no MapFileError for " << options.load_map;
  return "";
}

TEST(ObjectSlamMapFile, LoadingAndSavingAgainKeepsTheWholeState) {
  const std::string folder = testing::MakeTempDir("object_slam_map");
  ObjectSlamOptions options;
  options.snapshots = ParseSnapshotPolicy("none");
  ObjectSlam first(SmokeSettings(), options);
  EXPECT_EQ(first.Session(), 0);
  RunSequence(first, false);
  first.Shutdown();
  first.SaveMap(folder + "/a.ocgmap");

  options.load_map = folder + "/a.ocgmap";
  ObjectSlam second(SmokeSettings(), options);
  EXPECT_EQ(second.Session(), 1);
  second.Shutdown();
  second.SaveMap(folder + "/b.ocgmap");

  const auto [a_record, a_state] = ReadSessionMap(folder + "/a.ocgmap");
  const auto [b_record, b_state] = ReadSessionMap(folder + "/b.ocgmap");
  EXPECT_EQ(a_record.sessions, 1);
  EXPECT_EQ(b_record.sessions, 2);
  EXPECT_EQ(a_record.frames, kFrames);
  EXPECT_EQ(b_record.frames, kFrames);  // the second session was given none
  EXPECT_TRUE(a_record.has_objects);
  EXPECT_EQ(a_record.settings_source, SmokeSequence() + "/camera.yaml");
  EXPECT_EQ(a_record.settings_text, ReadFile(SmokeSequence() + "/camera.yaml"));
  EXPECT_EQ(a_record.camera.fx, SmokeSettings().camera.model.fx);
  EXPECT_EQ(a_record.vocabulary_words, first.VocabularyWords());
  // Every byte of the SLAM map, the object map and the OCG came back.
  EXPECT_GT(a_state.size(), 100000u);
  EXPECT_TRUE(a_state == b_state) << "the state saved after loading differs from the loaded one";
  // The readers agree: objects with their OCG states and doubts, the change log, keyframes.
  EXPECT_EQ(second.Objects(), first.Objects());
  EXPECT_EQ(second.Changes(), first.Changes());
  EXPECT_NE(first.Objects().find("\"first_session\": 0"), std::string::npos);
  ASSERT_EQ(second.KeyFrameTrajectory().size(), first.KeyFrameTrajectory().size());
  for (std::size_t i = 0; i < first.KeyFrameTrajectory().size(); ++i) {
    EXPECT_EQ(second.KeyFrameTrajectory()[i].T_wc.Matrix(),
              first.KeyFrameTrajectory()[i].T_wc.Matrix());
  }
}

// A run whose tracking was lost too long made a second map (its objects start over in it):
// the map file keeps both maps, the second one current with the object map built in it,
// and a later session gets the whole atlas back (both maps with their keyframes and
// points, the objects) and saves the same state again.
TEST(ObjectSlamMapFile, AnAtlasOfTwoMapsAndItsObjectsContinue) {
  const std::string folder = testing::MakeTempDir("object_slam_map");
  Settings settings = SmokeSettings();
  settings.tracking.new_map_after_lost_seconds = 0.5;
  settings.loop_closing.merge_maps = false;
  ObjectSlamOptions options;
  options.snapshots = ParseSnapshotPolicy("none");
  ObjectSlam first(settings, options);
  const ImageSequence sequence = ReadTumSequence(SmokeSequence());
  const EaoDetectionFolder detections(SmokeSequence() + "/detections", [&] {
    std::vector<std::string> names;
    for (const TimedImage& image : sequence.images) names.push_back(image.timestamp_text);
    return names;
  }());
  // The first half, then grey frames (lost for 0.6 s), then the second half: a new map.
  const std::size_t half = sequence.images.size() / 2;
  double timestamp = 0.0;
  const double step = sequence.images[1].timestamp - sequence.images[0].timestamp;
  const auto give = [&](const cv::Mat& pixels, const TimedImage* image) {
    timestamp = image ? image->timestamp : timestamp + step;
    const std::string text = std::to_string(timestamp);
    first.Track(pixels, timestamp,
                image ? detections.ForFrame(image->timestamp_text) : std::vector<Detection>{},
                {text, image ? image->path : std::string()});
  };
  for (std::size_t i = 0; i < half; ++i)
    give(cv::imread(sequence.images[i].path, cv::IMREAD_GRAYSCALE), &sequence.images[i]);
  const cv::Mat grey = cv::Mat(cv::imread(sequence.images[0].path, cv::IMREAD_GRAYSCALE).size(),
                               CV_8UC1, cv::Scalar(128));
  for (int blind = 0; blind < 20; ++blind) give(grey, nullptr);
  for (std::size_t i = half; i < sequence.images.size(); ++i) {
    TimedImage later = sequence.images[i];
    later.timestamp = timestamp + step;
    give(cv::imread(later.path, cv::IMREAD_GRAYSCALE), &later);
  }
  first.Shutdown();
  const nlohmann::json report = first.Save(folder, {});
  ASSERT_EQ(report["maps"].size(), 2u) << report["maps"].dump();
  ASSERT_EQ(report["maps"][1]["current"], true);
  ASSERT_GT(report["maps"][0]["keyframes"].get<int>(), 2);
  ASSERT_GT(report["maps"][1]["keyframes"].get<int>(), 2);
  EXPECT_GT(report["objects"]["objects_live"].get<int>(), 0);  // mapped in the second map
  first.SaveMap(folder + "/a.ocgmap");

  options.load_map = folder + "/a.ocgmap";
  ObjectSlam second(settings, options);
  second.Shutdown();
  const nlohmann::json loaded = second.Save(testing::MakeTempDir("object_slam_map_loaded"), {});
  ASSERT_EQ(loaded["maps"].size(), 2u);
  for (std::size_t m = 0; m < 2; ++m) {
    for (const char* key : {"current", "keyframes", "map_points", "merged_into"})
      EXPECT_EQ(loaded["maps"][m][key], report["maps"][m][key]) << "map " << m << ": " << key;
  }
  EXPECT_EQ(loaded["session"]["keyframes_loaded"].get<int>(),
            report["maps"][0]["keyframes"].get<int>() + report["maps"][1]["keyframes"].get<int>());
  EXPECT_EQ(second.Objects(), first.Objects());
  second.SaveMap(folder + "/b.ocgmap");
  const auto [a_record, a_state] = ReadSessionMap(folder + "/a.ocgmap");
  const auto [b_record, b_state] = ReadSessionMap(folder + "/b.ocgmap");
  EXPECT_EQ(a_record.keyframes, b_record.keyframes);
  EXPECT_TRUE(a_state == b_state) << "the state saved after loading differs from the loaded one";
}

// A later session's keyframes number their frames after every frame of the earlier
// sessions, as the object layer numbers its sightings: a sighting's frame finds the
// keyframe made at it in every session (the box appearance of docs/sessions.md reads the
// keyframe's features by it). The second session here is the same sequence again.
TEST(ObjectSlamMapFile, ALaterSessionsKeyframesCountFramesOverAllSessions) {
  const std::string folder = testing::MakeTempDir("object_slam_map");
  ObjectSlamOptions options;
  options.snapshots = ParseSnapshotPolicy("none");
  ObjectSlam first(SmokeSettings(), options);
  RunSequence(first, false);
  first.Shutdown();
  first.SaveMap(folder + "/a.ocgmap");
  options.load_map = folder + "/a.ocgmap";
  ObjectSlam second(SmokeSettings(), options);
  RunSequence(second, false);
  second.Shutdown();
  second.SaveMap(folder + "/b.ocgmap");
  // Frame id and timestamp of every keyframe.
  const auto keyframes_of = [](const std::string& path) {
    PayloadStream in(ReadSessionMap(path).second);
    Map map;
    LoadMap(in, &map, SmokeSettings().orb.levels);
    std::map<KeyFrameId, std::pair<std::uint64_t, double>> frames;
    for (const auto& [id, keyframe] : map.keyframes())
      frames[id] = {keyframe->frame_id, keyframe->timestamp};
    return frames;
  };
  const ImageSequence sequence = ReadTumSequence(SmokeSequence());
  const auto before = keyframes_of(folder + "/a.ocgmap");
  int later = 0;
  for (const auto& [id, frame] : keyframes_of(folder + "/b.ocgmap")) {
    // Frame n of session 1 is frame kFrames + n of the map.
    const std::uint64_t in_session = before.count(id) > 0 ? frame.first : frame.first - kFrames;
    if (before.count(id) > 0) {
      EXPECT_EQ(frame, before.at(id));
    } else {
      ++later;
      EXPECT_GE(frame.first, static_cast<std::uint64_t>(kFrames)) << "keyframe " << id;
    }
    ASSERT_LT(in_session, sequence.images.size()) << "keyframe " << id;
    EXPECT_EQ(frame.second, sequence.images[in_session].timestamp) << "keyframe " << id;
  }
  EXPECT_GT(later, 0) << "the case needs a keyframe of the second session";
}

// A foreign file fails before the vocabulary is read (here: there is none to read).
TEST(ObjectSlamMapFile, ForeignFileFailsFirst) {
  ObjectSlamOptions options;
  options.vocabulary_path = testing::MakeTempDir("object_slam_map") + "/none.ocgvoc";
  options.load_map = ReadTumSequence(SmokeSequence()).images.front().path;
  const std::string message = MapFileErrorOf(SmokeSettings(), options);
  EXPECT_NE(message.find(options.load_map), std::string::npos) << message;
  EXPECT_NE(message.find("not an OCG-SLAM map file"), std::string::npos) << message;
}

TEST(ObjectSlamMapFile, SoundEnvelopeWithUnreadablePayloadIsDamaged) {
  ObjectSlamOptions options;
  options.load_map = testing::MakeTempDir("object_slam_map") + "/garbage.ocgmap";
  WriteMapFile(options.load_map, app_detail::kMapFileKind, app_detail::kMapFileVersion, "abc");
  const std::string message = MapFileErrorOf(SmokeSettings(), options);
  EXPECT_NE(message.find("cannot read its session record"), std::string::npos) << message;
}

// A map of the smoke sequence's 60 frames (with objects), saved once for every test.
const std::string& SmokeMap() {
  static const std::string path = [] {
    const std::string out = testing::MakeTempDir("object_slam_smoke_map") + "/smoke.ocgmap";
    ObjectSlamOptions options;
    options.snapshots = ParseSnapshotPolicy("none");
    ObjectSlam slam(SmokeSettings(), options);
    RunSequence(slam, false);
    slam.Shutdown();
    slam.SaveMap(out);
    return out;
  }();
  return path;
}

// The smoke map written again as format version `version`: its session record without
// the fields later versions added, its SLAM map as one map before version 5, the object
// layer's part as it was.
std::string SmokeMapAsVersion(std::uint32_t version, const std::string& name,
                              const std::function<void(app_detail::SessionRecord*)>& edit = {}) {
  auto [record, rest] = ReadSessionMap(SmokeMap());
  if (edit) edit(&record);
  std::ostringstream payload;
  app_detail::SaveSessionRecord(record, payload, version);
  if (version < 5) {
    std::istringstream slam_part(rest);
    Map map;
    LoadMap(slam_part, &map, SmokeSettings().orb.levels);
    const std::string objects = rest.substr(static_cast<std::size_t>(slam_part.tellg()));
    std::ostringstream single;
    SaveMap(map, single, {}, MapFileFormat::kSingleMap);
    rest = single.str() + objects;
  }
  const std::string path = testing::MakeTempDir("object_slam_map") + "/" + name;
  WriteMapFile(path, app_detail::kMapFileKind, version, payload.str() + rest);
  return path;
}

TEST(ObjectSlamMapFile, AnotherCameraIsRefused) {
  Settings other = SmokeSettings();
  other.camera.model.fx += 1.0;
  ObjectSlamOptions options;
  options.load_map = SmokeMap();
  const std::string message = MapFileErrorOf(other, options);
  EXPECT_NE(message.find("was made with the camera"), std::string::npos) << message;
}

// Keypoints carry their pyramid level and map points their scale distances from it: a map
// continued with another pyramid read past the end of the pyramid's tables. Refused before
// the vocabulary is read, naming the key and both values.
TEST(ObjectSlamMapFile, AnotherOrbPyramidIsRefusedNamingTheKeyAndBothValues) {
  ObjectSlamOptions options;
  options.load_map = SmokeMap();
  options.vocabulary_path = testing::MakeTempDir("object_slam_map") + "/none.ocgvoc";
  const Settings made_with = SmokeSettings();
  ASSERT_EQ(made_with.orb.levels, 8);
  struct Case {
    int levels;
    double scale_factor;
    std::string expected;
  };
  for (const Case& c :
       {Case{3, 1.2, "ORBextractor.nLevels: 8 ('"}, Case{12, 1.2, "ORBextractor.nLevels: 8 ('"},
        Case{8, 1.5, "ORBextractor.scaleFactor: 1.2 ('"}}) {
    Settings other = made_with;
    other.orb.levels = c.levels;
    other.orb.scale_factor = c.scale_factor;
    const std::string message = MapFileErrorOf(other, options);
    EXPECT_NE(message.find("map file '" + SmokeMap() + "' was made with " + c.expected),
              std::string::npos)
        << message;
    const std::string given = c.levels != 8 ? "ORBextractor.nLevels: " + std::to_string(c.levels)
                                            : "ORBextractor.scaleFactor: 1.5";
    EXPECT_NE(message.find("gives " + given), std::string::npos) << message;
  }
}

// A vocabulary of the same size with other words would make the map's BoW vectors
// meaningless (no relocalization, no loop): named as the cause.
TEST(ObjectSlamMapFile, AVocabularyOfTheSameSizeWithOtherWordsIsNamed) {
  ObjectSlamOptions options;
  options.snapshots = ParseSnapshotPolicy("none");
  options.load_map = SmokeMap();
  const Vocabulary original = Vocabulary::Load(SmokeSettings().vocabulary.Resolve());
  std::vector<NodeId> parents;
  std::vector<Descriptor> descriptors;
  std::vector<double> weights;
  std::vector<bool> leaves;
  for (NodeId node = 0; node < original.NodeCount(); ++node) {
    parents.push_back(original.Parent(node));
    descriptors.push_back(original.NodeDescriptor(node));
    weights.push_back(original.Weight(node));
    leaves.push_back(original.IsLeaf(node));
  }
  descriptors[original.WordNode(17)][0] ^= 1;  // one bit of one word
  options.vocabulary_path = testing::MakeTempDir("object_slam_map") + "/other.ocgvoc";
  Vocabulary::FromNodes(original.branching(), original.depth(), parents, descriptors, weights,
                        leaves)
      .SaveBinary(options.vocabulary_path);
  const std::string message = MapFileErrorOf(SmokeSettings(), options);
  EXPECT_NE(message.find("was made with another vocabulary"), std::string::npos) << message;
  EXPECT_NE(message.find("'" + options.vocabulary_path + "' has other words"), std::string::npos)
      << message;
  EXPECT_NE(message.find("the same count " + std::to_string(original.WordCount())),
            std::string::npos)
      << message;
  // The vocabulary it was made with loads it.
  options.vocabulary_path.clear();
  ObjectSlam slam(SmokeSettings(), options);
  EXPECT_EQ(slam.Session(), 1);
}

// Files of the previous format (version 3) did not record the ORB pyramid: it is read
// from the settings text they saved, so they load with their own settings and are refused
// with another pyramid like new files.
TEST(ObjectSlamMapFile, OlderFilesTakeTheirPyramidFromTheSettingsTheySaved) {
  const std::string path = SmokeMapAsVersion(3, "v3.ocgmap");
  ObjectSlamOptions options;
  options.snapshots = ParseSnapshotPolicy("none");
  options.load_map = path;
  {
    ObjectSlam slam(SmokeSettings(), options);
    EXPECT_EQ(slam.Session(), 1);
    EXPECT_GT(slam.KeyFrameTrajectory().size(), 2u);
  }
  Settings other = SmokeSettings();
  other.orb.levels = 3;
  const std::string message = MapFileErrorOf(other, options);
  EXPECT_NE(message.find("ORBextractor.nLevels: 8"), std::string::npos) << message;
  // Without settings text (made in code): the defaults, ORB-SLAM2's 8 levels of 1.2.
  options.load_map = SmokeMapAsVersion(3, "v3_no_text.ocgmap",
                                       [](app_detail::SessionRecord* r) { r->settings_text = ""; });
  EXPECT_NE(MapFileErrorOf(other, options).find("ORBextractor.nLevels: 8"), std::string::npos);
}

// A map with no keyframe holds nothing a later session could relocalize in: not written
// (the run's other outputs are), and said to be empty on load (files of older builds).
TEST(ObjectSlamMapFile, AnEmptyMapIsNotSavedAndIsNamedEmptyOnLoad) {
  const std::string folder = testing::MakeTempDir("object_slam_map");
  ObjectSlamOptions options;
  options.snapshots = ParseSnapshotPolicy("none");
  {
    ObjectSlam slam(SmokeSettings(), options);
    slam.Shutdown();
    try {
      slam.SaveMap(folder + "/empty.ocgmap");
      ADD_FAILURE() << "an empty map was saved";
    } catch (const MapFileError& error) {
      EXPECT_NE(std::string(error.what()).find("the map is empty"), std::string::npos)
          << error.what();
    }
    EXPECT_FALSE(std::ifstream(folder + "/empty.ocgmap").good());
    EXPECT_NO_THROW(slam.Save(folder, {}));
  }
  // As older builds wrote it: a record, an empty SLAM map, no objects.
  for (const std::uint32_t version : {3u, app_detail::kMapFileVersion}) {
    app_detail::SessionRecord record = ReadSessionMap(SmokeMap()).first;
    record.keyframes = 0;
    record.has_objects = false;
    std::ostringstream payload;
    app_detail::SaveSessionRecord(record, payload, version);
    Map empty;
    SaveMap(empty, payload, {}, version < 5 ? MapFileFormat::kSingleMap : MapFileFormat::kAtlas);
    options.load_map = folder + "/empty_v" + std::to_string(version) + ".ocgmap";
    WriteMapFile(options.load_map, app_detail::kMapFileKind, version, payload.str());
    const std::string message = MapFileErrorOf(SmokeSettings(), options);
    EXPECT_NE(message.find("map file '" + options.load_map + "': the map is empty"),
              std::string::npos)
        << message;
  }
}

// Long runs show their growth: Status() now, and run.json's "progress" over the run.
TEST(ObjectSlam, StatusCountsTheRunAndRunJsonKeepsItsSeries) {
  ObjectSlamOptions options;
  options.snapshots = ParseSnapshotPolicy("none");
  ObjectSlam slam(SmokeSettings(), options);
  RunSequence(slam, false);
  const RunStatus status = slam.Status();
  EXPECT_EQ(status.frames, static_cast<std::size_t>(kFrames));
  EXPECT_GT(status.keyframes, 2u);
  EXPECT_GT(status.map_points, 100u);
  EXPECT_GT(status.objects, 0u);
  EXPECT_GT(status.resident_bytes, 10'000'000u);
  EXPECT_GT(status.heap_bytes, 1'000'000u);
  EXPECT_LT(status.heap_bytes, status.resident_bytes);
  slam.Shutdown();
  const nlohmann::json report = slam.Save(testing::MakeTempDir("object_slam_status"), {});
  EXPECT_EQ(report["interrupted"], false);
  ASSERT_FALSE(report["progress"].empty());
  const nlohmann::json& last = report["progress"].back();
  EXPECT_EQ(last["frames"], kFrames);
  EXPECT_EQ(last["keyframes"], report["keyframes"]);
  EXPECT_EQ(last["map_points"], report["map_points"]);
  EXPECT_GT(last["resident_mb"].get<double>(), 10.0);
  EXPECT_GT(last["heap_mb"].get<double>(), 1.0);
}

// A stop requested between frames: the caller's loop sees it, and run.json says the run
// was interrupted (the rest of the outputs are those of a run of the frames given).
TEST(ObjectSlam, AStopRequestedBeforeShutdownMarksTheRunInterrupted) {
  RunStop stop;
  ObjectSlamOptions options;
  options.snapshots = ParseSnapshotPolicy("none");
  options.stop = &stop;
  ObjectSlam slam(SmokeSettings(), options);
  EXPECT_FALSE(slam.StopRequested());
  EXPECT_EQ(stop.Request(), 1);
  EXPECT_TRUE(slam.StopRequested());
  EXPECT_EQ(stop.Request(), 2);  // the caller's to read as "now"
  slam.Shutdown();
  EXPECT_EQ(slam.Save(testing::MakeTempDir("object_slam_stop"), {})["interrupted"], true);
}

// However long the run, the series stays short and spans it: first and last kept.
TEST(ProgressSeries, StaysShortAndSpansTheWholeRun) {
  app_detail::ProgressSeries series(10.0, 8);
  std::size_t added = 0;
  for (int second = 0; second <= 36000; ++second) {
    if (!series.Due(second)) continue;
    RunStatus status;
    status.seconds = second;
    status.frames = static_cast<std::size_t>(second) * 30;
    series.Add(status);
    ++added;
  }
  RunStatus end;
  end.seconds = 36000.5;
  series.Add(end);
  const nlohmann::json json = series.Json();
  EXPECT_GT(added, 20u);
  EXPECT_LE(json.size(), 8u);
  EXPECT_GE(json.size(), 4u);
  EXPECT_EQ(json.front()["seconds"], 0.0);
  EXPECT_EQ(json.back()["seconds"], 36000.5);
  for (std::size_t i = 1; i < json.size(); ++i)
    EXPECT_GT(json[i]["seconds"].get<double>(), json[i - 1]["seconds"].get<double>());
}

// A heap whose free memory lies in holes between live blocks (what a long run that frees
// in another order than it allocated leaves): free() gives none of it back, as only the
// heap's top can be trimmed; ReleaseFreeHeap() gives back the free pages in the holes.
TEST(ReleaseFreeHeap, GivesBackTheFreePagesBetweenLiveBlocks) {
  constexpr std::size_t kBlock = 16 * 1024, kBlocks = 2048, kKeepEvery = 32;  // 32 MB
  std::vector<char*> blocks;
  for (std::size_t i = 0; i < kBlocks; ++i) {
    blocks.push_back(static_cast<char*>(std::malloc(kBlock)));
    ASSERT_NE(blocks.back(), nullptr);
    std::memset(blocks.back(), static_cast<int>(i), kBlock);  // resident
  }
  for (std::size_t i = 0; i < kBlocks; ++i) {
    if (i % kKeepEvery != kKeepEvery - 1) {
      std::free(blocks[i]);
      blocks[i] = nullptr;
    }
  }
  const std::size_t holes = app_detail::ResidentMemoryBytes();
  app_detail::ReleaseFreeHeap();
  const std::size_t released = app_detail::ResidentMemoryBytes();
  const std::size_t freed = kBlock * (kBlocks - kBlocks / kKeepEvery);  // 31 MB
  EXPECT_GT(holes, released + freed / 2)
      << "resident " << holes / 1e6 << " MB with 31 MB free in holes, " << released / 1e6
      << " MB after ReleaseFreeHeap";
  long sum = 0;
  for (char* block : blocks) {
    if (block != nullptr) sum += block[0];
    std::free(block);
  }
  EXPECT_GT(sum, 0);
}

// Released at most once an interval of the run's wall time, the first at its start.
TEST(HeapRelease, ReleasesOnceAnInterval) {
  app_detail::HeapRelease release(10.0);
  EXPECT_TRUE(release.MaybeRelease(0.0));
  EXPECT_FALSE(release.MaybeRelease(5.0));
  EXPECT_TRUE(release.MaybeRelease(10.0));
  EXPECT_FALSE(release.MaybeRelease(19.9));
  EXPECT_TRUE(release.MaybeRelease(47.0));
  EXPECT_FALSE(release.MaybeRelease(49.0));
  EXPECT_TRUE(release.MaybeRelease(50.0));
}

}  // namespace
}  // namespace ocg
