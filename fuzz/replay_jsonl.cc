// ocg_replay's input: one keyframe observation per JSON line, each parsed by
// ParseObservationJson and then run through the OCG as ocg_replay does, so that values
// the parser lets through (ids, sizes, rates) are also exercised by the graph.
// Documented errors: ReplayFormatError.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "fuzz_input.h"
#include "ocg/ocg/manager.h"
#include "ocg/ocg/options.h"
#include "ocg/ocg/replay_format.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  ocg::fuzz::SilenceLogging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream lines(std::string(reinterpret_cast<const char*>(data), size));
  std::vector<ocg::KeyframeObservation> observations;
  try {
    for (std::string line; std::getline(lines, line);) {
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      observations.push_back(ocg::ParseObservationJson(line));
    }
  } catch (const ocg::ReplayFormatError&) {
    return 0;
  }
  ocg::OcgManager manager(ocg::OcgOptions{}, /*sequential=*/true);
  for (const ocg::KeyframeObservation& observation : observations) {
    manager.Submit(observation);
    ocg::StatesLineJson(observation.keyframe_id, manager.Snapshot(), {});
  }
  ocg::ChangeLogJson(manager.Removals());
  return 0;
}
