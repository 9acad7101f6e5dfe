// JSON detection lists ([{"file_name", "detections": [{"category_id", "detection_score",
// "bbox"}]}]). Documented errors: ParseError, FileError.
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
  const std::string path = ocg::fuzz::WriteInput("detections.json", data, size);
  try {
    ocg::ReadJsonDetections(path);
  } catch (const ocg::ParseError&) {
  } catch (const ocg::FileError&) {
  }
  return 0;
}
