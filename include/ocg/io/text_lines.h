#pragma once
// Line-oriented parsing shared by the dataset readers: every error names file and line.

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace ocg {

class ParseError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Calls handle(line_number, fields) for every line that is not blank and does not start
// with '#'. Fields are split on whitespace, or on commas when comma_separated.
// Throws FileError when the file cannot be read.
void ForEachDataLine(const std::string& path, bool comma_separated,
                     const std::function<void(int, const std::vector<std::string>&)>& handle);

// Strict number parsing: the whole field must be a finite number. On failure, throws
// ParseError "path:line: <what> must be a number, got '<field>'".
double ParseNumberField(const std::string& field, const std::string& what, const std::string& path,
                        int line);
long long ParseIntegerField(const std::string& field, const std::string& what,
                            const std::string& path, int line);
[[noreturn]] void ThrowParseError(const std::string& path, int line, const std::string& message);

}  // namespace ocg
