#pragma once
// Scene files (YAML), documented in docs/synthetic.md.

#include <string>
#include <vector>

#include "ocg/sim/presets.h"
#include "ocg/sim/scene.h"

namespace ocg::sim {

struct SceneFile {
  Scene scene;
  std::vector<PlannedMove> moves;  // "moves:" entries, scheduled by the generator
};

// Throws SettingsError naming the file and the field when the file is wrong.
SceneFile LoadSceneFile(const std::string& path);
SceneFile ParseSceneYaml(const std::string& text, const std::string& name);
// The scene with every change as an explicit history entry (no "moves:").
std::string SceneToYaml(const Scene& scene);

}  // namespace ocg::sim
