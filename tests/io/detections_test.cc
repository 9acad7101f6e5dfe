#include <gtest/gtest.h>

#include <filesystem>
#include <functional>

#include "ocg/core/file_io.h"
#include "ocg/io/detections.h"
#include "ocg/io/sequence.h"
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

std::string MessageOf(const std::function<void()>& action) {
  try {
    action();
  } catch (const std::exception& error) {
    return error.what();
  }
  return "(no exception)";
}

TEST(EaoDetectionFolder, FilesNamedByFrameIndexMatchNoFrame) {
  const std::string dir = testing::MakeTempDir("det_index_names");
  WriteFileAtomically(dir + "/000000.txt", "56 10 20 30 40 0.9\n");
  WriteFileAtomically(dir + "/000001.txt", "56 10 20 30 40 0.9\n");
  const std::string message = MessageOf([&] {
    EaoDetectionFolder(dir, {"1341847980.722988", "1341847981.726650"});
  });
  EXPECT_NE(message.find("no detection file in '" + dir + "' matches a frame"), std::string::npos)
      << message;
  EXPECT_NE(message.find("e.g. '1341847980.722988.txt'"), std::string::npos) << message;
  EXPECT_NE(message.find("found 2 .txt file(s) such as '000000.txt'"), std::string::npos)
      << message;
  const std::string empty = testing::MakeTempDir("det_no_files");
  EXPECT_NE(MessageOf([&] { EaoDetectionFolder(empty, {"1.5"}); }).find("holds no .txt file"),
            std::string::npos);
  EXPECT_THROW(ReadEaoDetectionDir(empty), FileError);
}

TEST(EaoDetectionFolder, ReadsTheFramesDetectionsAndAMissingFileIsNone) {
  const std::string dir = testing::MakeTempDir("det_folder");
  WriteFileAtomically(dir + "/1.5.txt", "56 10 20 30 40 0.9\n41 1 2 3 4 0.5\n");
  WriteFileAtomically(dir + "/9.0.txt", "this file belongs to no frame and is not read\n");
  const EaoDetectionFolder folder(dir, {"1.5", "2.5"});
  EXPECT_EQ(folder.FilesMatched(), 1u);
  EXPECT_EQ(folder.DetectionCount(), 2u);
  ASSERT_EQ(folder.ForFrame("1.5").size(), 2u);
  EXPECT_EQ(folder.ForFrame("1.5")[1].class_id, 41);
  EXPECT_TRUE(folder.ForFrame("2.5").empty());
  EXPECT_FALSE(folder.LooksNormalized());
}

TEST(EaoDetectionFolder, NormalizedBoxesAreFlagged) {
  const std::string dir = testing::MakeTempDir("det_normalized");
  // YOLO's own output: class cx cy w h conf, all in 0..1.
  WriteFileAtomically(dir + "/1.5.txt", "56 0.5 0.4 0.2 0.3 0.9\n41 0.1 0.9 0.05 0.05 0.5\n");
  WriteFileAtomically(dir + "/2.5.txt", "62 1 0 1 1 0.7\n");
  EXPECT_TRUE(EaoDetectionFolder(dir, {"1.5", "2.5"}).LooksNormalized());
  EXPECT_TRUE(BoxesLookNormalized(ReadEaoDetectionDir(dir)));
  WriteFileAtomically(dir + "/2.5.txt", "62 100 50 20 30 0.7\n");  // one box in pixels
  EXPECT_FALSE(EaoDetectionFolder(dir, {"1.5", "2.5"}).LooksNormalized());
  EXPECT_FALSE(BoxesLookNormalized({{"a", {}}}));  // no box: nothing to judge
}

TEST(EaoDetectionFolder, APathThatIsNotAReadableFileIsAnError) {
  const std::string dir = testing::MakeTempDir("det_not_file");
  WriteFileAtomically(dir + "/1.5.txt", "56 10 20 30 40 0.9\n");
  fs::create_directory(dir + "/2.5.txt");
  std::string message = MessageOf([&] { EaoDetectionFolder(dir, {"1.5", "2.5"}); });
  EXPECT_NE(message.find("'" + dir + "/2.5.txt' is a directory, not a readable file"),
            std::string::npos)
      << message;
  EXPECT_THROW(ReadEaoDetectionsForImage(dir, "2.5"), FileError);
  EXPECT_THROW(ReadEaoDetectionDir(dir), FileError);
  fs::remove(dir + "/2.5.txt");
  fs::create_symlink(dir + "/gone.txt", dir + "/2.5.txt");
  message = MessageOf([&] { EaoDetectionFolder(dir, {"1.5", "2.5"}); });
  EXPECT_NE(message.find("'" + dir + "/2.5.txt' is a broken symbolic link"), std::string::npos)
      << message;
}

TEST(EaoDetectionFolder, AMalformedLineInTheLastFrameFailsAtOnceAndNamesLenient) {
  const std::string dir = testing::MakeTempDir("det_late_bad_line");
  std::vector<std::string> frames;
  for (int i = 0; i < 50; ++i) {
    frames.push_back(std::to_string(100 + i) + ".25");
    WriteFileAtomically(dir + "/" + frames.back() + ".txt",
                        i == 49 ? "56 10 20 30 40 0.9\n56 10 20 30 0.9\n" : "56 10 20 30 40 0.9\n");
  }
  const std::string message = MessageOf([&] { EaoDetectionFolder(dir, frames); });
  EXPECT_NE(message.find(dir + "/149.25.txt:2: expected 6 fields"), std::string::npos) << message;
  EXPECT_NE(message.find("--lenient"), std::string::npos) << message;
  DetectionReadOptions lenient;
  lenient.lenient = true;
  EXPECT_EQ(EaoDetectionFolder(dir, frames, lenient).DetectionCount(), 50u);
}

TEST(EaoDetections, AbsurdlyLargeFilesAreRefusedNamingFileAndLimit) {
  const std::string dir = testing::MakeTempDir("det_large");
  std::string text;
  while (text.size() <= 2000) text += "56 10 20 30 40 0.9\n";
  WriteFileAtomically(dir + "/1.5.txt", text);
  DetectionReadOptions small;
  small.max_file_bytes = 2000;
  std::string message = MessageOf([&] { ReadEaoDetectionFile(dir + "/1.5.txt", small); });
  EXPECT_NE(message.find("'" + dir + "/1.5.txt' is"), std::string::npos) << message;
  EXPECT_NE(message.find("more than the limit of 2000 bytes for one image's detections"),
            std::string::npos)
      << message;
  EXPECT_THROW(EaoDetectionFolder(dir, {"1.5"}, small), FileError);
  small.max_file_bytes = text.size();  // at the limit: read, every line
  EXPECT_EQ(ReadEaoDetectionFile(dir + "/1.5.txt", small).size(), text.size() / 19);
  // The default: 16 MiB for one image's detections.
  EXPECT_EQ(DetectionReadOptions{}.max_file_bytes, 16u << 20);

  WriteFileAtomically(dir + "/d.json", FormatJsonDetections({{"a.png", {{56, 1, 2, 3, 4, 0.5}}}}));
  DetectionReadOptions small_json;
  small_json.max_json_bytes = 20;
  message = MessageOf([&] { ReadJsonDetections(dir + "/d.json", small_json); });
  EXPECT_NE(message.find("'" + dir + "/d.json' is"), std::string::npos) << message;
  EXPECT_NE(message.find("limit of 20 bytes for a JSON detection list"), std::string::npos)
      << message;
  EXPECT_EQ(ReadJsonDetections(dir + "/d.json").size(), 1u);
  EXPECT_THROW(ReadJsonDetections(dir), FileError);  // a folder
}

TEST(EaoDetectionFolder, TheWholeRealFolderIsReadForItsFrameList) {
  const auto data = testing::SharedDataDir();
  if (!data) GTEST_SKIP() << testing::SharedDataSkipMessage();
  const std::string sequence = *data + "/tum_fr3_long_office";
  std::vector<std::string> frames;
  for (const TimedImage& image : ReadTumImageList(sequence + "/rgb_all_frames.txt", sequence))
    frames.push_back(image.timestamp_text);
  ASSERT_EQ(frames.size(), 2585u);
  const EaoDetectionFolder folder(sequence + "/detections", frames);
  EXPECT_EQ(folder.FilesMatched(), 2585u);
  EXPECT_EQ(folder.DetectionCount(), 17225u);
  EXPECT_FALSE(folder.LooksNormalized());
  EXPECT_EQ(folder.ForFrame("1341847980.722988")[0].class_id, 73);
}

}  // namespace
}  // namespace ocg
