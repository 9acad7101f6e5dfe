// The settings file parser alone (ocg::core): both dialects, every key read as every type
// the modules ask for. The suite's fuzz_smoke runs this one instead of `settings`, whose
// build needs the whole library; tools/fuzz.sh runs both.
// Documented errors: SettingsError.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_input.h"
#include "ocg/core/settings_file.h"

namespace {

// Each Read either fills the value or throws SettingsError naming the key; both are fine.
template <typename T>
void TryRead(const ocg::SettingsFile& file, const std::string& key) {
  T value{};
  try {
    file.Read(key, &value);
  } catch (const ocg::SettingsError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  ocg::fuzz::SilenceLogging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const ocg::SettingsFile file = ocg::SettingsFile::Parse(text, "fuzz.yaml");
    file.UnreadKeys();
    for (const std::string& key : file.KeysUnder("")) {
      TryRead<double>(file, key);
      TryRead<int>(file, key);
      TryRead<std::uint64_t>(file, key);
      TryRead<bool>(file, key);
      TryRead<std::string>(file, key);
      TryRead<std::vector<double>>(file, key);
      file.LineOf(key);
      file.Describe(key, "checked");
    }
  } catch (const ocg::SettingsError&) {
  }
  return 0;
}
