#include <gtest/gtest.h>

#include <filesystem>

#include "ocg/app/settings.h"
#include "ocg/core/settings_file.h"
#include "test_support.h"

namespace ocg {
namespace {

namespace fs = std::filesystem;

std::string ErrorOf(const std::string& text) {
  try {
    ParseSettings(text, "fixture.yaml");
  } catch (const SettingsError& error) {
    return error.what();
  }
  return "";
}

TEST(Settings, ReadsOrbSlam2SettingsFilesUnchanged) {
  const auto data = testing::SharedDataDir();
  if (!data) GTEST_SKIP() << testing::SharedDataSkipMessage();
  const std::map<std::string, double> expected_fx = {{"Monocular_TUM1.yaml", 517.306408},
                                                     {"Monocular_TUM2.yaml", 520.908620},
                                                     {"Monocular_TUM3.yaml", 535.4}};
  for (const auto& [name, fx] : expected_fx) {
    const std::string path = *data + "/orbslam2_settings/" + name;
    const LoadedSettings loaded = LoadSettings(path);
    EXPECT_DOUBLE_EQ(loaded.settings.camera.model.fx, fx) << name;
    EXPECT_EQ(loaded.settings.camera.model.width, 640);
    EXPECT_EQ(loaded.settings.orb.features, 1000);
    EXPECT_DOUBLE_EQ(loaded.settings.orb.scale_factor, 1.2);
    EXPECT_EQ(loaded.settings.orb.levels, 8);
    EXPECT_EQ(loaded.settings.orb.initial_fast_threshold, 20);
    EXPECT_EQ(loaded.settings.orb.minimum_fast_threshold, 7);
    EXPECT_TRUE(loaded.settings.camera.rgb);
    EXPECT_DOUBLE_EQ(loaded.settings.viewer.point_size, 2.0) << "'Viewer.PointSize:2' (no space)";
    EXPECT_DOUBLE_EQ(loaded.settings.viewer.viewpoint_f, 500.0);
    EXPECT_TRUE(loaded.warnings.empty()) << loaded.warnings.front();
  }
  const LoadedSettings tum1 = LoadSettings(*data + "/orbslam2_settings/Monocular_TUM1.yaml");
  EXPECT_DOUBLE_EQ(tum1.settings.camera.model.k3, 1.163314);
}

TEST(Settings, ShippedConfigsLoadWithoutWarnings) {
  for (const char* name : {"TUM1.yaml", "TUM2.yaml", "TUM3.yaml", "EuRoC.yaml"}) {
    const std::string path = testing::SourceDir() + "/config/" + name;
    ASSERT_TRUE(fs::exists(path)) << path;
    const LoadedSettings loaded = LoadSettings(path);
    EXPECT_TRUE(loaded.warnings.empty()) << name << ": " << loaded.warnings.front();
    EXPECT_GT(loaded.settings.camera.model.fx, 400) << name;
  }
  EXPECT_EQ(LoadSettings(testing::SourceDir() + "/config/EuRoC.yaml").settings.camera.model.width,
            752);
}

TEST(Settings, NestedAndDottedKeysAreTheSame) {
  const LoadedSettings nested =
      ParseSettings("OCG:\n  tau_doubt: 70\n  mode: improved\n", "a.yaml");
  const LoadedSettings dotted = ParseSettings("OCG.tau_doubt: 70\nOCG.mode: improved\n", "b.yaml");
  EXPECT_DOUBLE_EQ(nested.settings.ocg.tau_doubt, 70.0);
  EXPECT_DOUBLE_EQ(dotted.settings.ocg.tau_doubt, 70.0);
  EXPECT_EQ(nested.settings.ocg.mode, "improved");
  EXPECT_TRUE(nested.settings.ocg.modes().dropout_guard);
}

TEST(Settings, DefaultsMatchTheSpec) {
  const Settings settings;
  EXPECT_DOUBLE_EQ(settings.ocg.tau_observable, 0.2);
  EXPECT_DOUBLE_EQ(settings.ocg.tau_doubt, 50.0);
  EXPECT_EQ(settings.ocg.mode, "paper");
  EXPECT_EQ(settings.camera.model.width, 640);
  EXPECT_EQ(settings.camera.model.height, 480);
  EXPECT_NO_THROW(settings.Check());
}

TEST(Settings, UnknownKeyWarnsWithItsNameAndLine) {
  const LoadedSettings loaded = ParseSettings("Camera.fx: 500\nOCG.tau_dobut: 3\n", "typo.yaml");
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_NE(loaded.warnings[0].find("typo.yaml:2"), std::string::npos) << loaded.warnings[0];
  EXPECT_NE(loaded.warnings[0].find("OCG.tau_dobut"), std::string::npos);
}

TEST(Settings, WrongTypeNamesFileLineAndKey) {
  const std::string error = ErrorOf("Camera.fx: 500\nCamera.fy: fast\n");
  EXPECT_NE(error.find("fixture.yaml:2"), std::string::npos) << error;
  EXPECT_NE(error.find("Camera.fy"), std::string::npos) << error;
  EXPECT_NE(ErrorOf("ORBextractor.nFeatures: 1000.5\n").find("expected an integer"),
            std::string::npos);
  EXPECT_NE(ErrorOf("System.sequential: maybe\n").find("System.sequential"), std::string::npos);
  EXPECT_NE(ErrorOf("Camera.fx: [1, 2]\n").find("expected a single value"), std::string::npos);
}

TEST(Settings, ImpossibleValueNamesFileLineAndKey) {
  const std::string error = ErrorOf("Camera.fx: 500\nOCG.tau_observable: 1.5\n");
  EXPECT_NE(error.find("fixture.yaml:2"), std::string::npos) << error;
  EXPECT_NE(error.find("OCG.tau_observable"), std::string::npos) << error;
  EXPECT_NE(ErrorOf("OCG.mode: magic\n").find("unknown mode 'magic'"), std::string::npos);
  EXPECT_NE(ErrorOf("ORBextractor.minThFAST: 30\n").find("ORBextractor.minThFAST"),
            std::string::npos);
  EXPECT_NE(ErrorOf("Camera.width: 0\n").find("Camera.width"), std::string::npos);
}

TEST(Settings, MissingFileAndBrokenYamlNameTheFile) {
  try {
    LoadSettings("/nonexistent/settings.yaml");
    FAIL();
  } catch (const SettingsError& error) {
    EXPECT_NE(std::string(error.what()).find("/nonexistent/settings.yaml"), std::string::npos);
  }
  const std::string error = ErrorOf("Camera.fx: 500\nCamera: [unclosed\n");
  EXPECT_NE(error.find("fixture.yaml:"), std::string::npos) << error;
}

TEST(SettingsFile, TracksUnreadKeysInFileOrder) {
  const SettingsFile file = SettingsFile::Parse("%YAML:1.0\nb: 1\na:2\nc: [1, 2]\n", "x.yaml");
  double value = 0;
  EXPECT_TRUE(file.Read("a", &value));
  EXPECT_DOUBLE_EQ(value, 2.0);
  EXPECT_EQ(file.LineOf("c"), 4);
  EXPECT_EQ(file.UnreadKeys(), (std::vector<std::string>{"b", "c"}));
  std::vector<double> list;
  EXPECT_TRUE(file.Read("c", &list));
  EXPECT_EQ(list, (std::vector<double>{1, 2}));
  EXPECT_FALSE(file.Read("missing", &value));
}

}  // namespace
}  // namespace ocg
