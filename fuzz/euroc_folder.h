#pragma once
// EuRoC MAV folders for the fuzz targets: a small valid folder under the scratch folder,
// one of whose files is replaced by the input before ReadEurocSequence reads it.
#include <cstddef>
#include <cstdint>
#include <string>

namespace ocg::fuzz {

// Writes the valid folder, then the input as relative_file (e.g. "mav0/cam0/data.csv"),
// and reads it. Documented errors (ParseError, FileError, SettingsError) are swallowed;
// anything else propagates to the fuzzer as a finding.
void ReadEurocWithInput(const std::string& relative_file, const std::uint8_t* data,
                        std::size_t size);

}  // namespace ocg::fuzz
