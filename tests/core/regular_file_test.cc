// A path that is not a regular file (a directory, a FIFO, nothing) is named with what it
// is, instead of reading as an empty file.

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <string>

#include "ocg/core/file_io.h"
#include "test_support.h"

namespace ocg {
namespace {

std::string FileErrorOf(const std::string& path) {
  try {
    ReadTextFile(path);
  } catch (const FileError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no FileError for " << path;
  return "";
}

TEST(RegularFile, ADirectoryIsNamedAsOne) {
  const std::string dir = testing::MakeTempDir("regular_dir");
  EnsureDirectory(dir + "/rgb.txt");
  EXPECT_EQ(FileErrorOf(dir + "/rgb.txt"),
            "cannot read '" + dir + "/rgb.txt': it is a directory, not a file");
}

TEST(RegularFile, AFifoAndAMissingPathAreNamed) {
  const std::string dir = testing::MakeTempDir("regular_fifo");
  ASSERT_EQ(::mkfifo((dir + "/pipe").c_str(), 0600), 0);
  // Reading would block forever on a FIFO with no writer.
  EXPECT_EQ(FileErrorOf(dir + "/pipe"),
            "cannot read '" + dir + "/pipe': it is a named pipe (FIFO), not a file");
  EXPECT_EQ(FileErrorOf(dir + "/none.txt"),
            "cannot read '" + dir + "/none.txt': it does not exist");
}

TEST(RegularFile, ARegularFileAndALinkToOneRead) {
  const std::string dir = testing::MakeTempDir("regular_ok");
  WriteFileAtomically(dir + "/a.txt", "text\n");
  EXPECT_NO_THROW(RequireRegularFile(dir + "/a.txt"));
  ASSERT_EQ(::symlink((dir + "/a.txt").c_str(), (dir + "/link.txt").c_str()), 0);
  EXPECT_EQ(ReadTextFile(dir + "/link.txt"), "text\n");
}

}  // namespace
}  // namespace ocg
