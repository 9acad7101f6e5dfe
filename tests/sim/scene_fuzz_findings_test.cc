// Scene files the scene fuzz target (fuzz/scene.cc) showed mishandled: a node of the wrong
// shape (a scalar or list where a map is expected) let yaml-cpp's BadSubscript or
// InvalidNode escape ParseSceneYaml and end the program; it is now a SettingsError.
#include <gtest/gtest.h>

#include <string>

#include "ocg/core/settings_file.h"
#include "ocg/sim/scene_io.h"

namespace ocg::sim {
namespace {

TEST(SceneFuzzFindings, NodesOfTheWrongShapeAreSettingsErrorsNamingTheFile) {
  const char* const cases[] = {
      "just a scalar\n",                                    // the fuzzer's input, reduced
      "- a\n- b\n",                                         // a list at the top level
      "name: x\ncamera: 5\n",                               // a scalar where a map is expected
      "camera: [1, 2]\n",                                   // a list where a map is expected
      "furniture: 3\n",                                     // a scalar where a list is expected
      "furniture: [5]\n",                                   // list items that are no maps
      "objects: [{size: [1, 1, 1], history: 3}]\n",         // history a scalar
      "objects: [{size: [1, 1, 1], history: [[0, 1]]}]\n",  // history items that are lists
      "moves: {a: 1}\n",                                    // a map where a list is expected
  };
  for (const char* text : cases) {
    try {
      ParseSceneYaml(text, "scene.yaml");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const SettingsError& error) {
      EXPECT_EQ(std::string(error.what()).rfind("scene.yaml", 0), 0u) << text << error.what();
    }
  }
}

}  // namespace
}  // namespace ocg::sim
