#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <set>
#include <sstream>
#include <type_traits>

#include "ocg/app/settings.h"
#include "ocg/core/file_io.h"
#include "ocg/core/option_fields.h"
#include "ocg/core/settings_file.h"
#include "test_support.h"

namespace ocg {
namespace {

namespace fs = std::filesystem;

// The error message of loading text as "fixture.yaml", or "" when it loads.
std::string ErrorOf(const std::string& text, CameraNeed need = CameraNeed::kNone) {
  try {
    ParseSettings(text, "fixture.yaml", need);
  } catch (const SettingsError& error) {
    return error.what();
  }
  return "";
}

// The published calibration of the TUM RGB-D freiburg1 RGB camera.
void ExpectTum1Calibration(const PinholeCamera& camera) {
  EXPECT_DOUBLE_EQ(camera.fx, 517.306408);
  EXPECT_DOUBLE_EQ(camera.fy, 516.469215);
  EXPECT_DOUBLE_EQ(camera.cx, 318.643040);
  EXPECT_DOUBLE_EQ(camera.cy, 255.313989);
  EXPECT_DOUBLE_EQ(camera.k1, 0.262383);
  EXPECT_DOUBLE_EQ(camera.k2, -0.953104);
  EXPECT_DOUBLE_EQ(camera.p1, -0.005358);
  EXPECT_DOUBLE_EQ(camera.p2, 0.002628);
  EXPECT_DOUBLE_EQ(camera.k3, 1.163314);
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
  // Every camera value of TUM1, read as ocg_slam run reads it (the camera required).
  const LoadedSettings tum1 =
      LoadSettings(*data + "/orbslam2_settings/Monocular_TUM1.yaml", CameraNeed::kIntrinsics);
  ExpectTum1Calibration(tum1.settings.camera.model);
  EXPECT_EQ(tum1.settings.camera.model.height, 480);
  EXPECT_DOUBLE_EQ(tum1.settings.camera.fps, 30.0);
  // ORB-SLAM2 files take the image size from the images: ocg_slam objects reads none.
  const std::string no_size =
      ErrorOf(ReadTextFile(*data + "/orbslam2_settings/Monocular_TUM1.yaml"),
              CameraNeed::kIntrinsicsAndImageSize);
  EXPECT_NE(no_size.find("Camera.width, Camera.height"), std::string::npos) << no_size;
}

TEST(Settings, ReadsTheOrbSlam2KittiFileUnchanged) {
  const auto data = testing::SharedDataDir();
  if (!data) GTEST_SKIP() << testing::SharedDataSkipMessage();
  const LoadedSettings kitti = LoadSettings(*data + "/kitti_07_first160/orbslam2_KITTI04-12.yaml",
                                            CameraNeed::kIntrinsicsAndImageSize);
  const PinholeCamera& camera = kitti.settings.camera.model;
  EXPECT_DOUBLE_EQ(camera.fx, 707.0912);
  EXPECT_DOUBLE_EQ(camera.fy, 707.0912);
  EXPECT_DOUBLE_EQ(camera.cx, 601.8873);
  EXPECT_DOUBLE_EQ(camera.cy, 183.1104);
  EXPECT_FALSE(camera.HasDistortion());
  EXPECT_EQ(camera.width, 1226);
  EXPECT_EQ(camera.height, 370);
  EXPECT_DOUBLE_EQ(kitti.settings.camera.fps, 10.0);
  EXPECT_EQ(kitti.settings.orb.features, 2000);
  EXPECT_TRUE(kitti.warnings.empty()) << kitti.warnings.front();
}

// ORB-SLAM3's Examples/Monocular/TUM1.yaml layout, with the values that equal our defaults
// (640x480, 30 fps, RGB, ORB-SLAM2's ORB settings) changed so that reading them shows.
const char* const kOrbSlam3Tum1Like = R"(%YAML:1.0
File.version: "1.0"

Camera.type: "PinHole"

Camera1.fx: 517.306408
Camera1.fy: 516.469215
Camera1.cx: 318.643040
Camera1.cy: 255.313989

Camera1.k1: 0.262383
Camera1.k2: -0.953104
Camera1.p1: -0.005358
Camera1.p2: 0.002628
Camera1.k3: 1.163314

Camera.fps: 20
Camera.RGB: 0

Camera.width: 752
Camera.height: 500

ORBextractor.nFeatures: 1500
ORBextractor.scaleFactor: 1.25
ORBextractor.nLevels: 6
ORBextractor.iniThFAST: 18
ORBextractor.minThFAST: 6

Viewer.KeyFrameSize: 0.05
Viewer.KeyFrameLineWidth: 1.0
Viewer.GraphLineWidth: 0.9
Viewer.PointSize: 3.0
Viewer.CameraSize: 0.08
Viewer.CameraLineWidth: 3.0
Viewer.ViewpointX: 0.0
Viewer.ViewpointY: -0.7
Viewer.ViewpointZ: -1.8
Viewer.ViewpointF: 400.0
)";

TEST(Settings, ReadsOrbSlam3Version1PinholeFiles) {
  const LoadedSettings loaded =
      ParseSettings(kOrbSlam3Tum1Like, "TUM1.yaml", CameraNeed::kIntrinsicsAndImageSize);
  ExpectTum1Calibration(loaded.settings.camera.model);
  EXPECT_EQ(loaded.settings.camera.model.width, 752);
  EXPECT_EQ(loaded.settings.camera.model.height, 500);
  EXPECT_DOUBLE_EQ(loaded.settings.camera.fps, 20.0);
  EXPECT_FALSE(loaded.settings.camera.rgb);
  EXPECT_EQ(loaded.settings.orb.features, 1500);
  EXPECT_DOUBLE_EQ(loaded.settings.orb.scale_factor, 1.25);
  EXPECT_EQ(loaded.settings.orb.levels, 6);
  EXPECT_EQ(loaded.settings.orb.initial_fast_threshold, 18);
  EXPECT_EQ(loaded.settings.orb.minimum_fast_threshold, 6);
  EXPECT_DOUBLE_EQ(loaded.settings.viewer.point_size, 3.0);
  EXPECT_DOUBLE_EQ(loaded.settings.viewer.viewpoint_f, 400.0);
  EXPECT_TRUE(loaded.warnings.empty()) << loaded.warnings.front();

  // Four distortion coefficients (no k3), as ORB-SLAM3 allows.
  std::string four = kOrbSlam3Tum1Like;
  four.erase(four.find("Camera1.k3"), std::string("Camera1.k3: 1.163314\n").size());
  EXPECT_DOUBLE_EQ(ParseSettings(four, "four.yaml").settings.camera.model.k3, 0.0);
  // Values are checked under the key the file uses.
  std::string negative = kOrbSlam3Tum1Like;
  negative.replace(negative.find("517.306408"), 10, "-517.3");
  const std::string error = ErrorOf(negative);
  EXPECT_NE(error.find("fixture.yaml:6: key 'Camera1.fx': must be positive"), std::string::npos)
      << error;
}

TEST(Settings, OtherCameraModelsAreErrorsNamingKeyAndValue) {
  // ORB-SLAM3's pre-1.0 fisheye layout: k1..k4 are Kannala-Brandt coefficients.
  const std::string fisheye = ErrorOf(
      "Camera.type: \"KannalaBrandt8\"\nCamera.fx: 190.97\nCamera.fy: 190.97\nCamera.cx: 254.93\n"
      "Camera.cy: 256.89\nCamera.k1: 0.0034\nCamera.k2: 0.0007\nCamera.k3: -0.0020\n"
      "Camera.k4: 0.0002\n");
  EXPECT_NE(fisheye.find("fixture.yaml:1: key 'Camera.type': camera model 'KannalaBrandt8'"),
            std::string::npos)
      << fisheye;
  std::string version1 = kOrbSlam3Tum1Like;
  version1.replace(version1.find("PinHole"), 7, "KannalaBrandt8");
  EXPECT_NE(ErrorOf(version1).find("fixture.yaml:4: key 'Camera.type': camera model "
                                   "'KannalaBrandt8' is not supported"),
            std::string::npos);
  EXPECT_NE(ErrorOf("Camera.type: Rectified\n").find("'Rectified'"), std::string::npos);
  // Without Camera.type, a fourth radial coefficient still says "not a pinhole camera".
  const std::string k4 =
      ErrorOf("Camera.fx: 1\nCamera.fy: 1\nCamera.cx: 1\nCamera.cy: 1\nCamera.k4: 0.1\n");
  EXPECT_NE(k4.find("fixture.yaml:5: key 'Camera.k4': not a parameter"), std::string::npos) << k4;
  std::string k4_version1 = kOrbSlam3Tum1Like;
  k4_version1 += "Camera1.k4: 0.0002\n";
  EXPECT_NE(ErrorOf(k4_version1).find("key 'Camera1.k4': not a parameter"), std::string::npos);
  EXPECT_NE(ErrorOf("Camera:\n  newWidth: 600\n").find("key 'Camera.newWidth': resizing"),
            std::string::npos);
  EXPECT_NE(ErrorOf("File.version: \"2.0\"\n")
                .find("key 'File.version': unknown settings file "
                      "version '2.0'"),
            std::string::npos);
}

TEST(Settings, CameraKeysOfTheOtherLayoutAreErrors) {
  // ORB-SLAM3 keys without File.version: ORB-SLAM3 itself would not read them either.
  const std::string camera1 = ErrorOf("Camera1.fx: 500\n");
  EXPECT_NE(camera1.find("fixture.yaml:1: key 'Camera1.fx'"), std::string::npos) << camera1;
  EXPECT_NE(camera1.find("File.version"), std::string::npos) << camera1;
  const std::string camera = ErrorOf(std::string(kOrbSlam3Tum1Like) + "Camera.k1: 0.1\n");
  EXPECT_NE(camera.find("key 'Camera.k1': this file says File.version \"1.0\""), std::string::npos)
      << camera;
}

TEST(Settings, IncompleteCameraGroupsAreErrorsNamingTheMissingKeys) {
  const std::string intrinsics = ErrorOf("OCG.tau_doubt: 40\nCamera.fx: 535.4\n");
  EXPECT_NE(intrinsics.find("fixture.yaml:2: key 'Camera.fx': given without Camera.fy, "
                            "Camera.cx, Camera.cy"),
            std::string::npos)
      << intrinsics;
  const std::string distortion = ErrorOf(
      "Camera: {fx: 1, fy: 1, cx: 1, cy: 1}\nCamera.k1: 0.2\nCamera.k2: -0.9\nCamera.p1: 0.01\n");
  EXPECT_NE(distortion.find("key 'Camera.k1': given without Camera.p2"), std::string::npos)
      << distortion;
  EXPECT_NE(ErrorOf("Camera.k3: 0.5\n").find("key 'Camera.k3': given without Camera.k1"),
            std::string::npos);
  const std::string version1 = ErrorOf("File.version: \"1.0\"\nCamera1.fy: 500\n");
  EXPECT_NE(version1.find("key 'Camera1.fy': given without Camera1.fx, Camera1.cx, Camera1.cy"),
            std::string::npos)
      << version1;
}

TEST(Settings, CommandsThatNeedACameraRequireItsKeys) {
  const std::string no_camera = "OCG.tau_doubt: 40\n";
  EXPECT_DOUBLE_EQ(ParseSettings(no_camera, "a.yaml").settings.camera.model.fx, 525.0)
      << "tools without a camera keep the defaults";
  const std::string run = ErrorOf(no_camera, CameraNeed::kIntrinsics);
  EXPECT_NE(run.find("fixture.yaml: camera keys missing: this command needs Camera.fx, "
                     "Camera.fy, Camera.cx, Camera.cy;"),
            std::string::npos)
      << run;
  const std::string intrinsics = "Camera: {fx: 500, fy: 500, cx: 320, cy: 240}\n";
  EXPECT_NO_THROW(ParseSettings(intrinsics, "a.yaml", CameraNeed::kIntrinsics));
  const std::string objects = ErrorOf(intrinsics, CameraNeed::kIntrinsicsAndImageSize);
  EXPECT_NE(objects.find("needs Camera.width, Camera.height (it reads no image"), std::string::npos)
      << objects;
  EXPECT_NE(ErrorOf("File.version: \"1.0\"\n", CameraNeed::kIntrinsics)
                .find("needs Camera1.fx, Camera1.fy, Camera1.cx, Camera1.cy"),
            std::string::npos);
}

TEST(Settings, PrincipalPointOffTheImageIsAnError) {
  // KITTI's intrinsics with width and height swapped.
  const std::string swapped = ErrorOf(
      "Camera: {fx: 707.09, fy: 707.09, cx: 601.89, cy: 183.11, width: 370, height: 1226}\n");
  EXPECT_NE(swapped.find("fixture.yaml:1: key 'Camera.cx': must lie inside the image (0 to "
                         "Camera.width = 370)"),
            std::string::npos)
      << swapped;
  std::string version1 = kOrbSlam3Tum1Like;
  version1.replace(version1.find("Camera.width: 752"), 17, "Camera.width: 300");
  EXPECT_NE(ErrorOf(version1).find("fixture.yaml:8: key 'Camera1.cx': must lie inside the image"),
            std::string::npos);
}

TEST(Settings, NonNumericCameraValuesNameTheKey) {
  std::string text = kOrbSlam3Tum1Like;
  text.replace(text.find("516.469215"), 10, "516,469215");
  const std::string error = ErrorOf(text);
  EXPECT_NE(error.find("fixture.yaml:7: key 'Camera1.fy': expected a number, got '516,469215'"),
            std::string::npos)
      << error;
  EXPECT_NE(ErrorOf("Camera.width: 640px\n").find("key 'Camera.width': expected an integer"),
            std::string::npos);
}

TEST(Settings, ShippedConfigsLoadWithoutWarnings) {
  for (const char* name : {"TUM1.yaml", "TUM2.yaml", "TUM3.yaml", "EuRoC.yaml"}) {
    const std::string path = testing::SourceDir() + "/config/" + name;
    ASSERT_TRUE(fs::exists(path)) << path;
    // As ocg_slam objects reads them: intrinsics and image size required.
    const LoadedSettings loaded = LoadSettings(path, CameraNeed::kIntrinsicsAndImageSize);
    EXPECT_TRUE(loaded.warnings.empty()) << name << ": " << loaded.warnings.front();
    EXPECT_GT(loaded.settings.camera.model.fx, 400) << name;
  }
  EXPECT_EQ(LoadSettings(testing::SourceDir() + "/config/EuRoC.yaml").settings.camera.model.width,
            752);
  ExpectTum1Calibration(
      LoadSettings(testing::SourceDir() + "/config/TUM1.yaml").settings.camera.model);
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
  // The default is the best measured mode (issue 18); the paper's OCG is OCG.mode: paper.
  EXPECT_EQ(settings.ocg.mode, "improved");
  EXPECT_EQ(settings.camera.model.width, 640);
  EXPECT_EQ(settings.camera.model.height, 480);
  EXPECT_NO_THROW(settings.Check());
}

TEST(Settings, UnknownKeyWarnsWithItsNameAndLine) {
  const LoadedSettings loaded = ParseSettings("System.seed: 7\nOCG.tau_dobut: 3\n", "typo.yaml");
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_NE(loaded.warnings[0].find("typo.yaml:2"), std::string::npos) << loaded.warnings[0];
  EXPECT_NE(loaded.warnings[0].find("OCG.tau_dobut"), std::string::npos);
}

TEST(Settings, UnknownKeySuggestsTheKnownKeyItMostLikelyMeant) {
  const LoadedSettings loaded =
      ParseSettings("System.seed: 7\nLoopClosing.enabeld: false\nCompletelyNew.key: 1\n", "v.yaml");
  ASSERT_EQ(loaded.warnings.size(), 2u);
  EXPECT_NE(loaded.warnings[0].find("v.yaml:2: unknown key 'LoopClosing.enabeld' ignored; did "
                                    "you mean 'LoopClosing.enabled'?"),
            std::string::npos)
      << loaded.warnings[0];
  EXPECT_EQ(loaded.warnings[1].find("did you mean"), std::string::npos) << loaded.warnings[1];
  EXPECT_TRUE(loaded.settings.loop_closing.enabled) << "the misspelt key changes nothing";
  // Strict: an error listing every unknown key, the value never taken silently.
  try {
    ParseSettings("OCG.tau_dobut: 3\nLoopClosing.enabeld: false\n", "v.yaml", CameraNeed::kNone,
                  UnknownKeys::kError);
    FAIL() << "strict loading accepted unknown keys";
  } catch (const SettingsError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("v.yaml:1: unknown key 'OCG.tau_dobut'; did you mean 'OCG.tau_doubt'?"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("v.yaml:2: unknown key 'LoopClosing.enabeld'; did you mean "
                           "'LoopClosing.enabled'?"),
              std::string::npos)
        << message;
  }
  // ORB-SLAM's own keys of other sensors stay quiet, strict or not.
  EXPECT_NO_THROW(ParseSettings("ThDepth: 35\nCamera.bf: 40\n", "s.yaml", CameraNeed::kNone,
                                UnknownKeys::kError));
}

TEST(Settings, MisspeltCameraKeysSuggestTheKeyNotAnotherCameraModel) {
  const std::string version1 =
      "File.version: \"1.0\"\nCamera.type: \"PinHole\"\nCamera1.Fx: 517.3\nCamera1.fy: 516.5\n"
      "Camera1.cx: 318.6\nCamera1.cy: 255.3\n";
  const std::string error = ErrorOf(version1);
  EXPECT_NE(error.find("fixture.yaml:3: key 'Camera1.Fx'"), std::string::npos) << error;
  EXPECT_NE(error.find("did you mean Camera1.fx?"), std::string::npos) << error;
  EXPECT_EQ(error.find("camera models"), std::string::npos) << error;
  EXPECT_NE(ErrorOf("Camera.FX: 500\n").find("did you mean Camera.fx?"), std::string::npos);
  EXPECT_NE(ErrorOf("Camera.widht: 640\n").find("did you mean Camera.width?"), std::string::npos);
  // k4 is a fisheye coefficient, not a misspelt k1.
  const std::string fisheye = ErrorOf("Camera.k4: 0.1\n");
  EXPECT_NE(fisheye.find("other camera models"), std::string::npos) << fisheye;
  EXPECT_EQ(fisheye.find("did you mean"), std::string::npos) << fisheye;
}

TEST(SettingsFile, ClosestKeyNeedsACloseSpelling) {
  const std::vector<std::string> known = {"OCG.tau_doubt", "OCG.tau_observable", "Camera.fx"};
  EXPECT_EQ(ClosestKey("ocg.TAU_DOUBT", known), "OCG.tau_doubt");
  EXPECT_EQ(ClosestKey("OCG.tau_doutb", known), "OCG.tau_doubt");
  EXPECT_EQ(ClosestKey("OCG.tau_obsrevable", known), "OCG.tau_observable");
  EXPECT_EQ(ClosestKey("Objects.min_confidence", known), "");
  EXPECT_EQ(ClosestKey("Camera.k4", known), "");
}

// The flat file a batch writes: an ORB-SLAM2 file (OpenCV YAML, "Key:value" without a
// space) with keys changed, read back to the same values.
TEST(SettingsFile, SetKeysAndWriteFlatYamlThatReadsBackTheSame) {
  SettingsFile file = SettingsFile::Parse(
      "%YAML:1.0\nCamera.fx: 517.306408\nCamera.fy: 516.469215\nCamera.cx: 318.643040\n"
      "Camera.cy: 255.313989\nViewer.PointSize:2\nLoopClosing:\n  enabled: true\n"
      "File.comment: \"a: b # c\"\n",
      "TUM1.yaml");
  file.Set("LoopClosing.enabled", "false", "--set LoopClosing.enabled");
  file.Set("Objects.up", "[0, 0, 1]", "--set Objects.up");
  file.Set("Vocabulary.path", "\"o'brien/voc \\\"1\\\".ocgvoc\"", "--set Vocabulary.path");
  const std::string flat = file.ToFlatYaml("from TUM1.yaml");
  EXPECT_EQ(flat.rfind("# from TUM1.yaml\n", 0), 0u) << flat;
  const SettingsFile again = SettingsFile::Parse(flat, "flat.yaml");
  for (const char* key : {"Camera.fx", "Camera.cy", "Viewer.PointSize", "LoopClosing.enabled",
                          "Vocabulary.path", "File.comment"}) {
    std::string before, after;
    ASSERT_TRUE(file.Read(key, &before)) << key;
    ASSERT_TRUE(again.Read(key, &after)) << key << " missing in:\n" << flat;
    EXPECT_EQ(before, after) << key;
  }
  std::string vocabulary;
  again.Read("Vocabulary.path", &vocabulary);
  EXPECT_EQ(vocabulary, "o'brien/voc \"1\".ocgvoc");
  std::vector<double> up;
  ASSERT_TRUE(again.Read("Objects.up", &up));
  EXPECT_EQ(up, (std::vector<double>{0, 0, 1}));
  // File order kept, the new keys last.
  EXPECT_LT(flat.find("Camera.fx"), flat.find("LoopClosing.enabled: false"));
  EXPECT_LT(flat.find("File.comment"), flat.find("Objects.up"));
  const LoadedSettings loaded =
      ReadSettingsFile(again, CameraNeed::kIntrinsics, UnknownKeys::kWarn);
  EXPECT_FALSE(loaded.settings.loop_closing.enabled);
  EXPECT_DOUBLE_EQ(loaded.settings.viewer.point_size, 2.0);
  EXPECT_DOUBLE_EQ(loaded.settings.objects.up.z(), 1.0);
}

// The error of reading the file strictly, or "" when it reads.
std::string StrictReadError(const SettingsFile& file) {
  try {
    ReadSettingsFile(file, CameraNeed::kNone, UnknownKeys::kError);
  } catch (const SettingsError& error) {
    return error.what();
  }
  return "";
}

TEST(SettingsFile, ErrorsAboutASetKeyNameWhereItWasSet) {
  SettingsFile file = SettingsFile::Parse("System.seed: 7\n", "base.yaml");
  file.Set("OCG.tau_doubt", "lots", "--set OCG.tau_doubt");
  std::string error = StrictReadError(file);
  EXPECT_NE(error.find("--set OCG.tau_doubt: key 'OCG.tau_doubt': expected a number, got 'lots'"),
            std::string::npos)
      << error;
  file.Set("LoopClosing.enabeld", "false", "--set LoopClosing.enabeld");
  file.Set("OCG.tau_doubt", "40", "--set OCG.tau_doubt");
  error = StrictReadError(file);
  EXPECT_NE(error.find("--set LoopClosing.enabeld: unknown key 'LoopClosing.enabeld'; did you "
                       "mean 'LoopClosing.enabled'?"),
            std::string::npos)
      << error;
  EXPECT_THROW(file.Set("Objects.up", "{x: 1}", "--set Objects.up"), SettingsError);
  EXPECT_THROW(file.Set("bad key", "1", "--set bad key"), SettingsError);
}

TEST(Settings, KnownKeysAreEveryKeyTheModulesRead) {
  const std::vector<std::string> keys = KnownSettingsKeys();
  for (const char* key : {"Camera.fx", "Camera.width", "System.sequential", "ORBextractor.nLevels",
                          "LoopClosing.enabled", "Objects.up", "OCG.tau_doubt", "OCG.mode",
                          "Viewer.PointSize", "Vocabulary.path", "Initializer.seed"}) {
    EXPECT_NE(std::find(keys.begin(), keys.end(), key), keys.end()) << key;
  }
  EXPECT_EQ(std::set<std::string>(keys.begin(), keys.end()).size(), keys.size());
  EXPECT_GT(keys.size(), 100u);
}

// docs/settings.md names every key the modules read (in full, or `name` in its section's
// table): a key added to a reader without a line in the docs fails here.
TEST(Settings, EveryKnownKeyIsDocumented) {
  const std::string docs = ReadTextFile(testing::SourceDir() + "/docs/settings.md");
  for (const std::string& key : KnownSettingsKeys()) {
    const std::string name = key.substr(key.find('.') + 1);
    EXPECT_TRUE(docs.find(key) != std::string::npos ||
                docs.find("`" + name + "`") != std::string::npos)
        << key << " is not in docs/settings.md";
  }
}

// The tables of docs/settings.md are the field lists, as `ocg_slam settings --markdown`
// prints them (tools/settings_docs.py writes them): a key, default or bound changed in a
// field list without the docs fails here.
TEST(Settings, DocsTablesAreTheFieldLists) {
  const std::string docs = ReadTextFile(testing::SourceDir() + "/docs/settings.md");
  for (const SettingsSection& section : DescribeSettings()) {
    EXPECT_NE(docs.find(SettingsTableMarkdown(section)), std::string::npos)
        << "docs/settings.md: the table of " << section.name
        << " is not the field list's; run tools/settings_docs.py build/tools/ocg_slam";
  }
}

// One list drives reading, checking and the known keys: every field of every section is a
// known key, and a value just outside its bound (or NaN) is refused, naming the key, by the
// reader of a settings file.
TEST(Settings, EveryFieldIsReadAndEveryBoundIsEnforced) {
  const std::vector<std::string> known = KnownSettingsKeys();
  std::size_t bounds_tried = 0;
  for (const SettingsSection& section : DescribeSettings()) {
    ASSERT_FALSE(section.fields.empty()) << section.name;
    for (const OptionFieldDescription& field : section.fields) {
      EXPECT_EQ(field.key.rfind(section.name + ".", 0), 0u) << field.key;
      EXPECT_NE(std::find(known.begin(), known.end(), field.key), known.end()) << field.key;
      EXPECT_FALSE(field.meaning.empty()) << field.key;
    }
  }
  const auto try_value = [&](const std::string& key, double value) {
    std::ostringstream text;
    if (std::isnan(value)) {
      text << key << ": .nan\n";
    } else {
      text << key << ": " << value << "\n";
    }
    try {
      ParseSettings(text.str(), "bounds.yaml");
      ADD_FAILURE() << key << " accepted " << value;
    } catch (const SettingsError& error) {
      EXPECT_NE(std::string(error.what()).find(key), std::string::npos) << error.what();
      ++bounds_tried;
    }
  };
  const auto visit_bounds = [&](const char* key, const auto& member, const OptionBound& bound,
                                const char*) {
    using Member = std::decay_t<decltype(member)>;
    if constexpr (std::is_arithmetic_v<Member> && !std::is_same_v<Member, bool>) {
      for (double value : bound.RejectedExamples()) {
        if (std::is_integral_v<Member> && std::isnan(value)) continue;  // not a whole number
        try_value(key, value);
      }
    }
  };
  const Settings defaults;
  TrackingOptions::VisitFields(defaults.tracking, visit_bounds);
  LocalMappingOptions::VisitFields(defaults.local_mapping, visit_bounds);
  LoopClosingOptions::VisitFields(defaults.loop_closing, visit_bounds);
  InitialMapOptions::VisitFields(defaults.initializer, visit_bounds);
  OrbExtractorOptions::VisitFields(defaults.orb, visit_bounds);
  MatcherOptions::VisitFields(defaults.matcher, visit_bounds);
  ObjectsOptions::VisitFields(defaults.objects, visit_bounds);
  OcgOptions::VisitFields(defaults.ocg, visit_bounds);
  ViewerOptions::VisitFields(defaults.viewer, visit_bounds);
  EXPECT_GT(bounds_tried, 150u);
}

TEST(OptionBound, MessagesAndTextSayTheInterval) {
  EXPECT_EQ(OptionBound::Between(0, true, 1, false).Message(), "must be in (0, 1]");
  EXPECT_EQ(OptionBound::Between(0, true, 1, false).Text(), "(0, 1]");
  EXPECT_EQ(OptionBound::Positive().Message(), "must be positive");
  EXPECT_EQ(OptionBound::NonNegative().Message(), "must not be negative");
  EXPECT_EQ(OptionBound::AtLeast(8).Message(), "must be at least 8");
  EXPECT_EQ(OptionBound::AtLeast(8).Text(), ">= 8");
  EXPECT_EQ(OptionBound::MoreThan(1).Message(), "must be more than 1");
  EXPECT_EQ(OptionBound::AtLeast(2).Because("a centre needs two rays").Message(),
            "must be at least 2 (a centre needs two rays)");
  EXPECT_TRUE(OptionBound::Open(0, 1).Accepts(0.5));
  EXPECT_FALSE(OptionBound::Open(0, 1).Accepts(0));
  EXPECT_FALSE(OptionBound::Open(0, 1).Accepts(1));
  EXPECT_TRUE(OptionBound::Closed(0, 1).Accepts(1));
  EXPECT_FALSE(OptionBound::Positive().Accepts(std::numeric_limits<double>::infinity()));
  EXPECT_FALSE(OptionBound::Positive().Accepts(std::nan("")));
  EXPECT_TRUE(OptionBound::Any().Accepts(std::nan("")));
  EXPECT_TRUE(OptionBound::Any().RejectedExamples().empty());
}

TEST(Settings, SettingsOfAnotherCameraNameTheFileAndBothImageSizes) {
  const fs::path folder = fs::path(::testing::TempDir()) / "ocg_settings_image_size";
  fs::create_directories(folder);
  const std::string image = (folder / "000000.pgm").string();
  // A 1226x370 grey image, as KITTI's (a PGM: written without an image library).
  WriteFileAtomically(image, "P5\n1226 370\n255\n" + std::string(1226 * 370, '\x80'));
  const std::string tum1 =
      "%YAML:1.0\nCamera.fx: 517.306408\nCamera.fy: 516.469215\nCamera.cx: 318.643040\n"
      "Camera.cy: 255.313989\n";
  try {
    CheckCameraFitsImage(ParseSettings(tum1, "Monocular_TUM1.yaml", CameraNeed::kIntrinsics),
                         image);
    FAIL() << "TUM settings accepted for a 1226x370 image";
  } catch (const SettingsError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("Monocular_TUM1.yaml"), std::string::npos) << message;
    EXPECT_NE(message.find("640x480"), std::string::npos) << message;
    EXPECT_NE(message.find("1226x370"), std::string::npos) << message;
    EXPECT_NE(message.find(image), std::string::npos) << message;
  }
  EXPECT_NO_THROW(CheckCameraFitsImage(
      ParseSettings(tum1 + "Camera.width: 1226\nCamera.height: 370\n", "k.yaml"), image));
  fs::remove_all(folder);
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
  const std::string error = ErrorOf("System.seed: 7\nOCG.tau_observable: 1.5\n");
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

TEST(SettingsFile, KeySetTwiceNamesBothLines) {
  const auto error_of = [](const std::string& text) {
    try {
      SettingsFile::Parse(text, "twice.yaml");
    } catch (const SettingsError& error) {
      return std::string(error.what());
    }
    return std::string();
  };
  const std::pair<const char*, const char*> cases[] = {
      {"Camera: {fx: 535.4}\nOCG.tau_doubt: 40\nCamera.fx: 100\n",
       "twice.yaml:3: key 'Camera.fx' is set a second time; first set at twice.yaml:1"},
      {"%YAML:1.0\nCamera.fx: 535.4\nCamera.fx:100\n",
       "twice.yaml:3: key 'Camera.fx' is set a second time; first set at twice.yaml:2"},
      {"Camera:\n  fx: 535.4\n  fy: 539.2\n  fx: 100\n",
       "twice.yaml:4: key 'Camera.fx' is set a second time; first set at twice.yaml:2"},
      // The same map twice with different keys: most YAML readers keep only the last.
      {"Camera:\n  fx: 535.4\nOCG:\n  mode: paper\nCamera:\n  fy: 1\n",
       "twice.yaml:5: key 'Camera' is set a second time; first set at twice.yaml:1"},
  };
  for (const auto& [text, expected] : cases) {
    const std::string error = error_of(text);
    EXPECT_NE(error.find(expected), std::string::npos) << text << "gave: " << error;
  }
  EXPECT_EQ(error_of("Camera:\n  fx: 1\nCamera.fy: 2\nCamera1:\n  fx: 3\n"), "");
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
