#include "ocg/core/map_file.h"

#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <utility>

namespace ocg {
namespace {

// One header line: the text up to the next newline, at most max_length bytes (a binary
// file has none early; it must not be read whole as a "line").
bool NextLine(const std::string& text, std::size_t* position, std::string* line,
              std::size_t max_length = 200) {
  const std::size_t end = text.find('\n', *position);
  if (end == std::string::npos || end - *position > max_length) return false;
  *line = text.substr(*position, end - *position);
  *position = end + 1;
  return true;
}

// The whole file in one read into a string of its size (a stream copy took 250 ms of a
// 70 MB map's load).
std::string ReadBinaryFile(const std::string& path) {
  RequireRegularFile(path);
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) throw FileError("cannot open '" + path + "': " + std::strerror(errno));
  std::string content;
  if (std::fseek(file, 0, SEEK_END) == 0) {
    const long size = std::ftell(file);
    if (size > 0) content.resize(static_cast<std::size_t>(size));
    std::rewind(file);
  }
  const std::size_t read = std::fread(content.data(), 1, content.size(), file);
  const bool failed = std::ferror(file) != 0;
  std::fclose(file);
  if (failed || read != content.size()) throw FileError("error while reading '" + path + "'");
  return content;
}

std::string Printable(const std::string& text) {
  std::string shown;
  for (const char c : text.substr(0, 40)) shown += (c >= 32 && c < 127) ? c : '?';
  return shown;
}

}  // namespace

std::uint64_t PayloadChecksum(const std::string& bytes) {
  constexpr std::uint64_t kPrime = 0x100000001b3ull;
  std::uint64_t hash = 0xcbf29ce484222325ull;
  const std::size_t words = bytes.size() / 8;
  for (std::size_t i = 0; i < words; ++i) {
    std::uint64_t word = 0;
    for (int b = 7; b >= 0; --b) {  // little-endian on every machine; compilers fuse it
      word = (word << 8) | static_cast<unsigned char>(bytes[8 * i + static_cast<std::size_t>(b)]);
    }
    hash = (hash ^ word) * kPrime;
  }
  for (std::size_t i = 8 * words; i < bytes.size(); ++i)
    hash = (hash ^ static_cast<unsigned char>(bytes[i])) * kPrime;
  return hash;
}

PayloadStream::PayloadStream(std::string payload)
    : std::istream(nullptr), payload_(std::move(payload)) {
  buffer_.Set(payload_);
  rdbuf(&buffer_);
}

void PayloadStream::Buffer::Set(const std::string& bytes) {
  char* begin = const_cast<char*>(bytes.data());  // read only: the get area
  setg(begin, begin, begin + bytes.size());
}

PayloadStream::Buffer::pos_type PayloadStream::Buffer::seekoff(off_type offset,
                                                               std::ios_base::seekdir direction,
                                                               std::ios_base::openmode mode) {
  if (offset != 0 || direction != std::ios_base::cur || !(mode & std::ios_base::in))
    return pos_type(off_type(-1));
  return pos_type(gptr() - eback());
}

void WriteMapFile(const std::string& path, const std::string& kind, std::uint32_t version,
                  const std::string& payload) {
  char checksum[17];
  std::snprintf(checksum, sizeof checksum, "%016" PRIx64, PayloadChecksum(payload));
  std::string content = std::string(kMapFileMagic) + "\nkind " + kind + "\nversion " +
                        std::to_string(version) + "\npayload " + std::to_string(payload.size()) +
                        " checksum " + checksum + "\n";
  content += payload;
  WriteFileAtomically(path, content);
}

std::string ReadMapFile(const std::string& path, const std::string& kind, std::uint32_t version,
                        std::uint32_t oldest_version, std::uint32_t* read_version) {
  if (oldest_version == 0) oldest_version = version;
  std::string content = ReadBinaryFile(path);
  const std::string where = "map file '" + path + "': ";
  std::size_t position = 0;
  std::string line;
  if (content.empty()) {
    throw MapFileError("'" + path +
                       "' is empty, not an OCG-SLAM map file (an interrupted copy?); give a file "
                       "written by ocg_slam run --save-map");
  }
  if (!NextLine(content, &position, &line) || line != kMapFileMagic) {
    throw MapFileError("'" + path + "' is not an OCG-SLAM map file (it does not start with '" +
                       kMapFileMagic + "' but with '" + Printable(content) +
                       "'); give a file written by ocg_slam run --save-map");
  }
  if (!NextLine(content, &position, &line) || line.rfind("kind ", 0) != 0) {
    throw MapFileError(where + "damaged header: line 2 should be 'kind <kind>'");
  }
  if (line.substr(5) != kind) {
    throw MapFileError(where + "it holds a '" + line.substr(5) + "', not a '" + kind + "'");
  }
  unsigned long long file_version = 0;
  if (!NextLine(content, &position, &line) ||
      std::sscanf(line.c_str(), "version %llu", &file_version) != 1) {
    throw MapFileError(where + "damaged header: line 3 should be 'version <number>'");
  }
  if (file_version < oldest_version || file_version > version) {
    const std::string reads =
        oldest_version == version
            ? "version " + std::to_string(version) + " only"
            : "versions " + std::to_string(oldest_version) + " to " + std::to_string(version);
    throw MapFileError(where + "format version " + std::to_string(file_version) +
                       ", this build reads " + reads + " (" +
                       (file_version > version ? "written by a newer build: update OCG-SLAM"
                                               : "written by an older build: remake the map") +
                       ")");
  }
  if (read_version != nullptr) *read_version = static_cast<std::uint32_t>(file_version);
  unsigned long long size = 0;
  std::uint64_t checksum = 0;
  if (!NextLine(content, &position, &line) ||
      std::sscanf(line.c_str(), "payload %llu checksum %" SCNx64, &size, &checksum) != 2) {
    throw MapFileError(where +
                       "damaged header: line 4 should be 'payload <bytes> checksum <checksum>'");
  }
  const std::size_t present = content.size() - position;
  if (present < size) {
    throw MapFileError(where + "truncated: " + std::to_string(present) + " of " +
                       std::to_string(size) +
                       " payload bytes present (an interrupted copy or a full disk?)");
  }
  if (present > size) {
    throw MapFileError(where + "damaged: " + std::to_string(present - size) +
                       " bytes more than the header announces");
  }
  content.erase(0, position);  // the payload, in place: maps run to tens of megabytes
  if (PayloadChecksum(content) != checksum) {
    throw MapFileError(where +
                       "damaged: the payload's checksum does not match its header (a copy of the "
                       "file made before the damage, or a new map, is needed)");
  }
  return content;
}

}  // namespace ocg
