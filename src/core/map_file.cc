#include "ocg/core/map_file.h"

#include <algorithm>
#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <utility>
#include <vector>

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

constexpr std::size_t kHeaderLimit = 1024;  // 4 lines of at most 200 bytes
constexpr std::size_t kBlock = 1 << 20;     // bytes per read while checking and loading

std::uint64_t WordAt(const char* bytes) {
  std::uint64_t word = 0;
  for (int b = 7; b >= 0; --b) {  // little-endian on every machine; compilers fuse it
    word = (word << 8) | static_cast<unsigned char>(bytes[b]);
  }
  return word;
}

constexpr std::uint64_t kFnvPrime = 0x100000001b3ull;

std::string Printable(const std::string& text) {
  std::string shown;
  for (const char c : text.substr(0, 40)) shown += (c >= 32 && c < 127) ? c : '?';
  return shown;
}

}  // namespace

std::uint64_t PayloadChecksum(const std::string& bytes) {
  PayloadChecksummer checksum;
  checksum.Add(bytes.data(), bytes.size());
  return checksum.Value();
}

void PayloadChecksummer::Add(const char* bytes, std::size_t size) {
  while (pending_size_ > 0 && pending_size_ < 8 && size > 0) {
    pending_[pending_size_++] = *bytes++;
    --size;
  }
  if (pending_size_ == 8) {
    hash_ = (hash_ ^ WordAt(pending_)) * kFnvPrime;
    pending_size_ = 0;
  }
  const std::size_t words = size / 8;
  for (std::size_t i = 0; i < words; ++i) hash_ = (hash_ ^ WordAt(bytes + 8 * i)) * kFnvPrime;
  for (std::size_t i = 8 * words; i < size; ++i) pending_[pending_size_++] = bytes[i];
}

std::uint64_t PayloadChecksummer::Value() const {
  std::uint64_t hash = hash_;
  for (std::size_t i = 0; i < pending_size_; ++i)
    hash = (hash ^ static_cast<unsigned char>(pending_[i])) * kFnvPrime;
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

MapFileReader::MapFileReader(const std::string& path, const std::string& kind,
                             std::uint32_t version, std::uint32_t oldest_version) {
  if (oldest_version == 0) oldest_version = version;
  RequireRegularFile(path);
  buffer_ = std::make_unique<char[]>(kBlock);
  file_ = std::make_unique<std::ifstream>();
  file_->rdbuf()->pubsetbuf(buffer_.get(), kBlock);
  file_->open(path, std::ios::binary);
  if (!*file_) throw FileError("cannot open '" + path + "': " + std::strerror(errno));
  file_->seekg(0, std::ios::end);
  const std::uint64_t file_size = static_cast<std::uint64_t>(file_->tellg());
  file_->seekg(0);
  // The header alone, at most its limit: what a file is shows in its first bytes.
  std::string header(static_cast<std::size_t>(std::min<std::uint64_t>(file_size, kHeaderLimit)),
                     '\0');
  if (!file_->read(header.data(), static_cast<std::streamsize>(header.size())))
    throw FileError("error while reading '" + path + "'");
  const std::string where = "map file '" + path + "': ";
  std::size_t position = 0;
  std::string line;
  if (header.empty()) {
    throw MapFileError("'" + path +
                       "' is empty, not an OCG-SLAM map file (an interrupted copy?); give a file "
                       "written by ocg_slam run --save-map");
  }
  if (!NextLine(header, &position, &line) || line != kMapFileMagic) {
    throw MapFileError("'" + path + "' is not an OCG-SLAM map file (it does not start with '" +
                       kMapFileMagic + "' but with '" + Printable(header) +
                       "'); give a file written by ocg_slam run --save-map");
  }
  if (!NextLine(header, &position, &line) || line.rfind("kind ", 0) != 0) {
    throw MapFileError(where + "damaged header: line 2 should be 'kind <kind>'");
  }
  if (line.substr(5) != kind) {
    throw MapFileError(where + "it holds a '" + line.substr(5) + "', not a '" + kind + "'");
  }
  unsigned long long file_version = 0;
  if (!NextLine(header, &position, &line) ||
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
  version_ = static_cast<std::uint32_t>(file_version);
  unsigned long long size = 0;
  std::uint64_t checksum = 0;
  if (!NextLine(header, &position, &line) ||
      std::sscanf(line.c_str(), "payload %llu checksum %" SCNx64, &size, &checksum) != 2) {
    throw MapFileError(where +
                       "damaged header: line 4 should be 'payload <bytes> checksum <checksum>'");
  }
  const std::uint64_t present = file_size - position;
  if (present < size) {
    throw MapFileError(where + "truncated: " + std::to_string(present) + " of " +
                       std::to_string(size) +
                       " payload bytes present (an interrupted copy or a full disk?)");
  }
  if (present > size) {
    throw MapFileError(where + "damaged: " + std::to_string(present - size) +
                       " bytes more than the header announces");
  }
  payload_size_ = size;
  // The checksum before any of the payload is parsed, so damage is named as such.
  file_->seekg(static_cast<std::streamoff>(position));
  PayloadChecksummer sum;
  std::vector<char> block(kBlock);
  for (std::uint64_t left = size; left > 0;) {
    const std::size_t count = static_cast<std::size_t>(std::min<std::uint64_t>(left, kBlock));
    if (!file_->read(block.data(), static_cast<std::streamsize>(count)))
      throw FileError("error while reading '" + path + "'");
    sum.Add(block.data(), count);
    left -= count;
  }
  if (sum.Value() != checksum) {
    throw MapFileError(where +
                       "damaged: the payload's checksum does not match its header (a copy of the "
                       "file made before the damage, or a new map, is needed)");
  }
  file_->seekg(static_cast<std::streamoff>(position));
}

std::string ReadMapFile(const std::string& path, const std::string& kind, std::uint32_t version,
                        std::uint32_t oldest_version, std::uint32_t* read_version) {
  MapFileReader reader(path, kind, version, oldest_version);
  if (read_version != nullptr) *read_version = reader.version();
  std::string payload(static_cast<std::size_t>(reader.payload_size()), '\0');
  if (!reader.payload().read(payload.data(), static_cast<std::streamsize>(payload.size())))
    throw FileError("error while reading '" + path + "'");
  return payload;
}

}  // namespace ocg
