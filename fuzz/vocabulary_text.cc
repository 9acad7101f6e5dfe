// Text vocabularies through Vocabulary::LoadOrbSlamText, the reader Vocabulary::Load
// calls for them. Documented errors: FileError
// (the header says std::runtime_error naming the file; every one thrown is a FileError).
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "ocg/core/file_io.h"
#include "ocg/features/vocabulary.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  ocg::fuzz::SilenceLogging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = ocg::fuzz::WriteInput("vocabulary", data, size);
  try {
    ocg::Vocabulary::LoadOrbSlamText(path);
  } catch (const ocg::FileError&) {
  }
  return 0;
}
