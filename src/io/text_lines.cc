#include "ocg/io/text_lines.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "ocg/core/file_io.h"

namespace ocg {

void ThrowParseError(const std::string& path, int line, const std::string& message) {
  throw ParseError(FileLocation(path, line) + ": " + message);
}

void ForEachDataLine(const std::string& path, bool comma_separated,
                     const std::function<void(int, const std::vector<std::string>&)>& handle) {
  // Line by line: memory stays that of the longest line, whatever the file's size. A FIFO
  // or a directory would block or read as empty: named instead.
  RequireRegularFile(path);
  std::ifstream input(path, std::ios::binary);
  if (!input) throw FileError("cannot open '" + path + "': " + std::strerror(errno));
  std::string line;
  std::vector<std::string> fields;
  for (int number = 1; std::getline(input, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();  // files from Windows tools
    const size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    if (comma_separated) {
      for (char& c : line) {
        if (c == ',') c = ' ';
      }
    }
    fields.clear();
    std::istringstream words(line);
    for (std::string word; words >> word;) fields.push_back(word);
    handle(number, fields);
  }
  if (input.bad()) throw FileError("error while reading '" + path + "'");
}

double ParseNumberField(const std::string& field, const std::string& what, const std::string& path,
                        int line) {
  errno = 0;
  char* end = nullptr;
  const double value = std::strtod(field.c_str(), &end);
  if (field.empty() || errno != 0 || end != field.c_str() + field.size() || !std::isfinite(value)) {
    ThrowParseError(path, line, what + " must be a number, got '" + field + "'");
  }
  return value;
}

long long ParseIntegerField(const std::string& field, const std::string& what,
                            const std::string& path, int line) {
  errno = 0;
  char* end = nullptr;
  const long long value = std::strtoll(field.c_str(), &end, 10);
  if (field.empty() || errno != 0 || end != field.c_str() + field.size()) {
    ThrowParseError(path, line, what + " must be an integer, got '" + field + "'");
  }
  return value;
}

}  // namespace ocg
