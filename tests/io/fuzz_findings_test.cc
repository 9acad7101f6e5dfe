// Inputs the fuzz targets (fuzz/, tools/fuzz.sh) showed the readers mishandling: each must
// now end in the reader's documented error, naming the file and the field.
#include <gtest/gtest.h>

#include <string>

#include "error_of.h"
#include "ocg/core/file_io.h"
#include "ocg/core/settings_file.h"
#include "ocg/io/detections.h"
#include "ocg/io/point_cloud.h"
#include "ocg/io/sequence.h"
#include "ocg/io/text_lines.h"
#include "test_support.h"

namespace ocg {
namespace {

using testing::ErrorOf;

TEST(FuzzFindings, PlyVertexCountTheFileCannotHoldIsAParseErrorNotAnAllocation) {
  const std::string dir = testing::MakeTempDir("fuzz_ply");
  // Before: points.reserve(99999999999) asked for 2.4 TB (bad_alloc, or an abort under ASan).
  WriteFileAtomically(dir + "/huge.ply",
                      "ply\nformat ascii 1.0\nelement vertex 99999999999\nproperty float x\n"
                      "property float y\nproperty float z\nend_header\n1 2 3\n");
  const std::string message = ErrorOf<ParseError>([&] { ReadPlyPoints(dir + "/huge.ply"); });
  EXPECT_NE(message.find("huge.ply:9"), std::string::npos) << message;
  EXPECT_NE(message.find("ends after 1 of 99999999999 vertices"), std::string::npos) << message;
}

// A EuRoC folder with a valid data.csv and the given sensor.yaml body.
std::string EurocFolder(const std::string& name, const std::string& sensor_yaml) {
  const std::string root = testing::MakeTempDir(name);
  WriteFileAtomically(root + "/mav0/cam0/data.csv",
                      "#timestamp [ns],filename\n1403715273262142976,1403715273262142976.png\n");
  WriteFileAtomically(
      root + "/mav0/cam0/sensor.yaml",
      "%YAML:1.0\nintrinsics: [458.654, 457.296, 367.215, 248.375]\n" + sensor_yaml);
  return root;
}

TEST(FuzzFindings, EurocResolutionThatIsNoPixelCountIsASettingsError) {
  // Before: static_cast<int>(1e30), undefined behaviour (any width, or a trap).
  for (const char* resolution : {"[1e30, 480]", "[752, -1e12]", "[752.5, 480]", "[.nan, 480]"}) {
    const std::string root =
        EurocFolder("fuzz_euroc_resolution", std::string("resolution: ") + resolution + "\n");
    const std::string message = ErrorOf<SettingsError>([&] { ReadEurocSequence(root); });
    EXPECT_NE(message.find("sensor.yaml"), std::string::npos) << resolution << ": " << message;
    EXPECT_NE(message.find("key 'resolution'"), std::string::npos) << resolution << ": " << message;
  }
}

TEST(FuzzFindings, EurocImpossibleCameraIsASettingsErrorNamingTheSensorKey) {
  // Before: PinholeCamera::Check's OptionError ("Camera.fx: ...", a key of another file)
  // escaped the reader, whose documented errors are FileError, ParseError, SettingsError.
  const std::string root = testing::MakeTempDir("fuzz_euroc_camera");
  WriteFileAtomically(root + "/mav0/cam0/data.csv", "1403715273262142976,a.png\n");
  WriteFileAtomically(root + "/mav0/cam0/sensor.yaml",
                      "intrinsics: [-458.654, 457.296, 367.215, 248.375]\n"
                      "resolution: [752, 480]\n");
  std::string message = ErrorOf<SettingsError>([&] { ReadEurocSequence(root); });
  EXPECT_NE(message.find("sensor.yaml: key 'intrinsics'"), std::string::npos) << message;
  WriteFileAtomically(root + "/mav0/cam0/sensor.yaml",
                      "intrinsics: [458.654, 457.296, 367.215, 248.375]\n"
                      "resolution: [0, 480]\n");
  message = ErrorOf<SettingsError>([&] { ReadEurocSequence(root); });
  EXPECT_NE(message.find("sensor.yaml: key 'resolution'"), std::string::npos) << message;
}

TEST(FuzzFindings, EaoClassIdBeyondIntDoesNotWrapToAValidClass) {
  const std::string dir = testing::MakeTempDir("fuzz_eao_class");
  // 2^32 + 1 narrowed to int is 1 ("bicycle"): it was accepted as such.
  WriteFileAtomically(dir + "/1.0.txt", "4294967297 10 20 30 40 0.9\n");
  const std::string message = ErrorOf<ParseError>([&] { ReadEaoDetectionFile(dir + "/1.0.txt"); });
  EXPECT_NE(message.find("1.0.txt:1: class_id must be a COCO-80 index"), std::string::npos)
      << message;
  EXPECT_NE(message.find("4294967297"), std::string::npos) << message;
}

TEST(FuzzFindings, JsonCategoryIdMustBeAWholeNumberThatFits) {
  const std::string dir = testing::MakeTempDir("fuzz_json_class");
  // Before: nlohmann's get<int>() of 1e30 is a float-to-int cast out of range.
  for (const char* category : {"1e30", "-1e30", "2.5", "\"41\"", "true"}) {
    WriteFileAtomically(dir + "/d.json",
                        std::string(R"([{"file_name": "a.png", "detections": )") +
                            R"([{"category_id": )" + category +
                            R"(, "detection_score": 0.5, "bbox": [1, 2, 3, 4]}]}])");
    const std::string message = ErrorOf<ParseError>([&] { ReadJsonDetections(dir + "/d.json"); });
    EXPECT_NE(message.find("d.json: image #0"), std::string::npos) << category << ": " << message;
    EXPECT_NE(message.find("category_id"), std::string::npos) << category << ": " << message;
  }
  // A number beyond a double made nlohmann throw out_of_range, which escaped the reader.
  WriteFileAtomically(dir + "/d.json", R"([{"file_name": "a.png", "detections": [1e99999]}])");
  const std::string message = ErrorOf<ParseError>([&] { ReadJsonDetections(dir + "/d.json"); });
  EXPECT_NE(message.find("d.json: not valid JSON"), std::string::npos) << message;
  // A whole number written as a float is still the class.
  WriteFileAtomically(dir + "/d.json", R"([{"file_name": "a.png", "detections": )"
                                       R"([{"category_id": 41.0, "detection_score": 0.5,)"
                                       R"( "bbox": [1, 2, 3, 4]}]}])");
  EXPECT_EQ(ReadJsonDetections(dir + "/d.json").at(0).detections.at(0).class_id, 41);
}

}  // namespace
}  // namespace ocg
