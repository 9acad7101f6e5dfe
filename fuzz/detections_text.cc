// EAO-SLAM / YOLO detection text files ("class_id x y w h confidence" per line), strict
// and --lenient. The first byte chooses the mode, the rest is the file.
// Documented errors: ParseError (strict only), FileError.
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "ocg/core/file_io.h"
#include "ocg/io/detections.h"
#include "ocg/io/text_lines.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  ocg::fuzz::SilenceLogging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  ocg::DetectionReadOptions options;
  options.lenient = (data[0] & 1) != 0;
  const std::string path =
      ocg::fuzz::WriteInput("detections/1305031102.175304.txt", data + 1, size - 1);
  try {
    ocg::ReadEaoDetectionFile(path, options);
  } catch (const ocg::ParseError&) {
    if (options.lenient) throw;  // lenient mode skips bad lines instead
  } catch (const ocg::FileError&) {
  }
  return 0;
}
