#pragma once
// File helpers used at the boundaries: every error names the file.

#include <stdexcept>
#include <string>

namespace ocg {

class FileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws FileError naming the path and saying what it is when it is not a regular file
// (missing, a directory, a FIFO, a device, ...); symbolic links are followed.
void RequireRegularFile(const std::string& path);

// Whole file as text. Throws FileError naming the path when it is not a regular file
// (RequireRegularFile) or cannot be read.
std::string ReadTextFile(const std::string& path);

// Writes content to a temporary file beside path, then renames it over path, so readers
// never see a half-written file and a failure leaves any previous file intact.
// Creates missing parent directories. Throws FileError naming the path.
void WriteFileAtomically(const std::string& path, const std::string& content);

// Writes content to path directly (no temporary file, no fsync): for files inside a
// folder that is itself made atomically (built under another name, then renamed).
// Throws FileError naming the path.
void WriteFile(const std::string& path, const std::string& content);

// Creates the directory and its parents if missing. Throws FileError naming it.
void EnsureDirectory(const std::string& path);

// For an output folder, before any work: creates it if missing, then creates and removes
// a temporary file in it, so an unwritable folder fails at start, not after a run.
// Throws FileError naming the folder and the reason.
void CheckWritableFolder(const std::string& path);

// "path:line: message", the form editors and terminals turn into links.
std::string FileLocation(const std::string& path, int line);

}  // namespace ocg
