#include "fuzz_input.h"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <system_error>

namespace ocg::fuzz {
namespace {

namespace fs = std::filesystem;

std::string MakeScratchDir() {
  const fs::path base = fs::temp_directory_path();
  std::string pattern = (base / "ocg_fuzz_XXXXXX").string();
  if (mkdtemp(pattern.data()) == nullptr) {
    throw std::runtime_error("cannot make a scratch folder under " + base.string());
  }
  return pattern;
}

void RemoveScratchDir() {
  std::error_code ignored;
  fs::remove_all(ScratchDir(), ignored);
}

}  // namespace

const std::string& ScratchDir() {
  // Never destroyed: RemoveScratchDir runs at exit, after static objects are gone.
  static const std::string* const dir = [] {
    const std::string* made = new std::string(MakeScratchDir());
    std::atexit(RemoveScratchDir);
    return made;
  }();
  return *dir;
}

std::string WriteInput(const std::string& relative_path, const std::uint8_t* data,
                       std::size_t size) {
  const fs::path path = fs::path(ScratchDir()) / relative_path;
  fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  out.close();
  if (!out) throw std::runtime_error("cannot write the fuzz input to " + path.string());
  return path.string();
}

std::string WriteInput(const std::string& relative_path, const std::string& text) {
  return WriteInput(relative_path, reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
}

void SilenceLogging() { spdlog::set_level(spdlog::level::off); }

}  // namespace ocg::fuzz
