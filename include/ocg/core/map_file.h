#pragma once
// The envelope of map files (docs/sessions.md): a short text header of our own, then a
// binary payload that the modules fill with cereal archives. The header says what the
// file is before anything is parsed, so a foreign file, a file of another kind or
// version, a truncated or a damaged one is refused with a message naming the file:
//
//   OCG-SLAM map file\n
//   kind <kind>\n
//   version <version>\n
//   payload <bytes> fnv1a64 <16 hex digits>\n
//   <payload>

#include <cstdint>
#include <string>

#include "ocg/core/file_io.h"

namespace ocg {

class MapFileError : public FileError {
 public:
  using FileError::FileError;
};

inline constexpr const char* kMapFileMagic = "OCG-SLAM map file";

// FNV-1a, 64 bits: the payload's checksum (catches damage, not tampering).
std::uint64_t Fnv1a64(const std::string& bytes);

// Writes header and payload atomically (temporary file, then rename). Throws FileError
// naming the path.
void WriteMapFile(const std::string& path, const std::string& kind, std::uint32_t version,
                  const std::string& payload);

// The payload of a map file of this kind and version. Throws MapFileError naming the path
// and what is wrong: not a map file, another kind, another version, truncated (bytes
// present and expected), damaged (checksum); FileError when it cannot be read.
std::string ReadMapFile(const std::string& path, const std::string& kind, std::uint32_t version);

}  // namespace ocg
