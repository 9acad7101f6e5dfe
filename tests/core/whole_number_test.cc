#include "ocg/core/whole_number.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>

namespace ocg {
namespace {

TEST(WholeNumber, AcceptsExactlyTheWholeNumbersThatFit) {
  EXPECT_EQ(WholeNumberAs<int>(752.0), 752);
  EXPECT_EQ(WholeNumberAs<int>(-3.0), -3);
  EXPECT_EQ(WholeNumberAs<int>(2147483647.0), 2147483647);
  EXPECT_EQ(WholeNumberAs<int>(-2147483648.0), std::numeric_limits<int>::lowest());
  EXPECT_FALSE(WholeNumberAs<int>(2147483648.0));
  EXPECT_FALSE(WholeNumberAs<int>(-2147483649.0));
  EXPECT_FALSE(WholeNumberAs<int>(1e30));
  EXPECT_FALSE(WholeNumberAs<int>(0.5));
  EXPECT_FALSE(WholeNumberAs<int>(std::nan("")));
  EXPECT_FALSE(WholeNumberAs<int>(HUGE_VAL));
  EXPECT_FALSE(WholeNumberAs<std::uint32_t>(-1.0));
  // 2^63 is one past the largest int64.
  EXPECT_FALSE(WholeNumberAs<std::int64_t>(9223372036854775808.0));
  EXPECT_EQ(WholeNumberAs<std::int64_t>(-9223372036854775808.0),
            std::numeric_limits<std::int64_t>::lowest());
}

TEST(WholeNumber, JsonIntegersFloatsAndOtherTypes) {
  using nlohmann::json;
  EXPECT_EQ(JsonWholeNumberAs<int>(json(41)), 41);
  EXPECT_EQ(JsonWholeNumberAs<int>(json(41.0)), 41);
  EXPECT_EQ(JsonWholeNumberAs<std::int64_t>(json::parse("-9223372036854775808")),
            std::numeric_limits<std::int64_t>::lowest());
  EXPECT_FALSE(JsonWholeNumberAs<int>(json::parse("4294967297")));
  EXPECT_FALSE(JsonWholeNumberAs<int>(json::parse("-4294967297")));
  EXPECT_FALSE(JsonWholeNumberAs<std::int64_t>(json::parse("18446744073709551615")));
  EXPECT_FALSE(JsonWholeNumberAs<std::uint32_t>(json(-1)));
  EXPECT_FALSE(JsonWholeNumberAs<int>(json(1e30)));
  EXPECT_FALSE(JsonWholeNumberAs<int>(json(2.5)));
  EXPECT_FALSE(JsonWholeNumberAs<int>(json("41")));
  EXPECT_FALSE(JsonWholeNumberAs<int>(json(true)));
  EXPECT_FALSE(JsonWholeNumberAs<int>(json(nullptr)));
}

}  // namespace
}  // namespace ocg
