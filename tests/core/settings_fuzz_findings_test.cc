// Settings files the settings fuzz target (fuzz/settings.cc) showed mishandled: a YAML
// complex key ("? k2: ...") made yaml-cpp's TypedBadConversion escape SettingsFile::Parse.
#include <gtest/gtest.h>

#include <string>

#include "ocg/core/settings_file.h"

namespace ocg {
namespace {

TEST(SettingsFuzzFindings, ComplexKeysAreASettingsErrorNamingFileAndLine) {
  for (const char* text :
       {"Camera:\n  fx: 500\n? k2: -0.95\n", "? [a, b]\n: 1\n", "Camera:\n  ? {fx: 1}\n  : 2\n"}) {
    try {
      SettingsFile::Parse(text, "camera.yaml");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const SettingsError& error) {
      EXPECT_EQ(std::string(error.what()).rfind("camera.yaml:", 0), 0u) << error.what();
      EXPECT_NE(std::string(error.what()).find("plain names"), std::string::npos) << error.what();
    }
  }
  EXPECT_TRUE(SettingsFile::Parse("Camera:\n  fx: 500\n", "camera.yaml").Has("Camera.fx"));
}

}  // namespace
}  // namespace ocg
