#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>

#include "ocg/core/file_io.h"
#include "test_support.h"

namespace ocg {
namespace {

namespace fs = std::filesystem;

TEST(FileIo, AtomicWriteCreatesParentsAndReplaces) {
  const std::string dir = testing::MakeTempDir("file_io");
  const std::string path = dir + "/a/b/out.txt";
  WriteFileAtomically(path, "first");
  WriteFileAtomically(path, "second");
  EXPECT_EQ(ReadTextFile(path), "second");
  for (const auto& entry : fs::directory_iterator(dir + "/a/b")) {
    EXPECT_EQ(entry.path().filename(), "out.txt") << "temporary file left behind";
  }
}

TEST(FileIo, FailedWriteKeepsThePreviousFile) {
  const std::string dir = testing::MakeTempDir("file_io_fail");
  const std::string path = dir + "/out.txt";
  WriteFileAtomically(path, "keep me");
  fs::create_directory(path + ".tmp." + std::to_string(::getpid()));  // blocks the temp file
  EXPECT_THROW(WriteFileAtomically(path, "lost"), FileError);
  EXPECT_EQ(ReadTextFile(path), "keep me");
}

TEST(FileIo, ErrorsNameTheFile) {
  try {
    ReadTextFile("/nonexistent/file.txt");
    FAIL();
  } catch (const FileError& error) {
    EXPECT_NE(std::string(error.what()).find("/nonexistent/file.txt"), std::string::npos);
  }
}

TEST(FileIo, WritableFolderCheckCreatesTheFolderAndLeavesNothing) {
  const std::string dir = testing::MakeTempDir("file_io_writable") + "/a/b";
  CheckWritableFolder(dir);
  EXPECT_TRUE(fs::is_directory(dir));
  EXPECT_TRUE(fs::is_empty(dir));  // the probe file is removed
}

TEST(FileIo, UnwritableFolderFailsNamingIt) {
  const std::string dir = testing::MakeTempDir("file_io_unwritable");
  // A folder in the probe file's place makes the folder unwritable even for root.
  fs::create_directory(dir + "/.write_test." + std::to_string(::getpid()));
  try {
    CheckWritableFolder(dir);
    FAIL();
  } catch (const FileError& error) {
    EXPECT_NE(std::string(error.what()).find("output folder '" + dir + "' is not writable"),
              std::string::npos)
        << error.what();
  }
  WriteFileAtomically(dir + "/file", "x");
  try {
    CheckWritableFolder(dir + "/file/out");  // under a file: cannot be created
    FAIL();
  } catch (const FileError& error) {
    EXPECT_NE(
        std::string(error.what()).find("cannot create the output folder '" + dir + "/file/out'"),
        std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace ocg
