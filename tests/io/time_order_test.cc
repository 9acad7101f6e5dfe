// Frame lists and trajectories must increase strictly in time: each reader names the
// offending line and the earlier line it conflicts with.

#include "ocg/io/time_order.h"

#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <memory>
#include <sstream>
#include <string>

#include "error_of.h"
#include "ocg/core/file_io.h"
#include "ocg/io/sequence.h"
#include "ocg/io/text_lines.h"
#include "ocg/io/trajectory.h"
#include "test_support.h"

namespace ocg {
namespace {

// The message of the ParseError read throws; fails the test when none is thrown.
template <typename Read>
std::string ParseErrorOf(Read read) {
  return testing::ErrorOf<ParseError>(read);
}

void ExpectContains(const std::string& text, const std::string& part) {
  EXPECT_NE(text.find(part), std::string::npos) << "'" << part << "' not in: " << text;
}

const char kTumHeader[] = "# color images\n# timestamp filename\n";

TEST(FrameOrder, TumListGoingBackwardsNamesBothLines) {
  const std::string dir = testing::MakeTempDir("order_backwards");
  // Lines 3-5 hold frames; the third goes back in time.
  WriteFileAtomically(dir + "/rgb.txt",
                      std::string(kTumHeader) + "1.30 rgb/a.png\n1.40 rgb/b.png\n1.20 rgb/c.png\n");
  const std::string message = ParseErrorOf([&] { ReadTumSequence(dir); });
  ExpectContains(message, dir + "/rgb.txt:5: frame time 1.20 is earlier than line 4 ('1.40')");
  ExpectContains(message, "increasing time");
}

TEST(FrameOrder, OneFrameLabelledWithAnEarlierTimeIsCaught) {
  const std::string dir = testing::MakeTempDir("order_earlier");
  WriteFileAtomically(dir + "/frames.txt",
                      "1.0 a.png\n1.1 b.png\n1.2 c.png\n0.5 d.png\n1.4 e.png\n");
  ExpectContains(ParseErrorOf([&] { ReadTumImageList(dir + "/frames.txt", dir); }),
                 "frames.txt:4: frame time 0.5 is earlier than line 3 ('1.2')");
}

TEST(FrameOrder, RepeatedTimeNamesTheLineItRepeatsWhereverItIs) {
  const std::string dir = testing::MakeTempDir("order_repeat");
  WriteFileAtomically(dir + "/adjacent.txt", "1.0 a.png\n1.1 b.png\n1.10 c.png\n");
  ExpectContains(ParseErrorOf([&] { ReadTumImageList(dir + "/adjacent.txt", dir); }),
                 "adjacent.txt:3: frame time 1.10 repeats line 2 ('1.1')");
  // Not next to each other: the message names the frame it repeats, not the previous one.
  WriteFileAtomically(dir + "/apart.txt", "1.0 a.png\n1.1 b.png\n1.2 c.png\n1.1 d.png\n");
  ExpectContains(ParseErrorOf([&] { ReadTumImageList(dir + "/apart.txt", dir); }),
                 "apart.txt:4: frame time 1.1 repeats line 2 ('1.1')");
}

TEST(FrameOrder, EurocDataCsvIsCheckedAsTumLists) {
  const std::string root = testing::MakeTempDir("order_euroc");
  WriteFileAtomically(root + "/mav0/cam0/sensor.yaml",
                      "%YAML:1.0\nresolution: [752, 480]\nintrinsics: [400, 400, 376, 240]\n");
  const std::string csv = root + "/mav0/cam0/data.csv";
  WriteFileAtomically(csv,
                      "#timestamp [ns],filename\n1000000000,1.png\n1050000000,2.png\n"
                      "1025000000,3.png\n");
  ExpectContains(ParseErrorOf([&] { ReadEurocSequence(root); }),
                 csv + ":4: frame time 1025000000 is earlier than line 3 ('1050000000')");
  WriteFileAtomically(csv, "#timestamp [ns],filename\n1000000000,1.png\n1000000000,2.png\n");
  ExpectContains(ParseErrorOf([&] { ReadEurocSequence(root); }),
                 csv + ":3: frame time 1000000000 repeats line 2 ('1000000000')");
  WriteFileAtomically(csv, "#timestamp [ns],filename\n1000000000,1.png\n1050000000,2.png\n");
  EXPECT_EQ(ReadEurocSequence(root).images.size(), 2u);
}

// The warnings spdlog's default logger receives while the capture lives.
class CapturedWarnings {
 public:
  CapturedWarnings()
      : previous_(spdlog::default_logger()),
        logger_(std::make_shared<spdlog::logger>(
            "capture", std::make_shared<spdlog::sinks::ostream_sink_mt>(text_))) {
    spdlog::set_default_logger(logger_);
  }
  ~CapturedWarnings() { spdlog::set_default_logger(previous_); }
  std::string Text() const { return text_.str(); }
  int Lines() const {
    const std::string text = Text();
    return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
  }

 private:
  std::ostringstream text_;
  std::shared_ptr<spdlog::logger> previous_;
  std::shared_ptr<spdlog::logger> logger_;
};

// Modelled on the official fr2_desk ground truth, which lists 1311868229.5760 on two
// consecutive lines (10862-10863): TUM's associate.py and evo read it, and so must we.
const char kFr2DeskLike[] =
    "# ground truth trajectory\n"
    "# file: 'rgbd_dataset_freiburg2_desk.bag'\n"
    "# timestamp tx ty tz qx qy qz qw\n"
    "1311868229.5660 -0.1001 -1.2001 0.6001 0.7001 0.1001 0.1001 -0.6956\n"
    "1311868229.5760 -0.1002 -1.2002 0.6002 0.7001 0.1001 0.1001 -0.6956\n"
    "1311868229.5760 -0.1003 -1.2003 0.6003 0.7001 0.1001 0.1001 -0.6956\n"
    "1311868229.5860 -0.1004 -1.2004 0.6004 0.7001 0.1001 0.1001 -0.6956\n";

TEST(ReferencePoses, ARepeatedTimeAsInFr2DeskKeepsTheFirstPoseWithOneWarning) {
  const std::string dir = testing::MakeTempDir("reference_repeat");
  const std::string path = dir + "/groundtruth.txt";
  WriteFileAtomically(path, kFr2DeskLike);
  CapturedWarnings warnings;
  const std::vector<StampedPose> poses = ReadTumTrajectory(path);
  ASSERT_EQ(poses.size(), 3u);
  EXPECT_EQ(poses[1].timestamp_text, "1311868229.5760");
  EXPECT_NEAR(poses[1].T_wc.translation().x(), -0.1002, 1e-12);  // the first of the two
  EXPECT_NEAR(poses[2].T_wc.translation().x(), -0.1004, 1e-12);
  EXPECT_EQ(warnings.Lines(), 1) << warnings.Text();
  ExpectContains(warnings.Text(), path +
                                      ": 1 repeated pose time (line 6 repeats line 5 "
                                      "('1311868229.5760')): kept the first pose of each time");
}

TEST(ReferencePoses, ManyRepeatsAreOneWarningWithTheirCount) {
  const std::string dir = testing::MakeTempDir("reference_repeats");
  std::string text;
  for (int i = 0; i < 10; ++i) {
    const std::string line = std::to_string(i) + " 0 0 0 0 0 0 1\n";
    text += line + line;
  }
  WriteFileAtomically(dir + "/poses.txt", text);
  CapturedWarnings warnings;
  EXPECT_EQ(ReadTumTrajectory(dir + "/poses.txt").size(), 10u);
  EXPECT_EQ(warnings.Lines(), 1) << warnings.Text();
  ExpectContains(warnings.Text(),
                 "10 repeated pose times (line 2 repeats line 1 ('0'); line 4 "
                 "repeats line 3 ('1'); line 6 repeats line 5 ('2'); ...)");
}

TEST(ReferencePoses, LinesOutOfOrderAreSortedWithAWarning) {
  // associate.py keys the lines by time, whatever their order.
  const std::string dir = testing::MakeTempDir("reference_unsorted");
  WriteFileAtomically(dir + "/poses.txt",
                      "# timestamp tx ty tz qx qy qz qw\n2.0 2 0 0 0 0 0 1\n1.0 1 0 0 0 0 0 1\n"
                      "3.0 3 0 0 0 0 0 1\n2.0 9 0 0 0 0 0 1\n");
  CapturedWarnings warnings;
  const std::vector<StampedPose> poses = ReadTumTrajectory(dir + "/poses.txt");
  ASSERT_EQ(poses.size(), 3u);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(poses[i].T_wc.translation().x(), i + 1.0);
  ExpectContains(warnings.Text(),
                 "2 poses listed before an earlier time (first: line 3, time "
                 "1.0 after 2.0 at line 2): sorted by time");
  ExpectContains(warnings.Text(), "1 repeated pose time (line 5 repeats line 2 ('2.0'))");
}

TEST(ReferencePoses, CommasAndTabsSeparateFieldsAsInAssociatePy) {
  const std::string dir = testing::MakeTempDir("reference_commas");
  WriteFileAtomically(dir + "/poses.txt", "1.0,1,2,3,0,0,0,1\n2.0\t4\t5\t6 0, 0, 0, 1\n");
  CapturedWarnings warnings;
  const std::vector<StampedPose> poses = ReadTumTrajectory(dir + "/poses.txt");
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_EQ(poses[1].T_wc.translation().z(), 6.0);
  EXPECT_EQ(warnings.Text(), "");  // nothing done to the poses: nothing to say
}

TEST(ReferencePoses, KittiPoseLinesAreNamedAsSuch) {
  const std::string dir = testing::MakeTempDir("reference_kitti");
  WriteFileAtomically(dir + "/poses.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n");
  ExpectContains(ParseErrorOf([&] { ReadTumTrajectory(dir + "/poses.txt"); }),
                 "poses.txt:1: expected 8 fields 'timestamp tx ty tz qx qy qz qw', got 12 (12 "
                 "numbers without a time are a KITTI pose line");
}

TEST(ReferencePoses, EurocGroundTruthWithARepeatedTimeKeepsTheFirst) {
  const std::string root = testing::MakeTempDir("reference_euroc");
  WriteFileAtomically(root + "/mav0/cam0/sensor.yaml",
                      "%YAML:1.0\nresolution: [752, 480]\nintrinsics: [400, 400, 376, 240]\n");
  WriteFileAtomically(root + "/mav0/cam0/data.csv",
                      "#timestamp [ns],filename\n1000000000,1.png\n1050000000,2.png\n");
  const std::string csv = root + "/mav0/state_groundtruth_estimate0/data.csv";
  WriteFileAtomically(csv,
                      "#timestamp,p_x,p_y,p_z,q_w,q_x,q_y,q_z\n1000000000,1,0,0,1,0,0,0\n"
                      "1000000000,2,0,0,1,0,0,0\n1050000000,3,0,0,1,0,0,0\n");
  CapturedWarnings warnings;
  const ImageSequence sequence = ReadEurocSequence(root);
  ASSERT_EQ(sequence.groundtruth.size(), 2u);
  EXPECT_EQ(sequence.groundtruth[0].T_wc.translation().x(), 1.0);
  ExpectContains(warnings.Text(), csv + ": 1 repeated pose time (line 3 repeats line 2");
}

TEST(ReferencePoses, TheInputsOfARunStayStrict) {
  // The same repeat in a frame list is refused: two frames would read one detection file.
  const std::string dir = testing::MakeTempDir("reference_inputs");
  WriteFileAtomically(dir + "/rgb.txt", "1311868229.5760 a.png\n1311868229.5760 b.png\n");
  ExpectContains(ParseErrorOf([&] { ReadTumImageList(dir + "/rgb.txt", dir); }),
                 "rgb.txt:2: frame time 1311868229.5760 repeats line 1");
}

TEST(FrameOrder, IncreasingListsPass) {
  TimeOrderCheck order("list.txt", "frame");
  order.Add(1.0, "1.0", 1);
  order.Add(1.000001, "1.000001", 3);
  order.Add(2.0, "2.0", 4);
  EXPECT_THROW(order.Add(2.0, "2.000", 5), ParseError);
}

TEST(FrameOrder, RealListsAreInOrder) {
  const auto data = testing::SharedDataDir();
  if (!data) GTEST_SKIP() << testing::SharedDataSkipMessage();
  EXPECT_EQ(ReadTumImageList(*data + "/tum_fr3_long_office/rgb_all_frames.txt", "/").size(), 2585u);
  EXPECT_EQ(ReadTumTrajectory(*data + "/tum_fr3_long_office/groundtruth.txt").size(), 8710u);
  EXPECT_EQ(ReadTumSequence(*data + "/kitti_07_first160").images.size(), 160u);
  EXPECT_EQ(ReadEurocSequence(*data + "/euroc_v101_micro").images.size(), 95u);
}

}  // namespace
}  // namespace ocg
