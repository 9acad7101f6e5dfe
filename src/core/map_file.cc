#include "ocg/core/map_file.h"

#include <cinttypes>
#include <cstdio>
#include <sstream>

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

std::string Printable(const std::string& text) {
  std::string shown;
  for (const char c : text.substr(0, 40)) shown += (c >= 32 && c < 127) ? c : '?';
  return shown;
}

}  // namespace

std::uint64_t Fnv1a64(const std::string& bytes) {
  std::uint64_t hash = 0xcbf29ce484222325ull;
  for (const char c : bytes) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 0x100000001b3ull;
  }
  return hash;
}

void WriteMapFile(const std::string& path, const std::string& kind, std::uint32_t version,
                  const std::string& payload) {
  char checksum[17];
  std::snprintf(checksum, sizeof checksum, "%016" PRIx64, Fnv1a64(payload));
  std::string content = std::string(kMapFileMagic) + "\nkind " + kind + "\nversion " +
                        std::to_string(version) + "\npayload " + std::to_string(payload.size()) +
                        " fnv1a64 " + checksum + "\n";
  content += payload;
  WriteFileAtomically(path, content);
}

std::string ReadMapFile(const std::string& path, const std::string& kind, std::uint32_t version) {
  const std::string content = ReadTextFile(path);
  const std::string where = "map file '" + path + "': ";
  std::size_t position = 0;
  std::string line;
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
  if (file_version != version) {
    throw MapFileError(where + "format version " + std::to_string(file_version) +
                       ", this build reads version " + std::to_string(version) + " only (" +
                       (file_version > version ? "written by a newer build: update OCG-SLAM"
                                               : "written by an older build: remake the map") +
                       ")");
  }
  unsigned long long size = 0;
  std::uint64_t checksum = 0;
  if (!NextLine(content, &position, &line) ||
      std::sscanf(line.c_str(), "payload %llu fnv1a64 %" SCNx64, &size, &checksum) != 2) {
    throw MapFileError(where +
                       "damaged header: line 4 should be 'payload <bytes> fnv1a64 <checksum>'");
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
  std::string payload = content.substr(position);
  if (Fnv1a64(payload) != checksum) {
    throw MapFileError(where + "damaged: the payload's checksum does not match its header");
  }
  return payload;
}

}  // namespace ocg
