#include "ate_plot.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "ocg/core/file_io.h"

extern char** environ;

namespace ocg::tools {
namespace {

namespace fs = std::filesystem;

nlohmann::json Positions(const std::vector<StampedPose>& poses, const Sim3& transform) {
  nlohmann::json rows = nlohmann::json::array();
  for (const StampedPose& pose : poses) {
    const Eigen::Vector3d p = transform * pose.T_wc.translation();
    rows.push_back({pose.timestamp, p.x(), p.y(), p.z()});
  }
  return rows;
}

// The interpreter with matplotlib: $OCG_PYTHON, else the one CMake found (Debian's).
std::string PythonInterpreter() {
  if (const char* given = std::getenv("OCG_PYTHON"); given != nullptr && *given != '\0') {
    return given;
  }
  return OCG_PYTHON_EXECUTABLE;
}

fs::path PlotScript() {
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  const fs::path script = (error ? fs::path(".") : self.parent_path()) / "ocg_plot_ate.py";
  if (!fs::is_regular_file(script)) {
    throw std::runtime_error("--plot: the plotting script " + script.string() +
                             " is missing (it is built and installed beside ocg_eval)");
  }
  return script;
}

int Run(const std::vector<std::string>& command) {
  std::vector<char*> argv;
  for (const std::string& argument : command) argv.push_back(const_cast<char*>(argument.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawnp(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0) return 127;
  int status = 0;
  if (waitpid(pid, &status, 0) < 0 || !WIFEXITED(status)) return 128;
  return WEXITSTATUS(status);
}

}  // namespace

void PlotAte(const std::vector<StampedPose>& reference, const std::vector<StampedPose>& estimate,
             const AteResult& result, const std::string& alignment, const std::string& png_path) {
  nlohmann::json pairs = nlohmann::json::array();
  for (const PoseAssociation& pair : result.pairs) {
    const Eigen::Vector3d truth = reference[pair.reference_index].T_wc.translation();
    const Eigen::Vector3d aligned =
        result.reference_from_estimate * estimate[pair.estimate_index].T_wc.translation();
    const Eigen::Vector3d error = aligned - truth;
    pairs.push_back(
        {estimate[pair.estimate_index].timestamp, error.x(), error.y(), error.z(), error.norm()});
  }
  const nlohmann::json data = {{"alignment", alignment},
                               {"scale", result.reference_from_estimate.scale()},
                               {"rmse", result.translation.rmse},
                               {"count", result.pairs.size()},
                               {"reference", Positions(reference, Sim3())},
                               {"estimate", Positions(estimate, result.reference_from_estimate)},
                               {"errors", pairs}};
  const fs::path script = PlotScript();
  const fs::path data_path =
      fs::temp_directory_path() / ("ocg_eval_plot_" + std::to_string(::getpid()) + ".json");
  WriteFileAtomically(data_path.string(), data.dump());
  const std::string python = PythonInterpreter();
  const int status = Run({python, script.string(), data_path.string(), png_path});
  std::error_code ignored;
  fs::remove(data_path, ignored);
  if (status == 127) {
    throw std::runtime_error("--plot: cannot run the Python interpreter '" + python +
                             "' (set OCG_PYTHON to a python3 with matplotlib)");
  }
  if (status != 0) {
    throw std::runtime_error("--plot: " + python + " " + script.string() + " failed (exit " +
                             std::to_string(status) + ", its message is above); no plot written");
  }
}

}  // namespace ocg::tools
