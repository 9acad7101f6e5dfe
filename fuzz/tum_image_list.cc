// TUM RGB-D image lists (rgb.txt: "timestamp filename" lines), through ReadTumSequence
// on a folder holding the input as rgb.txt. Documented errors: ParseError, FileError.
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "fuzz_input.h"
#include "ocg/core/file_io.h"
#include "ocg/io/sequence.h"
#include "ocg/io/text_lines.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  ocg::fuzz::SilenceLogging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = ocg::fuzz::WriteInput("tum/rgb.txt", data, size);
  try {
    ocg::ReadTumSequence(std::filesystem::path(path).parent_path().string());
  } catch (const ocg::ParseError&) {
  } catch (const ocg::FileError&) {
  }
  return 0;
}
