#pragma once
// `ocg_slam settings`: check a settings file as a run reads it, change keys, write the result
// (docs/settings.md). Tools that make settings files (the batch, docs/batch.md) go through it,
// so that they read ORB-SLAM's OpenCV-YAML files and know the keys exactly as a run does.

#include <CLI/CLI.hpp>
#include <iostream>
#include <string>
#include <vector>

#include "ocg/app/settings.h"
#include "ocg/core/file_io.h"
#include "ocg/core/settings_file.h"
#include "ocg/ocg/judgement_terms.h"
#include "ocg/ocg/replay_format.h"

namespace ocg::tools {

struct SettingsCommand {
  CLI::App* app = nullptr;
  std::string file;                      // "" for the defaults
  std::vector<std::string> assignments;  // KEY=VALUE
  std::string write;
  bool strict = false;
  bool need_camera = false;
  bool list_keys = false;
  bool markdown = false;
  std::string image;  // an image of the sequence the settings are for, or ""
};

inline void AddSettingsCommand(CLI::App& parent, SettingsCommand* command) {
  command->app = parent.add_subcommand(
      "settings",
      "check a settings file as a run reads it (ours, ORB-SLAM2's or ORB-SLAM3's), change keys "
      "with --set, write the result with --write");
  CLI::App& app = *command->app;
  app.add_option("file", command->file, "settings file (default: none, the defaults alone)")
      ->check(CLI::ExistingFile);
  app.add_option("--set", command->assignments,
                 "KEY=VALUE over the file's value (repeatable); VALUE in YAML: 0.5, false, "
                 "[0, -1, 0], 'a b'")
      ->allow_extra_args(false);
  app.add_flag("--strict", command->strict,
               "a key no module reads is an error (with the key it most likely meant), not a "
               "warning");
  app.add_flag("--need-camera", command->need_camera,
               "the camera's intrinsics must be given, as for ocg_slam run");
  app.add_option("--image", command->image,
                 "an image of the sequence these settings are for: its size must be the "
                 "camera's")
      ->check(CLI::ExistingFile);
  app.add_option("--write", command->write,
                 "write the checked settings here, flat (one 'key: value' per line, --set keys "
                 "included)");
  app.add_flag("--list-keys", command->list_keys, "print every key the modules read, and exit");
  app.add_flag("--markdown", command->markdown,
               "print every module's keys as the tables of docs/settings.md (key, default, "
               "values taken, meaning), and the OCG's modes and observation fields as the "
               "tables of docs/ocg.md, and exit");
}

inline void RunSettingsCommand(const SettingsCommand& command) {
  if (command.list_keys) {
    for (const std::string& key : KnownSettingsKeys()) std::cout << key << "\n";
    return;
  }
  if (command.markdown) {
    for (const SettingsSection& section : DescribeSettings()) {
      std::cout << SettingsTableMarkdown(section) << "\n";
    }
    // The OCG's modes and observation fields (docs/ocg.md), made from their lists too.
    std::cout << JudgementTermsMarkdown() << "\n" << ObservationFieldsMarkdown() << "\n";
    return;
  }
  SettingsFile file = command.file.empty() ? SettingsFile::Parse("", "(defaults)")
                                           : SettingsFile::Load(command.file);
  for (const std::string& assignment : command.assignments) {
    const std::size_t equals = assignment.find('=');
    if (equals == std::string::npos) {
      throw SettingsError("--set '" + assignment + "': expected KEY=VALUE, e.g. OCG.tau_doubt=40");
    }
    const std::string key = assignment.substr(0, equals);
    file.Set(key, assignment.substr(equals + 1), "--set " + key);
  }
  const LoadedSettings loaded =
      ReadSettingsFile(file, command.need_camera ? CameraNeed::kIntrinsics : CameraNeed::kNone,
                       command.strict ? UnknownKeys::kError : UnknownKeys::kWarn);
  if (!command.image.empty()) CheckCameraFitsImage(loaded, command.image);
  if (!command.write.empty()) {
    std::string comment = "Made by ocg_slam settings from " +
                          (command.file.empty() ? std::string("the defaults") : command.file);
    for (const std::string& assignment : command.assignments) comment += " --set " + assignment;
    WriteFileAtomically(command.write, file.ToFlatYaml(comment));
  }
  std::cout << (command.file.empty() ? "(defaults)" : command.file) << ": ok"
            << (loaded.warnings.empty()
                    ? ""
                    : ", " + std::to_string(loaded.warnings.size()) + " unknown key(s) ignored")
            << (command.write.empty() ? "" : "; wrote " + command.write) << "\n";
}

}  // namespace ocg::tools
