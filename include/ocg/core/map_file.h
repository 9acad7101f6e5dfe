#pragma once
// The envelope of map files (docs/sessions.md): a short text header of our own, then a
// binary payload that the modules fill with cereal archives. The header says what the
// file is before anything is parsed, so a foreign file, a file of another kind or
// version, a truncated or a damaged one is refused with a message naming the file:
//
//   OCG-SLAM map file\n
//   kind <kind>\n
//   version <version>\n
//   payload <bytes> checksum <16 hex digits>\n
//   <payload>

#include <cstdint>
#include <fstream>
#include <istream>
#include <memory>
#include <streambuf>
#include <string>

#include "ocg/core/file_io.h"

namespace ocg {

class MapFileError : public FileError {
 public:
  using FileError::FileError;
};

inline constexpr const char* kMapFileMagic = "OCG-SLAM map file";

// The payload's checksum (catches damage, not tampering): FNV-1a's step over 64-bit
// words (little-endian), then over the last bytes one by one; a word at a time, because
// the byte-wise FNV-1a took 150 ms of a 70 MB map's load.
std::uint64_t PayloadChecksum(const std::string& bytes);

// A map file's payload as an input stream, without copying it (cereal reads streams).
// tellg() works; other seeks do not.
class PayloadStream : public std::istream {
 public:
  explicit PayloadStream(std::string payload);
  const std::string& payload() const { return payload_; }

 private:
  class Buffer : public std::streambuf {
   public:
    void Set(const std::string& bytes);

   protected:
    pos_type seekoff(off_type offset, std::ios_base::seekdir direction,
                     std::ios_base::openmode mode) override;
  };
  std::string payload_;
  Buffer buffer_;
};

// Sums a payload handed over in pieces: the same value as PayloadChecksum of the pieces
// joined, without holding them.
class PayloadChecksummer {
 public:
  void Add(const char* bytes, std::size_t size);
  std::uint64_t Value() const;  // of everything added so far

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ull;
  char pending_[8] = {};  // the bytes of the last, incomplete word
  std::size_t pending_size_ = 0;
};

// Writes header and payload atomically (temporary file, then rename). Throws FileError
// naming the path.
void WriteMapFile(const std::string& path, const std::string& kind, std::uint32_t version,
                  const std::string& payload);

// A map file opened for reading, checked as it is opened without reading it whole: the
// header first (a foreign file is refused after its first kilobyte, whatever its size),
// then the payload's size against the file's, then the checksum in one pass over the
// payload in blocks. payload() then streams the payload from the file. Throws as
// ReadMapFile.
class MapFileReader {
 public:
  MapFileReader(const std::string& path, const std::string& kind, std::uint32_t version,
                std::uint32_t oldest_version = 0);
  std::uint32_t version() const { return version_; }
  std::uint64_t payload_size() const { return payload_size_; }
  // The payload from its first byte, read forward once; tellg() counts from the file's
  // start.
  std::istream& payload() { return *file_; }

 private:
  std::unique_ptr<char[]> buffer_;  // the stream's, larger than the default for cereal's blocks
  std::unique_ptr<std::ifstream> file_;
  std::uint32_t version_ = 0;
  std::uint64_t payload_size_ = 0;
};

// The payload of a map file of this kind and of a version from oldest_version (0: version
// alone) to version; the file's version goes to *read_version when given. Throws
// MapFileError naming the path and what is wrong: not a map file, another kind, a version
// outside that range, truncated (bytes present and expected), damaged (checksum);
// FileError when it cannot be read.
std::string ReadMapFile(const std::string& path, const std::string& kind, std::uint32_t version,
                        std::uint32_t oldest_version = 0, std::uint32_t* read_version = nullptr);

}  // namespace ocg
