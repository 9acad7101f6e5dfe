#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

#include "ocg/core/file_io.h"
#include "ocg/io/sequence.h"
#include "ocg/io/text_lines.h"
#include "test_support.h"

namespace ocg {
namespace {

namespace fs = std::filesystem;

// Line readers stream their file: a named pipe with no writer would block them forever
// (a run hung on an rgb.txt FIFO), so it is named before it is opened.
TEST(TumSequence, AFrameListThatIsANamedPipeIsNamedNotWaitedOn) {
  const std::string dir = testing::MakeTempDir("fifo_sequence");
  ASSERT_EQ(::mkfifo((dir + "/rgb.txt").c_str(), 0600), 0);
  try {
    ReadTumSequence(dir);
    FAIL() << "no FileError";
  } catch (const FileError& error) {
    EXPECT_EQ(std::string(error.what()),
              "cannot read '" + dir + "/rgb.txt': it is a named pipe (FIFO), not a file");
  }
  EXPECT_THROW(ForEachDataLine(dir + "/rgb.txt", false, [](int, const auto&) {}), FileError);
}

TEST(TumSequence, ReadsRealFramesAndGroundTruth) {
  const auto data = testing::SharedDataDir();
  if (!data) GTEST_SKIP() << testing::SharedDataSkipMessage();
  const ImageSequence sequence = ReadTumSequence(*data + "/tum_fr3_long_office");
  ASSERT_EQ(sequence.images.size(), 20u);
  EXPECT_EQ(sequence.images[0].timestamp_text, "1341847980.722988");
  EXPECT_DOUBLE_EQ(sequence.images[0].timestamp, 1341847980.722988);
  for (const TimedImage& image : sequence.images) EXPECT_TRUE(fs::exists(image.path)) << image.path;
  EXPECT_EQ(sequence.groundtruth.size(), 8710u);
  EXPECT_NEAR(sequence.groundtruth[0].T_wc.translation().x(), -0.6832, 1e-12);
  const auto all = ReadTumImageList(*data + "/tum_fr3_long_office/rgb_all_frames.txt", "/base");
  EXPECT_EQ(all.size(), 2585u);
  EXPECT_EQ(all[0].path.rfind("/base/rgb/", 0), 0u);
}

TEST(EurocSequence, ReadsRealCalibrationFramesAndExtrinsics) {
  const auto data = testing::SharedDataDir();
  if (!data) GTEST_SKIP() << testing::SharedDataSkipMessage();
  const ImageSequence sequence = ReadEurocSequence(*data + "/euroc_v101_micro");
  ASSERT_EQ(sequence.images.size(), 95u);
  EXPECT_EQ(sequence.images[0].timestamp_text, "1403715273262142976");
  EXPECT_NEAR(sequence.images[0].timestamp, 1403715273.262142976, 1e-6);
  EXPECT_TRUE(fs::exists(sequence.images[0].path));
  ASSERT_TRUE(sequence.camera.has_value());
  EXPECT_DOUBLE_EQ(sequence.camera->fx, 458.654);
  EXPECT_DOUBLE_EQ(sequence.camera->k1, -0.28340811);
  EXPECT_DOUBLE_EQ(sequence.camera->p2, 1.76187114e-05);
  EXPECT_EQ(sequence.camera->width, 752);
  ASSERT_TRUE(sequence.T_body_camera.has_value());
  EXPECT_NEAR(sequence.T_body_camera->translation().x(), -0.0216401454975, 1e-12);
  // The body ground truth turned into camera poses moves the position by T_BS's offset.
  const auto body = ReadTumTrajectory(*data + "/euroc_v101_micro/groundtruth_body_tum.txt");
  const auto camera = BodyToCameraPoses(body, *sequence.T_body_camera);
  ASSERT_EQ(camera.size(), body.size());
  EXPECT_NEAR((camera[0].T_wc.translation() - body[0].T_wc.translation()).norm(),
              sequence.T_body_camera->translation().norm(), 1e-9);
}

TEST(EurocSequence, GroundTruthCsvBecomesCameraPoses) {
  const std::string root = testing::MakeTempDir("euroc");
  WriteFileAtomically(root + "/mav0/cam0/data.csv", "#timestamp [ns],filename\n1000000000,1.png\n");
  WriteFileAtomically(root + "/mav0/cam0/sensor.yaml",
                      "%YAML:1.0\nT_BS:\n  cols: 4\n  rows: 4\n  data: [1, 0, 0, 0.5, 0, 1, 0, 0, "
                      "0, 0, 1, 0, 0, 0, 0, 1]\nresolution: [752, 480]\nintrinsics: [400, 400, "
                      "376, 240]\ndistortion_model: radial-tangential\n"
                      "distortion_coefficients: [0, 0, 0, 0]\n");
  WriteFileAtomically(root + "/mav0/state_groundtruth_estimate0/data.csv",
                      "#timestamp,p_x,p_y,p_z,q_w,q_x,q_y,q_z,v\n1000000000,1,2,3,1,0,0,0,0\n");
  const ImageSequence sequence = ReadEurocSequence(root);
  ASSERT_EQ(sequence.groundtruth.size(), 1u);
  EXPECT_EQ(sequence.groundtruth[0].timestamp_text, "1.000000000");
  EXPECT_NEAR(sequence.groundtruth[0].T_wc.translation().x(), 1.5, 1e-12);
}

TEST(Sequence, MissingFolderOrBadListNamesTheFile) {
  try {
    ReadTumSequence("/nonexistent/seq");
    FAIL();
  } catch (const FileError& error) {
    EXPECT_NE(std::string(error.what()).find("/nonexistent/seq/rgb.txt"), std::string::npos);
  }
  EXPECT_THROW(ReadEurocSequence("/nonexistent/seq"), FileError);
  const std::string root = testing::MakeTempDir("tum_bad");
  WriteFileAtomically(root + "/rgb.txt", "# x\n1.0 rgb/1.png\n2.0\n");
  try {
    ReadTumSequence(root);
    FAIL();
  } catch (const ParseError& error) {
    EXPECT_NE(std::string(error.what()).find("rgb.txt:3"), std::string::npos) << error.what();
  }
}

// A KITTI odometry folder as the dataset ships it: image_0/, times.txt, calib.txt.
TEST(KittiSequence, ReadsImagesTimesAndTheCameraOfP0) {
  const std::string root = testing::MakeTempDir("kitti_sequence");
  fs::create_directories(root + "/image_0");
  for (const char* name : {"000000.png", "000001.png", "000002.png"})
    cv::imwrite(root + "/image_0/" + name, cv::Mat(37, 122, CV_8UC1, cv::Scalar(90)));
  WriteFileAtomically(root + "/times.txt", "0.000000e+00\n1.038752e-01\n2.078941e-01\n");
  WriteFileAtomically(root + "/calib.txt",
                      "P0: 7.070912e+02 0 6.018873e+02 0 0 7.070912e+02 1.831104e+02 0 0 0 1 0\n"
                      "P1: 7.070912e+02 0 6.018873e+02 -3.798145e+02 0 7.070912e+02 "
                      "1.831104e+02 0 0 0 1 0\n");
  for (const char* format : {"kitti", "auto"}) {
    const ImageSequence sequence = ReadSequence(root, format);
    ASSERT_EQ(sequence.images.size(), 3u);
    EXPECT_EQ(sequence.images[1].timestamp_text, "0.103875");
    EXPECT_DOUBLE_EQ(sequence.images[1].timestamp, 0.1038752);
    EXPECT_EQ(sequence.images[2].path, root + "/image_0/000002.png");
    ASSERT_TRUE(sequence.camera.has_value());
    EXPECT_EQ(sequence.camera->fx, 707.0912);
    EXPECT_EQ(sequence.camera->cy, 183.1104);
    EXPECT_EQ(sequence.camera->width, 122);
    EXPECT_EQ(sequence.camera->height, 37);
  }
  // More times than images, a missing calib.txt: named.
  WriteFileAtomically(root + "/times.txt", "0\n0.1\n0.2\n0.3\n");
  try {
    ReadKittiSequence(root);
    ADD_FAILURE() << "accepted 4 times for 3 images";
  } catch (const FileError& error) {
    EXPECT_NE(std::string(error.what())
                  .find("lists 4 times, but '" + root + "/image_0' holds 3 PNG images"),
              std::string::npos)
        << error.what();
  }
  // Read as TUM (ocg_slam run's default format): the error names the format to give.
  try {
    ReadSequence(root, "tum");
    ADD_FAILURE() << "read a KITTI folder as TUM";
  } catch (const FileError& error) {
    EXPECT_NE(std::string(error.what()).find("a KITTI odometry folder: read it as format kitti"),
              std::string::npos)
        << error.what();
  }
  fs::remove(root + "/calib.txt");
  EXPECT_THROW(ReadKittiSequence(root), FileError);
  EXPECT_THROW(ReadSequence(root, "kitty"), std::invalid_argument);
}

TEST(KittiSequence, ReadsTheRealFolder) {
  const auto data = testing::SharedDataDir();
  if (!data) GTEST_SKIP() << testing::SharedDataSkipMessage();
  const ImageSequence sequence = ReadKittiSequence(*data + "/kitti_07_first160");
  ASSERT_EQ(sequence.images.size(), 160u);
  EXPECT_EQ(sequence.images.back().timestamp_text, "16.533760");
  EXPECT_EQ(sequence.camera->width, 1226);
  EXPECT_EQ(sequence.camera->height, 370);
  EXPECT_EQ(sequence.camera->fx, 707.0912);
}

}  // namespace
}  // namespace ocg
