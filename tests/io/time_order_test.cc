// Frame lists and trajectories must increase strictly in time: each reader names the
// offending line and the earlier line it conflicts with.

#include "ocg/io/time_order.h"

#include <gtest/gtest.h>

#include <string>

#include "ocg/core/file_io.h"
#include "ocg/io/sequence.h"
#include "ocg/io/text_lines.h"
#include "ocg/io/trajectory.h"
#include "test_support.h"

namespace ocg {
namespace {

// The message of the ParseError that read throws; fails the test when none is thrown.
template <typename Read>
std::string ParseErrorOf(Read read) {
  try {
    read();
  } catch (const ParseError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no ParseError";
  return "";
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

TEST(FrameOrder, TrajectoriesAreCheckedToo) {
  const std::string dir = testing::MakeTempDir("order_trajectory");
  WriteFileAtomically(dir + "/poses.txt",
                      "# timestamp tx ty tz qx qy qz qw\n2.0 0 0 0 0 0 0 1\n1.0 0 0 0 0 0 0 1\n");
  ExpectContains(ParseErrorOf([&] { ReadTumTrajectory(dir + "/poses.txt"); }),
                 "poses.txt:3: pose time 1.0 is earlier than line 2 ('2.0')");
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
