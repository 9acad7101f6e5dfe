#include "ocg/core/map_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "test_support.h"

namespace ocg {
namespace {

std::string BinaryPayload() {
  std::string payload;
  for (int i = 0; i < 1000; ++i) payload += static_cast<char>(i * 7);  // NULs and newlines too
  return payload;
}

void WriteRaw(const std::string& path, const std::string& content) {
  std::ofstream(path, std::ios::binary) << content;
}

// The message of the MapFileError reading path throws; fails the test when none is thrown.
std::string ReadError(const std::string& path, const std::string& kind = "test-map",
                      std::uint32_t version = 3) {
  try {
    ReadMapFile(path, kind, version);
  } catch (const MapFileError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no MapFileError for " << path;
  return "";
}

TEST(MapFileEnvelope, PayloadComesBackByteForByte) {
  const std::string path = testing::MakeTempDir("map_file") + "/a.ocgmap";
  WriteMapFile(path, "test-map", 3, BinaryPayload());
  EXPECT_EQ(ReadMapFile(path, "test-map", 3), BinaryPayload());
}

TEST(MapFileEnvelope, ForeignFileIsNamedAndRefused) {
  const std::string path = testing::MakeTempDir("map_file") + "/image.png";
  WriteRaw(path, "\x89PNG\r\n\x1a\n" + BinaryPayload());
  const std::string message = ReadError(path);
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find("is not an OCG-SLAM map file"), std::string::npos) << message;
}

TEST(MapFileEnvelope, AnEmptyFileSaysItIsEmpty) {
  const std::string path = testing::MakeTempDir("map_file") + "/empty.ocgmap";
  WriteRaw(path, "");
  const std::string message = ReadError(path);
  EXPECT_NE(message.find("'" + path + "' is empty"), std::string::npos) << message;
}

TEST(MapFileEnvelope, AnotherKindIsRefused) {
  const std::string path = testing::MakeTempDir("map_file") + "/other.ocgmap";
  WriteMapFile(path, "other-map", 3, BinaryPayload());
  const std::string message = ReadError(path);
  EXPECT_NE(message.find("holds a 'other-map', not a 'test-map'"), std::string::npos) << message;
}

TEST(MapFileEnvelope, AnotherVersionSaysWhichAndWhatToDo) {
  const std::string path = testing::MakeTempDir("map_file") + "/v.ocgmap";
  WriteMapFile(path, "test-map", 4, BinaryPayload());
  std::string message = ReadError(path);
  EXPECT_NE(message.find("format version 4, this build reads version 3"), std::string::npos)
      << message;
  EXPECT_NE(message.find("newer build"), std::string::npos) << message;
  WriteMapFile(path, "test-map", 2, BinaryPayload());
  message = ReadError(path);
  EXPECT_NE(message.find("older build"), std::string::npos) << message;
}

// A build that still reads older versions (session maps: 1 and 2) says which it read, and
// refuses those outside the range with the range.
TEST(MapFileEnvelope, AnOlderVersionInTheRangeIsReadAndReported) {
  const std::string path = testing::MakeTempDir("map_file") + "/o.ocgmap";
  WriteMapFile(path, "test-map", 2, BinaryPayload());
  std::uint32_t read_version = 0;
  EXPECT_EQ(ReadMapFile(path, "test-map", 3, 2, &read_version), BinaryPayload());
  EXPECT_EQ(read_version, 2u);
  WriteMapFile(path, "test-map", 1, BinaryPayload());
  try {
    ReadMapFile(path, "test-map", 3, 2, &read_version);
    ADD_FAILURE() << "version 1 read by a build reading 2 to 3";
  } catch (const MapFileError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("format version 1, this build reads versions 2 to 3 (written by an "
                           "older build: remake the map)"),
              std::string::npos)
        << message;
  }
}

TEST(MapFileEnvelope, TruncatedFileSaysHowMuchIsMissing) {
  const std::string path = testing::MakeTempDir("map_file") + "/t.ocgmap";
  WriteMapFile(path, "test-map", 3, BinaryPayload());
  std::string content = ReadTextFile(path);
  WriteRaw(path, content.substr(0, content.size() - 300));
  const std::string message = ReadError(path);
  EXPECT_NE(message.find("truncated: 700 of 1000 payload bytes"), std::string::npos) << message;
  // Cut inside the header.
  WriteRaw(path, content.substr(0, 30));
  EXPECT_NE(ReadError(path).find("damaged header"), std::string::npos);
}

TEST(MapFileEnvelope, FlippedByteIsDetected) {
  const std::string path = testing::MakeTempDir("map_file") + "/d.ocgmap";
  WriteMapFile(path, "test-map", 3, BinaryPayload());
  std::string content = ReadTextFile(path);
  content[content.size() - 500] ^= 0x10;
  WriteRaw(path, content);
  const std::string message = ReadError(path);
  EXPECT_NE(message.find("damaged: the payload's checksum"), std::string::npos) << message;
}

TEST(MapFileEnvelope, ChecksumIsFnv1aOnShortTailsAndSeesEveryByte) {
  // Under 8 bytes it is FNV-1a: the FNV reference's vectors (isthe.com/chongo/tech/comp/fnv).
  EXPECT_EQ(PayloadChecksum(""), 0xcbf29ce484222325ull);
  EXPECT_EQ(PayloadChecksum("a"), 0xaf63dc4c8601ec8cull);
  EXPECT_EQ(PayloadChecksum("foobar"), 0x85944171f73967e8ull);
  // Any one bit changed anywhere in words or tail changes it.
  const std::string bytes = BinaryPayload().substr(0, 45);
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    std::string changed = bytes;
    changed[i] ^= 0x01;
    EXPECT_NE(PayloadChecksum(changed), PayloadChecksum(bytes)) << "byte " << i;
  }
}

TEST(MapFileEnvelope, PayloadStreamReadsWithoutCopyAndTellsItsPosition) {
  PayloadStream in(BinaryPayload());
  char first[10];
  in.read(first, sizeof first);
  EXPECT_EQ(std::string(first, 10), BinaryPayload().substr(0, 10));
  EXPECT_EQ(in.tellg(), 10);
  std::string rest(990, '\0');
  in.read(rest.data(), 990);
  EXPECT_EQ(rest, BinaryPayload().substr(10));
  EXPECT_FALSE(in.read(first, 1));  // the end
}

TEST(MapFileEnvelope, ChecksumOfPiecesIsTheChecksumOfTheWhole) {
  const std::string bytes = BinaryPayload();
  for (const std::size_t piece : {1u, 3u, 7u, 8u, 13u, 64u, 999u}) {
    PayloadChecksummer sum;
    for (std::size_t at = 0; at < bytes.size(); at += piece)
      sum.Add(bytes.data() + at, std::min(piece, bytes.size() - at));
    EXPECT_EQ(sum.Value(), PayloadChecksum(bytes)) << "pieces of " << piece;
  }
}

TEST(MapFileEnvelope, ReaderStreamsThePayloadFromTheFile) {
  const std::string path = testing::MakeTempDir("map_file") + "/s.ocgmap";
  WriteMapFile(path, "test-map", 3, BinaryPayload());
  MapFileReader reader(path, "test-map", 3);
  EXPECT_EQ(reader.version(), 3u);
  EXPECT_EQ(reader.payload_size(), BinaryPayload().size());
  std::string payload(BinaryPayload().size(), '\0');
  ASSERT_TRUE(reader.payload().read(payload.data(), static_cast<std::streamsize>(payload.size())));
  EXPECT_EQ(payload, BinaryPayload());
  char beyond = 0;
  EXPECT_FALSE(reader.payload().read(&beyond, 1));
}

// The process's resident memory in bytes (Linux).
std::size_t ResidentBytes() {
  std::ifstream statm("/proc/self/statm");
  std::size_t pages = 0, resident = 0;
  statm >> pages >> resident;
  return resident * static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
}

// A large file that is not a map (a rosbag given by mistake) is refused from its first
// bytes: it was read whole first (2.2 GB resident for a 2 GB file, std::bad_alloc for
// 7 GB). A sparse file costs no disk.
TEST(MapFileEnvelope, ALargeFileThatIsNotAMapIsRefusedWithoutReadingIt) {
  const std::string path = testing::MakeTempDir("map_file") + "/large.bag";
  {
    std::ofstream out(path, std::ios::binary);
    out << "#ROSBAG V2.0\n";
  }
  std::filesystem::resize_file(path, std::uintmax_t{8} << 30);  // 8 GiB, sparse
  const std::size_t before = ResidentBytes();
  const std::string message = ReadError(path);
  EXPECT_NE(message.find("is not an OCG-SLAM map file"), std::string::npos) << message;
  EXPECT_NE(message.find("#ROSBAG V2.0"), std::string::npos) << message;
  EXPECT_LT(ResidentBytes(), before + (64u << 20));
}

// A map file's payload is checked (size, checksum) and read in blocks: a damaged
// 192 MiB payload is found damaged without holding it.
TEST(MapFileEnvelope, ALargePayloadIsCheckedWithoutHoldingIt) {
  const std::string path = testing::MakeTempDir("map_file") + "/large.ocgmap";
  const std::uint64_t size = std::uint64_t{192} << 20;
  const std::string header = std::string(kMapFileMagic) + "\nkind test-map\nversion 3\npayload " +
                             std::to_string(size) + " checksum 0123456789abcdef\n";
  WriteRaw(path, header);
  std::filesystem::resize_file(path, header.size() + size);  // sparse zeros
  const std::size_t before = ResidentBytes();
  const std::string message = ReadError(path);
  EXPECT_NE(message.find("damaged: the payload's checksum"), std::string::npos) << message;
  EXPECT_LT(ResidentBytes(), before + (64u << 20));
}

}  // namespace
}  // namespace ocg
