#include <gtest/gtest.h>

#include <filesystem>

#include "ocg/core/file_io.h"
#include "ocg/io/detections.h"
#include "ocg/io/text_lines.h"
#include "test_support.h"

namespace ocg {
namespace {

namespace fs = std::filesystem;

TEST(EaoDetections, AllRealFilesOfTheTumSequenceParse) {
  const auto data = testing::SharedDataDir();
  if (!data) GTEST_SKIP() << testing::SharedDataSkipMessage();
  const auto frames = ReadEaoDetectionDir(*data + "/tum_fr3_long_office/detections");
  ASSERT_EQ(frames.size(), 2585u);
  std::size_t count = 0;
  for (const auto& frame : frames) count += frame.detections.size();
  EXPECT_EQ(count, 17225u);  // 22 files end without a newline: their last line counts too
  const Detection& first = frames[0].detections[0];  // "73 173 138 46 70 0.578918"
  EXPECT_EQ(frames[0].file_name, "1341847980.722988");
  EXPECT_EQ(first.class_id, 73);
  EXPECT_DOUBLE_EQ(first.x, 173);
  EXPECT_DOUBLE_EQ(first.height, 70);
  EXPECT_DOUBLE_EQ(first.confidence, 0.578918);
  const auto by_image =
      ReadEaoDetectionsForImage(*data + "/tum_fr3_long_office/detections", "1341847980.722988");
  EXPECT_EQ(by_image.size(), frames[0].detections.size());
}

TEST(EaoDetections, MissingFileMeansNoDetections) {
  EXPECT_TRUE(ReadEaoDetectionsForImage(testing::MakeTempDir("det_empty"), "123.456").empty());
  EXPECT_THROW(ReadEaoDetectionFile("/nonexistent/1.txt"), FileError);
}

TEST(EaoDetections, MalformedLinesNameFileAndLine) {
  const std::string dir = testing::MakeTempDir("det_bad");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"56 1 2 3 4 0.9\n56 1 2 3 0.9\n", ":2: expected 6 fields"},
      {"cup 1 2 3 4 0.9\n", ":1: class_id must be an integer"},
      {"56 1 2 3 4 high\n", ":1: confidence must be a number"},
      {"56 1 2 -3 4 0.5\n", ":1: box width and height must be positive"},
      {"80 1 2 3 4 0.5\n", ":1: class_id must be a COCO-80 index"},
      {"56 1 2 3 4 1.5\n", ":1: confidence must be in [0, 1]"}};
  for (const auto& [text, expected] : cases) {
    const std::string path = dir + "/1.txt";
    WriteFileAtomically(path, text);
    try {
      ReadEaoDetectionFile(path);
      FAIL() << "accepted: " << text;
    } catch (const ParseError& error) {
      EXPECT_NE(std::string(error.what()).find(path + expected), std::string::npos) << error.what();
    }
  }
  WriteFileAtomically(dir + "/2.txt", "56 1 2 3 4 0.9\nbroken\n41 5 6 7 8 0.25");
  DetectionReadOptions lenient;
  lenient.lenient = true;
  const auto kept = ReadEaoDetectionFile(dir + "/2.txt", lenient);
  ASSERT_EQ(kept.size(), 2u);
  EXPECT_EQ(kept[1].class_id, 41);
  EXPECT_DOUBLE_EQ(kept[1].confidence, 0.25);
}

TEST(Detections, EaoAndJsonRoundTrip) {
  std::vector<DetectionFrame> frames = {{"rgb/1.0.png", {{56, 10, 20, 30.5, 40, 0.875}}},
                                        {"rgb/2.0.png", {}}};
  const std::string dir = testing::MakeTempDir("det_json");
  WriteFileAtomically(dir + "/d.json", FormatJsonDetections(frames));
  const auto read = ReadJsonDetections(dir + "/d.json");
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[0].file_name, "rgb/1.0.png");
  ASSERT_EQ(read[0].detections.size(), 1u);
  EXPECT_DOUBLE_EQ(read[0].detections[0].width, 30.5);  // from bbox x2 - x1
  EXPECT_DOUBLE_EQ(read[0].detections[0].confidence, 0.875);
  WriteFileAtomically(dir + "/1.0.txt", FormatEaoDetections(read[0].detections));
  const auto text = ReadEaoDetectionFile(dir + "/1.0.txt");
  ASSERT_EQ(text.size(), 1u);
  EXPECT_DOUBLE_EQ(text[0].width, 30.5);
  EXPECT_EQ(text[0].class_id, 56);
}

TEST(Detections, MalformedJsonNamesFileAndEntry) {
  const std::string dir = testing::MakeTempDir("det_json_bad");
  WriteFileAtomically(dir + "/a.json",
                      R"([{"file_name": "a.png", "detections": []}, {"file_name": "b.png",
                          "detections": [{"category_id": 1, "detection_score": 0.5, "bbox": [1, 2, 3]}]}])");
  try {
    ReadJsonDetections(dir + "/a.json");
    FAIL();
  } catch (const ParseError& error) {
    EXPECT_NE(std::string(error.what()).find("image #1"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("bbox"), std::string::npos) << error.what();
  }
  WriteFileAtomically(dir + "/b.json", "{not json");
  EXPECT_THROW(ReadJsonDetections(dir + "/b.json"), ParseError);
}

}  // namespace
}  // namespace ocg
