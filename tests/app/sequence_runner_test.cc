// The sequence runner (FeedSequence) on a generated sequence: the outputs do not depend on
// the read-ahead nor on where the same boxes come from (EAO folder, JSON list, memory, a
// source that looks at the image as a detector does, on the reader thread).
#include "ocg/app/sequence_runner.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <mutex>
#include <set>
#include <thread>

#include "ocg/app/settings.h"
#include "ocg/core/file_io.h"
#include "ocg/io/detections.h"
#include "ocg/sim/generator.h"
#include "ocg/sim/presets.h"
#include "test_support.h"

namespace ocg {
namespace {

constexpr int kFrames = 30;

// A short smoke sequence; its boxes put on a 1/8-pixel grid, so that the EAO text
// ("%.6g") and the JSON corners ([x1, y1, x2, y2]) both hold them exactly.
struct Sequence {
  std::string root;
  std::vector<std::string> frames;
  std::unordered_map<std::string, std::vector<Detection>> boxes;
  std::string eao, json;
};

double OnGrid(double value) { return std::round(value * 8.0) / 8.0; }

const Sequence& Smoke() {
  static const Sequence sequence = [] {
    Sequence made;
    made.root = testing::MakeTempDir("sequence_runner_smoke") + "/smoke";
    sim::GeneratorOptions options;
    options.max_frames = kFrames;
    options.keyframe_interval = 0;
    sim::Generate(sim::MakePreset("smoke", 1), made.root, options);
    made.eao = made.root + "/grid_detections";
    made.json = made.root + "/grid_detections.json";
    std::filesystem::create_directories(made.eao);
    std::vector<DetectionFrame> listed;
    for (const TimedImage& image : ReadTumSequence(made.root).images) {
      made.frames.push_back(image.timestamp_text);
      std::vector<Detection> boxes =
          ReadEaoDetectionsForImage(made.root + "/detections", image.timestamp_text);
      for (Detection& box : boxes) {
        box.x = OnGrid(box.x);
        box.y = OnGrid(box.y);
        box.width = std::max(0.125, OnGrid(box.width));
        box.height = std::max(0.125, OnGrid(box.height));
        box.confidence = OnGrid(box.confidence);
      }
      WriteFileAtomically(made.eao + "/" + image.timestamp_text + ".txt",
                          FormatEaoDetections(boxes));
      listed.push_back({"rgb/" + image.timestamp_text + ".png", boxes});
      made.boxes[image.timestamp_text] = std::move(boxes);
    }
    WriteFileAtomically(made.json, FormatJsonDetections(listed));
    return made;
  }();
  return sequence;
}

const char* const kOutputs[] = {"KeyFrameTrajectory.txt", "CameraTrajectory.txt", "map_points.ply",
                                "objects.json",           "changes.json",         "ocg.json",
                                "ocg_observations.jsonl"};

// One sequential run through the runner; returns its folder.
std::string RunThrough(const std::string& name, DetectionSource& source, int read_ahead,
                       FeedReport* report = nullptr) {
  const std::string folder = testing::MakeTempDir("sequence_runner_" + name);
  ObjectSlamOptions options;
  options.snapshots = ParseSnapshotPolicy("none");
  ObjectSlam slam(LoadSettings(Smoke().root + "/camera.yaml", CameraNeed::kIntrinsics).settings,
                  options);
  FeedOptions feed;
  feed.read_ahead = read_ahead;
  const FeedReport fed = FeedSequence(slam, ReadTumSequence(Smoke().root), &source, feed);
  EXPECT_EQ(fed.frames, static_cast<std::size_t>(kFrames));
  EXPECT_FALSE(fed.stopped);
  EXPECT_EQ(fed.reader["read_ahead"], read_ahead);
  slam.Shutdown();
  const nlohmann::json saved = slam.Save(folder, {Smoke().root, "camera.yaml", name, 0});
  EXPECT_GT(saved["objects"]["objects_created"].get<int>(), 0) << name << " mapped no object";
  if (report != nullptr) *report = fed;
  return folder;
}

void ExpectSameOutputs(const std::string& a, const std::string& b, const std::string& what) {
  for (const char* file : kOutputs) {
    EXPECT_EQ(ReadTextFile(a + "/" + file), ReadTextFile(b + "/" + file))
        << file << " differs: " << what;
  }
}

// A source that looks at the image, as the detector network does: asked on the reader
// thread, given the frame as read from disk, its boxes reach the object map as files do.
class ImageLookingSource : public DetectionSource {
 public:
  explicit ImageLookingSource(const Sequence& sequence) : sequence_(sequence) {}
  std::vector<Detection> DetectionsFor(const std::string& timestamp_text,
                                       const cv::Mat& image) override {
    const std::lock_guard<std::mutex> lock(mutex_);
    threads_.insert(std::this_thread::get_id());
    if (image.cols != 640 || image.rows != 480) ++bad_images_;
    return sequence_.boxes.at(timestamp_text);
  }
  bool NeedsImage() const override { return true; }
  std::string Describe() const override { return "image-looking source"; }
  std::set<std::thread::id> threads_;
  int bad_images_ = 0;

 private:
  const Sequence& sequence_;
  std::mutex mutex_;
};

// Each test generates the sequence (most of its time), so each compares three runs.
TEST(SequenceRunner, ReadAheadOnOrOffAndASourceOnTheReaderThreadGiveTheSameRun) {
  FolderDetectionSource files(EaoDetectionFolder(Smoke().eao, Smoke().frames), Smoke().eao);
  FeedReport ahead;
  const std::string without = RunThrough("no_read_ahead", files, 0);
  ExpectSameOutputs(without, RunThrough("read_ahead", files, 3, &ahead), "read-ahead 0 and 3");
  EXPECT_EQ(ahead.reader["frame_wait_per_frame"]["count"], kFrames);
  ImageLookingSource detector(Smoke());
  FeedReport report;
  ExpectSameOutputs(without, RunThrough("image_source", detector, 2, &report),
                    "files and a source asked on the reader thread");
  EXPECT_EQ(detector.bad_images_, 0);
  ASSERT_EQ(detector.threads_.size(), 1u);
  EXPECT_NE(*detector.threads_.begin(), std::this_thread::get_id());
  EXPECT_EQ(report.reader["detect_per_frame"]["count"], kFrames);
  EXPECT_EQ(report.reader["detections"], "image-looking source");
}

TEST(SequenceRunner, EaoFilesAJsonListAndBoxesInMemoryGiveTheSameRun) {
  const std::unique_ptr<DetectionSource> eao = OpenDetectionFiles(Smoke().eao, Smoke().frames);
  const std::unique_ptr<DetectionSource> json = OpenDetectionFiles(Smoke().json, Smoke().frames);
  EXPECT_EQ(eao->Describe(), "EAO folder '" + Smoke().eao + "'");
  EXPECT_EQ(json->Describe(), "JSON list '" + Smoke().json + "'");
  EXPECT_EQ(json->FramesMatched(), Smoke().frames.size());
  InMemoryDetectionSource memory(Smoke().boxes, Smoke().frames);
  const std::string from_eao = RunThrough("eao", *eao, 2);
  ExpectSameOutputs(from_eao, RunThrough("json", *json, 2), "EAO folder and JSON list");
  ExpectSameOutputs(from_eao, RunThrough("memory", memory, 2), "EAO folder and boxes in memory");
}

TEST(SequenceRunner, ModesAreParsedOnceEachAndEurocTimesBecomeSeconds) {
  EXPECT_EQ(ParseModes("paper,visibility"), (std::vector<std::string>{"paper", "visibility"}));
  EXPECT_TRUE(ParseModes("").empty());
  EXPECT_THROW(ParseModes("paper,,visibility"), std::invalid_argument);
  EXPECT_THROW(ParseModes("paper,paper"), std::invalid_argument);
  EXPECT_EQ(TimestampInSeconds("1403715273262142976", "euroc"), "1403715273.262142976");
  EXPECT_EQ(TimestampInSeconds("1403715273262142976", "tum"), "1403715273262142976");
}

TEST(SequenceRunner, DetectionsFromFilesAndTheDetectorAreExclusive) {
  const std::string dir = testing::MakeTempDir("sequence_runner_inputs");
  WriteFileAtomically(dir + "/1.5.txt", "41 10 20 30 40 0.5\n");
  DetectionInput both;
  both.files = dir;
  both.detect = true;
  EXPECT_THROW(OpenDetections(both, {"1.5"}), std::invalid_argument);
  EXPECT_EQ(OpenDetections(DetectionInput{}, {"1.5"}), nullptr);
  both.detect = false;
  EXPECT_EQ(OpenDetections(both, {"1.5"})->FramesMatched(), 1u);
  DetectionInput missing_model;
  missing_model.detect = true;
  missing_model.model = dir + "/none.onnx";
  try {
    OpenDetections(missing_model, {"1.5"});
    FAIL() << "no error for a missing model";
  } catch (const FileError& error) {
    EXPECT_NE(std::string(error.what()).find("no detector model at"), std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace ocg
