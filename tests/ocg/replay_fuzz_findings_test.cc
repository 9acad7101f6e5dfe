// ocg_replay lines the replay fuzz target (fuzz/replay_jsonl.cc) showed mishandled: numbers
// that do not fit the field's integer type are a ReplayFormatError naming the field, where
// they were a float-to-integer cast out of range (undefined behaviour).
#include <gtest/gtest.h>

#include <string>

#include "ocg/ocg/replay_format.h"

namespace ocg {
namespace {

// A valid line with one field's value replaced.
std::string Line(const std::string& keyframe, const std::string& width, const std::string& observed,
                 const std::string& class_id) {
  return R"({"keyframe": )" + keyframe +
         R"(, "T_cw": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1], "camera": {"fx": 500, "fy": 500,)"
         R"( "cx": 320, "cy": 240, "width": )" +
         width + R"(, "height": 480}, "observed": )" + observed + R"(, "classes": {"3": )" +
         class_id + "}}";
}

std::string ErrorOf(const std::string& line) {
  try {
    ParseObservationJson(line);
  } catch (const ReplayFormatError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no ReplayFormatError for " << line;
  return {};
}

TEST(ReplayFuzzFindings, IntegersOutOfRangeNameTheField) {
  EXPECT_NO_THROW(ParseObservationJson(Line("7", "640", "[3]", "41")));
  EXPECT_NE(ErrorOf(Line("1e300", "640", "[3]", "41")).find("\"keyframe\" must be a whole number"),
            std::string::npos);
  EXPECT_NE(ErrorOf(Line("7", "1e30", "[3]", "41")).find("\"camera\" width must be a whole number"),
            std::string::npos);
  EXPECT_NE(ErrorOf(Line("7", "640", "[1e30]", "41")).find("\"observed\" entry"),
            std::string::npos);
  EXPECT_NE(ErrorOf(Line("7", "640", "[2.5]", "41")).find("\"observed\" entry"), std::string::npos);
  EXPECT_NE(ErrorOf(Line("7", "640", "3", "41")).find("\"observed\" must be a list"),
            std::string::npos);
  EXPECT_NE(ErrorOf(Line("7", "640", "[3]", "4294967297")).find("class of object 3"),
            std::string::npos);
}

TEST(ReplayFuzzFindings, NumberBeyondADoubleIsAFormatError) {
  // nlohmann throws out_of_range (not parse_error) for 1e999: it escaped the reader.
  EXPECT_NE(ErrorOf(R"({"keyframe": 1, "timestamp": -0.928e476691})").find("not valid JSON"),
            std::string::npos);
}

TEST(ReplayFuzzFindings, WholeNumbersWrittenAsFloatsAreAccepted) {
  const KeyframeObservation observation = ParseObservationJson(Line("7.0", "640.0", "[3.0]", "41"));
  EXPECT_EQ(observation.keyframe_id, 7);
  EXPECT_EQ(observation.camera.width, 640);
  ASSERT_EQ(observation.observed.size(), 1u);
  EXPECT_EQ(observation.observed[0], 3);
}

}  // namespace
}  // namespace ocg
