// TUM trajectories ("timestamp tx ty tz qx qy qz qw"), as ocg_eval and the ground truth
// of a TUM sequence are read. Documented errors: ParseError, FileError.
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "ocg/core/file_io.h"
#include "ocg/io/text_lines.h"
#include "ocg/io/trajectory.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  ocg::fuzz::SilenceLogging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = ocg::fuzz::WriteInput("trajectory.txt", data, size);
  try {
    ocg::ReadTumTrajectory(path);
  } catch (const ocg::ParseError&) {
  } catch (const ocg::FileError&) {
  }
  return 0;
}
