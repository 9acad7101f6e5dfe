// Detection sources of files and memory: which frame a JSON entry belongs to, the format
// told by the path, the frames named by detection files, and the errors at start.
#include "ocg/io/detection_source.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "ocg/core/file_io.h"
#include "ocg/io/text_lines.h"
#include "test_support.h"

namespace ocg {
namespace {

Detection Box(int class_id, double x) { return {class_id, x, 20.0, 30.0, 40.0, 0.5}; }

std::string ErrorOf(const std::function<void()>& body) {
  try {
    body();
  } catch (const std::exception& error) {
    return error.what();
  }
  return "";
}

TEST(JsonDetectionSource, AnEntryBelongsToTheFrameItsFileNameNames) {
  const std::string dir = testing::MakeTempDir("json_source");
  // Named as ocg_detect --json and ocg_convert_detections name them (a path with the
  // extension), and by the bare timestamp text (whose "extension" is its fraction).
  WriteFileAtomically(dir + "/d.json",
                      FormatJsonDetections({{"/data/rgb/1.500000.png", {Box(41, 10.0)}},
                                            {"2.500000", {Box(56, 11.0), Box(0, 12.0)}},
                                            {"rgb/9.000000.png", {Box(1, 13.0)}}}));
  JsonDetectionSource source(dir + "/d.json", {"1.500000", "2.500000", "3.500000"});
  EXPECT_EQ(source.FramesMatched(), 2u);
  ASSERT_EQ(source.DetectionsFor("1.500000", {}).size(), 1u);
  EXPECT_EQ(source.DetectionsFor("1.500000", {}).front().class_id, 41);
  EXPECT_EQ(source.DetectionsFor("2.500000", {}).size(), 2u);
  EXPECT_TRUE(source.DetectionsFor("3.500000", {}).empty());
  EXPECT_FALSE(source.NeedsImage());
}

TEST(JsonDetectionSource, NoMatchingEntryOrTwoEntriesForOneFrameAreErrors) {
  const std::string dir = testing::MakeTempDir("json_source_errors");
  WriteFileAtomically(dir + "/a.json", FormatJsonDetections({{"rgb/000001.png", {}}}));
  const std::string none = ErrorOf([&] { JsonDetectionSource(dir + "/a.json", {"1.500000"}); });
  EXPECT_NE(none.find("matches a frame"), std::string::npos) << none;
  EXPECT_NE(none.find("1.500000"), std::string::npos) << none;
  EXPECT_NE(none.find("rgb/000001.png"), std::string::npos) << none;
  WriteFileAtomically(dir + "/b.json",
                      FormatJsonDetections({{"a/1.5.png", {}}, {"b/1.5.jpg", {Box(1, 1.0)}}}));
  const std::string twice = ErrorOf([&] { JsonDetectionSource(dir + "/b.json", {"1.5"}); });
  EXPECT_NE(twice.find("name the same frame 1.5"), std::string::npos) << twice;
}

TEST(OpenDetectionFiles, TheFormatIsToldByTheFolderOrFile) {
  const std::string dir = testing::MakeTempDir("open_detections");
  std::filesystem::create_directories(dir + "/eao");
  WriteFileAtomically(dir + "/eao/1.5.txt", FormatEaoDetections({Box(41, 10.0)}));
  WriteFileAtomically(dir + "/list.json", FormatJsonDetections({{"rgb/1.5.png", {Box(41, 10.0)}}}));
  const auto folder = OpenDetectionFiles(dir + "/eao", {"1.5", "2.5"});
  const auto list = OpenDetectionFiles(dir + "/list.json", {"1.5", "2.5"});
  EXPECT_EQ(folder->Describe(), "EAO folder '" + dir + "/eao'");
  EXPECT_EQ(list->Describe(), "JSON list '" + dir + "/list.json'");
  for (const auto* source : {folder.get(), list.get()}) {
    EXPECT_EQ(source->FramesMatched(), 1u);
    const std::vector<Detection> boxes =
        const_cast<DetectionSource*>(source)->DetectionsFor("1.5", {});
    ASSERT_EQ(boxes.size(), 1u);
    EXPECT_EQ(boxes[0].x, 10.0);
    EXPECT_EQ(boxes[0].width, 30.0);
  }
  const std::string missing = ErrorOf([&] { OpenDetectionFiles(dir + "/none", {"1.5"}); });
  EXPECT_NE(missing.find("neither a folder"), std::string::npos) << missing;
}

TEST(FramesNamedByDetections, EaoFilesAndJsonEntriesNameFramesInTimeOrder) {
  const std::string dir = testing::MakeTempDir("frames_named");
  std::filesystem::create_directories(dir + "/eao");
  for (const char* name : {"10.25", "2.5", "3"})
    WriteFileAtomically(dir + "/eao/" + name + ".txt", "");
  const std::vector<TimedImage> from_folder = FramesNamedByDetections(dir + "/eao");
  ASSERT_EQ(from_folder.size(), 3u);
  EXPECT_EQ(from_folder[0].timestamp_text, "2.5");
  EXPECT_EQ(from_folder[2].timestamp_text, "10.25");
  EXPECT_EQ(from_folder[2].timestamp, 10.25);
  WriteFileAtomically(dir + "/list.json",
                      FormatJsonDetections({{"rgb/7.5.png", {}}, {"1.25", {}}}));
  const std::vector<TimedImage> from_list = FramesNamedByDetections(dir + "/list.json");
  ASSERT_EQ(from_list.size(), 2u);
  EXPECT_EQ(from_list[0].timestamp_text, "1.25");
  EXPECT_EQ(from_list[1].timestamp_text, "7.5");
  WriteFileAtomically(dir + "/eao/frame_a.txt", "");
  const std::string bad = ErrorOf([&] { FramesNamedByDetections(dir + "/eao"); });
  EXPECT_NE(bad.find("frame_a.txt' is not named <timestamp>.txt"), std::string::npos) << bad;
}

TEST(InMemoryDetectionSource, BoxesAreCheckedAsFilesAre) {
  InMemoryDetectionSource source({{"1.5", {Box(41, 10.0)}}}, {"1.5", "2.5"});
  EXPECT_EQ(source.FramesMatched(), 1u);
  EXPECT_EQ(source.DetectionsFor("1.5", {}).size(), 1u);
  EXPECT_TRUE(source.DetectionsFor("2.5", {}).empty());
  Detection bad = Box(80, 1.0);
  EXPECT_THROW(InMemoryDetectionSource({{"1.5", {bad}}}), ParseError);
}

}  // namespace
}  // namespace ocg

namespace ocg {
namespace {

// A detector's boxes inside a run are those its files would hold once read back.
TEST(AsStoredInEaoFiles, GivesWhatAFileWrittenAndReadBackHolds) {
  const std::vector<Detection> raw = {
      {41, 123.45678912, 0.1 + 0.2, 50.000000001, 1e-3 / 3.0, 0.87654321},
      {0, 1234567.891, 7.0, 1.0 / 3.0, 2.0 / 3.0, 1.0}};
  const std::string dir = testing::MakeTempDir("as_stored");
  WriteFileAtomically(dir + "/1.5.txt", FormatEaoDetections(raw));
  const std::vector<Detection> read = ReadEaoDetectionFile(dir + "/1.5.txt");
  const std::vector<Detection> stored = AsStoredInEaoFiles(raw);
  ASSERT_EQ(stored.size(), read.size());
  for (std::size_t i = 0; i < read.size(); ++i) {
    EXPECT_EQ(stored[i].class_id, read[i].class_id);
    EXPECT_EQ(stored[i].x, read[i].x);
    EXPECT_EQ(stored[i].y, read[i].y);
    EXPECT_EQ(stored[i].width, read[i].width);
    EXPECT_EQ(stored[i].height, read[i].height);
    EXPECT_EQ(stored[i].confidence, read[i].confidence);
  }
  EXPECT_NE(stored[0].x, raw[0].x);  // the text keeps 6 significant digits
  EXPECT_TRUE(AsStoredInEaoFiles({}).empty());
}

}  // namespace
}  // namespace ocg
