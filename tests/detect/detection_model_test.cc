// DetectionModel loading and running: on tiny ONNX models with a known answer, built at
// test time with Debian's python3-onnx (the real model is not needed), and on the real
// default model and real frames when they are there.

#include "ocg/detect/detection_model.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <opencv2/dnn.hpp>
#include <opencv2/imgcodecs.hpp>
#include <random>

#include "ocg/core/file_io.h"
#include "ocg/detect/detect_images.h"
#include "ocg/detect/onnx_file.h"
#include "ocg/io/text_lines.h"
#include "test_support.h"

namespace ocg {
namespace {

namespace fs = std::filesystem;

// A tiny detector of the given kind, or "" when python3-onnx is missing.
std::string TinyModel(const std::string& kind) {
  const std::string dir = testing::MakeTempDir("tiny_detector_" + kind);
  const std::string path = dir + "/" + kind + ".onnx";
  const std::string command = "/usr/bin/python3 " + testing::SourceDir() +
                              "/tests/detect/make_tiny_detector.py " + kind + " " + path +
                              " 2>/dev/null";
  if (std::system(command.c_str()) != 0 || !fs::exists(path)) return "";
  return path;
}

#define REQUIRE_TINY_MODEL(path)                                   \
  if ((path).empty())                                              \
  GTEST_SKIP() << "needs Debian's python3-onnx to build the tiny " \
                  "test model (apt-get install python3-onnx)"

TEST(OnnxInputs, ReadsTheImageInputsShapeFromTheFile) {
  const std::string path = TinyModel("yolov8");
  REQUIRE_TINY_MODEL(path);
  const std::vector<OnnxInput> inputs = ReadOnnxInputs(path);
  ASSERT_EQ(inputs.size(), 1u);  // the initializers are not inputs
  EXPECT_EQ(inputs[0].name, "images");
  EXPECT_EQ(inputs[0].dims, (std::vector<std::int64_t>{1, 3, 128, 128}));
}

TEST(OnnxInputs, RefusesAFileThatIsNotOnnxNamingIt) {
  const std::string path = testing::MakeTempDir("not_onnx") + "/model.onnx";
  WriteFile(path, "\xff\xff\xff\xff\xff\xff\xff\xff\xff\xff\xff this is not protobuf");
  try {
    ReadOnnxInputs(path);
    FAIL() << "no exception";
  } catch (const ParseError& error) {
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
  }
  EXPECT_THROW(ReadOnnxInputs(path + ".missing"), FileError);
}

// Truncated and corrupted copies of a real ONNX file: each read either succeeds or throws
// ParseError, never reads past its bytes (the ASan build checks that) or hangs.
TEST(OnnxInputs, CorruptedFilesAreParseErrorsNotCrashes) {
  const std::string path = TinyModel("yolov8");
  REQUIRE_TINY_MODEL(path);
  const std::string bytes = ReadTextFile(path);
  const std::string copy = testing::MakeTempDir("corrupt_onnx") + "/model.onnx";
  std::mt19937 random(7);
  int refused = 0;
  for (int trial = 0; trial < 300; ++trial) {
    std::string mutated = bytes.substr(0, random() % (bytes.size() + 1));
    for (int flips = 0; flips < 4 && !mutated.empty(); ++flips) {
      mutated[random() % mutated.size()] = static_cast<char>(random() % 256);
    }
    WriteFile(copy, mutated);
    try {
      ReadOnnxInputs(copy);
    } catch (const ParseError&) {
      ++refused;
    }
  }
  EXPECT_GT(refused, 0);
}

TEST(DetectionModel, LoadsAYoloV8ExportAndMapsItsBoxBackThroughTheLetterbox) {
  DetectionModelOptions options;
  options.model_path = TinyModel("yolov8");
  REQUIRE_TINY_MODEL(options.model_path);
  DetectionModel model(options);
  EXPECT_EQ(model.outputs().layout, OutputLayout::kYoloV8);
  EXPECT_EQ(model.outputs().num_classes, 80);
  EXPECT_EQ(model.input_size(), cv::Size(128, 128));
  // A 256 x 256 image is halved into the 128 x 128 input: the box (48, 48, 32, 32) of
  // every anchor is (96, 96, 64, 64) in the image, and the 1024 copies are one after NMS.
  const std::vector<Detection> boxes = model.Detect(cv::Mat(256, 256, CV_8UC3, cv::Scalar(0)));
  ASSERT_EQ(boxes.size(), 1u);
  EXPECT_EQ(boxes[0].class_id, 5);
  EXPECT_NEAR(boxes[0].confidence, 0.9, 1e-6);
  EXPECT_NEAR(boxes[0].x, 96, 1e-3);
  EXPECT_NEAR(boxes[0].y, 96, 1e-3);
  EXPECT_NEAR(boxes[0].width, 64, 1e-3);
  EXPECT_NEAR(boxes[0].height, 64, 1e-3);
}

TEST(DetectionModel, LoadsAYoloV5ExportAndTilesAWideImage) {
  DetectionModelOptions options;
  options.model_path = TinyModel("yolov5");
  REQUIRE_TINY_MODEL(options.model_path);
  DetectionModel model(options);
  EXPECT_EQ(model.outputs().layout, OutputLayout::kYoloV5);
  const cv::Mat wide(128, 512, CV_8UC1, cv::Scalar(0));  // grey, as KITTI's image_0
  // Tiles of 128 at x 0, 96, 192, 288, 384: each finds its centre box (32 x 32, not cut
  // by an edge), and the whole frame, letterboxed, one 128 x 128 box in the middle.
  const std::vector<Detection> tiled = model.Detect(wide);
  ASSERT_EQ(tiled.size(), 6u);
  int small = 0;
  for (const Detection& box : tiled) small += box.width < 40 ? 1 : 0;
  EXPECT_EQ(small, 5);
  options.tile_mode = TileMode::kOff;
  DetectionModel untiled(options);
  const std::vector<Detection> once = untiled.Detect(wide);
  ASSERT_EQ(once.size(), 1u);
  EXPECT_NEAR(once[0].x, 192, 1e-3);
  EXPECT_NEAR(once[0].width, 128, 1e-3);
}

TEST(DetectionModel, ErrorsNameTheFile) {
  DetectionModelOptions options;
  options.model_path = testing::MakeTempDir("bad_model") + "/garbage.onnx";
  WriteFile(options.model_path, "not a model");
  try {
    DetectionModel model(options);
    FAIL() << "no exception";
  } catch (const std::exception& error) {
    EXPECT_NE(std::string(error.what()).find("garbage.onnx"), std::string::npos) << error.what();
  }
  options.model_path += ".missing";
  EXPECT_THROW(DetectionModel{options}, FileError);
  options.score_threshold = 1.5;
  EXPECT_THROW(DetectionModel{options}, std::invalid_argument);
}

// The SLAM loop asks one DetectionSource per frame: files read beforehand or the network.
TEST(DetectionSource, FilesAndTheNetworkAnswerTheSameQuestion) {
  const std::string dir = testing::MakeTempDir("detection_source");
  WriteFile(dir + "/1.5.txt", "41 10 20 30 40 0.9\n");
  const EaoDetectionFolder folder(dir, {"1.5", "2.5"});
  FolderDetectionSource files(folder);
  DetectionSource& from_files = files;
  const cv::Mat image(256, 256, CV_8UC3, cv::Scalar(0));
  ASSERT_EQ(from_files.DetectionsFor("1.5", image).size(), 1u);
  EXPECT_EQ(from_files.DetectionsFor("1.5", image)[0].class_id, 41);
  EXPECT_TRUE(from_files.DetectionsFor("2.5", image).empty());  // no file: nothing found

  DetectionModelOptions options;
  options.model_path = TinyModel("yolov8");
  REQUIRE_TINY_MODEL(options.model_path);
  DetectionModel model(options);
  DetectionSource& from_network = model;
  const std::vector<Detection> found = from_network.DetectionsFor("2.5", image);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].class_id, 5);
}

TEST(ListImagesToDetect, AFolderOfImagesGivesFileStemsInNameOrder) {
  const std::string dir = testing::MakeTempDir("image_folder");
  const cv::Mat image(8, 8, CV_8UC3, cv::Scalar(0));
  cv::imwrite(dir + "/000002.png", image);
  cv::imwrite(dir + "/000001.png", image);
  WriteFile(dir + "/notes.txt", "not an image");
  const std::vector<TimedImage> images = ListImagesToDetect(dir);
  ASSERT_EQ(images.size(), 2u);
  EXPECT_EQ(images[0].timestamp_text, "000001");
  EXPECT_EQ(images[1].path, dir + "/000002.png");
  EXPECT_THROW(ListImagesToDetect(dir + "/nothing"), FileError);
}

TEST(DetectImagesToFolder, OneEaoFilePerImageThatTheReaderAccepts) {
  DetectionModelOptions options;
  options.model_path = TinyModel("yolov8");
  REQUIRE_TINY_MODEL(options.model_path);
  DetectionModel model(options);
  const std::string dir = testing::MakeTempDir("detect_images");
  cv::imwrite(dir + "/1.5.png", cv::Mat(128, 128, CV_8UC3, cv::Scalar(10)));
  cv::imwrite(dir + "/2.5.png", cv::Mat(128, 128, CV_8UC3, cv::Scalar(20)));
  const std::string out = dir + "/detections";
  const DetectRunSummary summary = DetectImagesToFolder(model, ListImagesToDetect(dir), out, true);
  EXPECT_EQ(summary.images, 2u);
  EXPECT_EQ(summary.boxes, 2u);
  const EaoDetectionFolder folder(out, {"1.5", "2.5"});
  ASSERT_EQ(folder.ForFrame("2.5").size(), 1u);
  EXPECT_EQ(folder.ForFrame("2.5")[0].class_id, 5);
  EXPECT_EQ(ReadJsonDetections(out + "/detections.json").size(), 2u);
}

std::vector<float> ReadFloats(const std::string& path) {
  std::ifstream stream(path, std::ios::binary);
  std::vector<float> values;
  float value = 0;
  while (stream.read(reinterpret_cast<char*>(&value), sizeof value)) values.push_back(value);
  return values;
}

// tools/tfjs_to_onnx.py on a tiny TF.js graph with every op of the default detector
// (NHWC convolutions with float16 weights, bias, LeakyRelu, depthwise, pooling, bilinear
// resizing, concatenation, split, a reshape whose shape is computed from constants):
// OpenCV runs the ONNX it writes and gets what numpy computes from the TF graph's meaning.
TEST(TfjsToOnnx, OpenCvRunsTheConvertedGraphAsTheTfGraphComputes) {
  const std::string dir = testing::MakeTempDir("tfjs_to_onnx");
  const std::string python = "/usr/bin/python3 " + testing::SourceDir();
  if (std::system((python + "/tests/detect/make_tiny_tfjs.py " + dir + " 2>/dev/null").c_str()) !=
      0) {
    GTEST_SKIP() << "needs Debian's python3-numpy and python3-onnx";
  }
  ASSERT_EQ(std::system((python + "/tools/tfjs_to_onnx.py " + dir + "/model.json " + dir +
                         "/model.onnx > /dev/null")
                            .c_str()),
            0);
  cv::dnn::Net net = cv::dnn::readNetFromONNX(dir + "/model.onnx");
  std::vector<float> input = ReadFloats(dir + "/input.f32");
  ASSERT_EQ(input.size(), 3u * 8 * 8);
  const int input_shape[] = {1, 3, 8, 8};
  net.setInput(cv::Mat(4, input_shape, CV_32F, input.data()));
  std::vector<cv::Mat> outputs;
  net.forward(outputs, std::vector<std::string>{"Identity", "Identity_1"});
  ASSERT_EQ(outputs.size(), 2u);
  for (int k = 0; k < 2; ++k) {
    const std::vector<float> expected = ReadFloats(dir + "/out" + std::to_string(k) + ".f32");
    ASSERT_EQ(outputs[k].total(), expected.size()) << "output " << k;
    const float* got = outputs[k].ptr<float>(0);
    for (std::size_t i = 0; i < expected.size(); ++i) {
      ASSERT_NEAR(got[i], expected[i], 1e-4) << "output " << k << " value " << i;
    }
  }
  EXPECT_EQ(outputs[0].size[1], 16);  // [1, 16, 5]: the final transpose kept
  EXPECT_EQ(outputs[0].size[2], 5);
}

// The real default model (tools/get_detector.sh) on real frames; skipped without either.
class RealDetector : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string path = testing::SourceDir() + "/models/nanodet/nanodet.onnx";
    if (!fs::exists(path)) GTEST_SKIP() << "no " << path << ": run tools/get_detector.sh";
    const auto data = testing::SharedDataDir();
    if (!data) GTEST_SKIP() << testing::SharedDataSkipMessage();
    data_ = *data;
    DetectionModelOptions options;
    options.model_path = path;
    model_ = std::make_unique<DetectionModel>(options);
  }
  std::string data_;
  std::unique_ptr<DetectionModel> model_;
};

TEST_F(RealDetector, FindsTheDeskObjectsOfATumFrame) {
  EXPECT_EQ(model_->outputs().layout, OutputLayout::kNanoDet);
  EXPECT_EQ(model_->input_size(), cv::Size(416, 416));
  // The first listed frame of fr3 long_office, against the reference YOLO boxes of it.
  const std::vector<TimedImage> frames = ListImagesToDetect(data_ + "/tum_fr3_long_office/rgb.txt");
  ASSERT_FALSE(frames.empty());
  const std::vector<Detection> found = model_->Detect(cv::imread(frames[0].path));
  const std::vector<Detection> reference = ReadEaoDetectionsForImage(
      data_ + "/tum_fr3_long_office/detections", frames[0].timestamp_text);
  int matched = 0;
  for (const Detection& ref : reference) {
    for (const Detection& box : found) {
      if (box.class_id == ref.class_id && BoxIou(box, ref) >= 0.5) {
        ++matched;
        break;
      }
    }
  }
  EXPECT_GE(matched, 3) << found.size() << " found, " << reference.size() << " reference";
}

TEST_F(RealDetector, FindsCarsOnAKittiFrame) {
  const std::vector<Detection> found = model_->Detect(
      cv::imread(data_ + "/kitti_07_first160/image_0/000000.png", cv::IMREAD_UNCHANGED));
  int cars = 0;
  for (const Detection& box : found) cars += box.class_id == 2 ? 1 : 0;
  EXPECT_GE(cars, 1);
}

}  // namespace
}  // namespace ocg
