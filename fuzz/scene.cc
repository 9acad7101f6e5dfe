// Scene files of the generator (scene.yaml, docs/synthetic.md), through LoadSceneFile.
// Documented errors: SettingsError.
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "ocg/core/settings_file.h"
#include "ocg/sim/scene_io.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  ocg::fuzz::SilenceLogging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = ocg::fuzz::WriteInput("scene.yaml", data, size);
  try {
    ocg::sim::LoadSceneFile(path);
  } catch (const ocg::SettingsError&) {
  }
  return 0;
}
