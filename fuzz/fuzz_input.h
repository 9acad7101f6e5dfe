#pragma once
// What every fuzz target shares: the input as a file for readers that only take paths,
// and quiet logging so that warnings about bad input do not slow the fuzzer down.
#include <cstddef>
#include <cstdint>
#include <string>

namespace ocg::fuzz {

// A folder of its own under $TMPDIR for this process, removed at exit.
const std::string& ScratchDir();

// Writes the input to ScratchDir()/relative_path (parents created) and returns the path.
std::string WriteInput(const std::string& relative_path, const std::uint8_t* data,
                       std::size_t size);
std::string WriteInput(const std::string& relative_path, const std::string& text);

// Turns spdlog off: the readers' warnings are expected for fuzzed input.
void SilenceLogging();

}  // namespace ocg::fuzz
