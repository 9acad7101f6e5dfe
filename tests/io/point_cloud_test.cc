#include <gtest/gtest.h>

#include <filesystem>

#include "ocg/core/file_io.h"
#include "ocg/io/point_cloud.h"
#include "ocg/io/text_lines.h"
#include "test_support.h"

namespace ocg {
namespace {

TEST(PlyPoints, RoundTripAndOtherWritersFiles) {
  const std::string dir = testing::MakeTempDir("ply");
  const std::vector<Eigen::Vector3d> points = {{0.5, -1.25, 3}, {1e-3, 2, -7.5}};
  WritePlyPoints(dir + "/a.ply", points);
  const std::vector<Eigen::Vector3d> back = ReadPlyPoints(dir + "/a.ply");
  ASSERT_EQ(back.size(), 2u);
  EXPECT_LT((back[0] - points[0]).norm(), 1e-6);
  EXPECT_LT((back[1] - points[1]).norm(), 1e-6);
  // Another program's file: colours before the coordinates, a face element after.
  WriteFileAtomically(dir + "/b.ply",
                      "ply\nformat ascii 1.0\nelement vertex 1\nproperty uchar red\n"
                      "property float x\nproperty float y\nproperty float z\n"
                      "element face 0\nproperty list uchar int vertex_indices\nend_header\n"
                      "255 1 2 3\n");
  EXPECT_EQ(ReadPlyPoints(dir + "/b.ply").at(0), Eigen::Vector3d(1, 2, 3));
  std::filesystem::remove_all(dir);
}

TEST(PlyPoints, ErrorsNameTheFileAndLine) {
  const std::string dir = testing::MakeTempDir("ply_bad");
  WriteFileAtomically(dir + "/short.ply",
                      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
                      "property float y\nproperty float z\nend_header\n1 2 3\n4 5\n");
  try {
    ReadPlyPoints(dir + "/short.ply");
    FAIL() << "no error";
  } catch (const ParseError& error) {
    EXPECT_NE(std::string(error.what()).find("short.ply:9"), std::string::npos) << error.what();
  }
  WriteFileAtomically(dir + "/binary.ply",
                      "ply\nformat binary_little_endian 1.0\nelement vertex 0\nend_header\n");
  EXPECT_THROW(ReadPlyPoints(dir + "/binary.ply"), ParseError);
  EXPECT_THROW(ReadPlyPoints(dir + "/missing.ply"), FileError);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ocg
