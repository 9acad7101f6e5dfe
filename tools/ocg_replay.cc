// ocg_replay: run the Object Covisibility Graph on a recorded stream of keyframe
// observations from any object SLAM system (SPEC 3.1, docs/ocg.md).

#include <spdlog/spdlog.h>

#include <filesystem>
#include <iostream>
#include <sstream>

#include "cli_common.h"
#include "ocg/app/settings.h"
#include "ocg/core/file_io.h"
#include "ocg/core/logging.h"
#include "ocg/ocg/manager.h"
#include "ocg/ocg/replay_format.h"

int main(int argc, char** argv) {
  CLI::App app{
      "ocg_replay: run the OCG change detection on a JSON-lines stream of keyframe "
      "observations; writes states.jsonl, changes.json and ocg.json",
      "ocg_replay"};
  std::string log_level, input, output, settings_path, mode;
  ocg::tools::AddLogLevelOption(app, &log_level);
  app.add_option("--input", input, "observations, one JSON object per line")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--out", output, "output folder (created if missing)")->required();
  app.add_option("--settings", settings_path, "settings file (OCG.* keys)")
      ->check(CLI::ExistingFile);
  app.add_flag_callback(
      "--fields",
      [] {
        std::cout << ocg::ObservationFieldsHelp();
        throw CLI::Success();
      },
      "print the fields of an input line (name, type, unit, optional, meaning) and exit");
  app.add_option("--mode", mode,
                 "overrides OCG.mode: paper, improved, or fallback/in_image/guard joined with '+'");

  return ocg::tools::RunTool(app, argc, argv, log_level, [&] {
    ocg::Settings settings;
    if (!settings_path.empty()) settings = ocg::LoadSettings(settings_path).settings;
    if (!mode.empty()) {
      settings.ocg.mode = mode;
      settings.Check();
    }
    // Parse everything first: a malformed line fails before any output is written.
    std::vector<ocg::KeyframeObservation> observations;
    {
      std::istringstream lines(ocg::ReadTextFile(input));
      std::string line;
      for (int number = 1; std::getline(lines, line); ++number) {
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
        try {
          observations.push_back(ocg::ParseObservationJson(line));
        } catch (const ocg::ReplayFormatError& error) {
          throw ocg::ReplayFormatError(ocg::FileLocation(input, number) + ": " + error.what());
        }
      }
    }
    ocg::CheckWritableFolder(output);
    ocg::OcgManager manager(settings.ocg, /*sequential=*/true);
    std::vector<ocg::RemovalEvent> removed;  // this keyframe's
    manager.SetRemovalCallback(
        [&](const ocg::KeyframeResult& result) { removed = result.removed; });
    std::string states;
    ocg::ProgressLine progress("keyframes", observations.size());
    for (std::size_t index = 0; index < observations.size(); ++index) {
      removed.clear();
      manager.Submit(observations[index]);
      states +=
          ocg::StatesLineJson(observations[index].keyframe_id, manager.Snapshot(), removed) + "\n";
      for (const ocg::RemovalEvent& event : removed) {
        spdlog::info("keyframe {}: object {} removed (doubt {})", event.keyframe_id,
                     event.object_id, event.doubt);
      }
      progress.Update(index + 1);
    }
    progress.Finish();
    namespace fs = std::filesystem;
    ocg::WriteFileAtomically((fs::path(output) / "states.jsonl").string(), states);
    ocg::WriteFileAtomically((fs::path(output) / "changes.json").string(),
                             ocg::ChangeLogJson(manager.Removals()));
    ocg::WriteFileAtomically((fs::path(output) / "ocg.json").string(), manager.GraphJson());
    std::cout << "ocg_replay: " << observations.size() << " keyframes, mode " << settings.ocg.mode
              << ", removed " << manager.Removals().size() << " object(s), "
              << manager.Snapshot().size() << " left\n"
              << "  " << (fs::path(output) / "states.jsonl").string() << "\n"
              << "  " << (fs::path(output) / "changes.json").string() << "\n"
              << "  " << (fs::path(output) / "ocg.json").string() << "\n";
  });
}
