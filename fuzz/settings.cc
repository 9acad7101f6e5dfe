// Settings files, both dialects: our YAML and ORB-SLAM2's OpenCV-YAML ("%YAML:1.0"),
// through LoadSettings as the tools call it (every module's keys read and checked).
// Documented errors: SettingsError.
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "ocg/app/settings.h"
#include "ocg/core/settings_file.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  ocg::fuzz::SilenceLogging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = ocg::fuzz::WriteInput("settings.yaml", data, size);
  try {
    ocg::LoadSettings(path);
  } catch (const ocg::SettingsError&) {
  }
  return 0;
}
