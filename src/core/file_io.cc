#include "ocg/core/file_io.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace ocg {

void RequireRegularFile(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (status.type() == fs::file_type::regular) return;
  std::string what;
  switch (status.type()) {
    case fs::file_type::not_found:
      what = "does not exist";
      break;
    case fs::file_type::directory:
      what = "is a directory, not a file";
      break;
    case fs::file_type::fifo:
      what = "is a named pipe (FIFO), not a file";
      break;
    case fs::file_type::socket:
      what = "is a socket, not a file";
      break;
    case fs::file_type::block:
    case fs::file_type::character:
      what = "is a device, not a file";
      break;
    default:
      what = error ? "cannot be examined: " + error.message() : "is not a regular file";
  }
  throw FileError("cannot read '" + path + "': it " + what);
}

std::string ReadTextFile(const std::string& path) {
  // A directory opens as a stream that reads nothing: it would pass as an empty file.
  RequireRegularFile(path);
  std::ifstream stream(path, std::ios::binary);
  if (!stream) throw FileError("cannot open '" + path + "': " + std::strerror(errno));
  std::ostringstream buffer;
  buffer << stream.rdbuf();
  if (stream.bad()) throw FileError("error while reading '" + path + "'");
  return buffer.str();
}

void EnsureDirectory(const std::string& path) {
  if (path.empty()) return;
  std::error_code error;
  std::filesystem::create_directories(path, error);
  if (error) throw FileError("cannot create directory '" + path + "': " + error.message());
}

void WriteFileAtomically(const std::string& path, const std::string& content) {
  const std::filesystem::path target(path);
  if (target.has_parent_path()) EnsureDirectory(target.parent_path().string());
  const std::string temporary = path + ".tmp." + std::to_string(::getpid());
  {
    std::FILE* file = std::fopen(temporary.c_str(), "wb");
    if (file == nullptr) {
      throw FileError("cannot write '" + temporary + "': " + std::strerror(errno));
    }
    const size_t written = std::fwrite(content.data(), 1, content.size(), file);
    const bool flushed = std::fflush(file) == 0 && ::fsync(::fileno(file)) == 0;
    const bool closed = std::fclose(file) == 0;
    if (written != content.size() || !flushed || !closed) {
      std::remove(temporary.c_str());
      throw FileError("cannot write '" + path + "': " + std::strerror(errno));
    }
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(temporary.c_str());
    throw FileError("cannot replace '" + path + "': " + reason);
  }
}

void WriteFile(const std::string& path, const std::string& content) {
  std::ofstream stream(path, std::ios::binary | std::ios::trunc);
  if (!stream) throw FileError("cannot write '" + path + "': " + std::strerror(errno));
  stream.write(content.data(), static_cast<std::streamsize>(content.size()));
  stream.close();
  if (!stream) throw FileError("error while writing '" + path + "'");
}

void CheckWritableFolder(const std::string& path) {
  std::error_code error;
  std::filesystem::create_directories(path, error);
  if (error) {
    throw FileError("cannot create the output folder '" + path + "': " + error.message());
  }
  const std::string probe =
      (std::filesystem::path(path) / (".write_test." + std::to_string(::getpid()))).string();
  std::FILE* file = std::fopen(probe.c_str(), "wb");
  if (file == nullptr) {
    throw FileError("the output folder '" + path + "' is not writable: " + std::strerror(errno));
  }
  const bool written = std::fputc('x', file) != EOF && std::fflush(file) == 0;
  const int write_errno = errno;
  std::fclose(file);
  std::remove(probe.c_str());
  if (!written) {
    throw FileError("the output folder '" + path +
                    "' is not writable: " + std::strerror(write_errno));
  }
}

std::string FileLocation(const std::string& path, int line) {
  return path + ":" + std::to_string(line);
}

}  // namespace ocg
