// EuRoC MAV folders: the image list mav0/cam0/data.csv ("timestamp [ns],filename")
// is the input, the other files of the folder are valid; read by ReadEurocSequence.
#include <cstddef>
#include <cstdint>

#include "euroc_folder.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  ocg::fuzz::SilenceLogging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ocg::fuzz::ReadEurocWithInput("mav0/cam0/data.csv", data, size);
  return 0;
}
