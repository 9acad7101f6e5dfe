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
#include <istream>
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

// Writes header and payload atomically (temporary file, then rename). Throws FileError
// naming the path.
void WriteMapFile(const std::string& path, const std::string& kind, std::uint32_t version,
                  const std::string& payload);

// The payload of a map file of this kind and of a version from oldest_version (0: version
// alone) to version; the file's version goes to *read_version when given. Throws
// MapFileError naming the path and what is wrong: not a map file, another kind, a version
// outside that range, truncated (bytes present and expected), damaged (checksum);
// FileError when it cannot be read.
std::string ReadMapFile(const std::string& path, const std::string& kind, std::uint32_t version,
                        std::uint32_t oldest_version = 0, std::uint32_t* read_version = nullptr);

}  // namespace ocg
