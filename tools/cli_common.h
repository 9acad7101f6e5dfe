#pragma once
// Shared main() scaffolding for the command-line tools: --log-level, and errors reported
// as one clear line with exit code 1 instead of an uncaught exception.

#include <CLI/CLI.hpp>
#include <exception>
#include <functional>
#include <iostream>
#include <string>

#include "ocg/core/logging.h"

namespace ocg::tools {

inline void AddLogLevelOption(CLI::App& app, std::string* level) {
  app.add_option("--log-level", *level, "trace, debug, info, warn, error or off")
      ->default_val("info")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "off"}));
}

// Parses the command line and runs body; returns the process exit code.
inline int RunTool(CLI::App& app, int argc, char** argv, const std::string& log_level,
                   const std::function<void()>& body) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return app.exit(error);
  }
  try {
    ConfigureLogging(log_level);
    body();
    return 0;
  } catch (const std::exception& error) {
    std::cerr << app.get_name() << ": error: " << error.what() << "\n";
    return 1;
  }
}

}  // namespace ocg::tools
