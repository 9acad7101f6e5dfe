#pragma once
// Numbers read from files, turned into integers with a check: a value that is not a whole
// number or does not fit the type is for the reader to report (naming file and field),
// never a float-to-integer cast out of range (undefined behaviour) or a silent wrap.
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <type_traits>

namespace ocg {

// value as Int when it is a whole number within Int's range; nullopt otherwise (NaN too).
template <typename Int>
std::optional<Int> WholeNumberAs(double value) {
  static_assert(std::is_integral_v<Int>, "Int must be an integer type");
  // 2^digits is exact in a double, and the largest Int is 2^digits - 1.
  const double limit = std::ldexp(1.0, std::numeric_limits<Int>::digits);
  const double lowest = std::is_signed_v<Int> ? -limit : 0.0;
  if (!(value >= lowest && value < limit) || value != std::trunc(value)) return std::nullopt;
  return static_cast<Int>(value);
}

// The same for a JSON value (nlohmann::json, taken as a template so that this header
// needs no JSON library): integers stored as such, or floats holding a whole number.
// nullopt for anything else (strings, booleans, out-of-range numbers).
template <typename Int, typename Json>
std::optional<Int> JsonWholeNumberAs(const Json& value) {
  static_assert(std::is_integral_v<Int> && sizeof(Int) <= sizeof(std::int64_t),
                "Int must be an integer type of at most 64 bits");
  if (value.is_number_unsigned()) {
    const auto number = value.template get<std::uint64_t>();
    if (number > static_cast<std::uint64_t>(std::numeric_limits<Int>::max())) return std::nullopt;
    return static_cast<Int>(number);
  }
  if (value.is_number_integer()) {
    const auto number = value.template get<std::int64_t>();
    if constexpr (std::is_signed_v<Int>) {
      if (number < static_cast<std::int64_t>(std::numeric_limits<Int>::lowest()) ||
          number > static_cast<std::int64_t>(std::numeric_limits<Int>::max())) {
        return std::nullopt;
      }
    } else {
      if (number < 0 || static_cast<std::uint64_t>(number) > std::numeric_limits<Int>::max()) {
        return std::nullopt;
      }
    }
    return static_cast<Int>(number);
  }
  if (value.is_number_float()) return WholeNumberAs<Int>(value.template get<double>());
  return std::nullopt;
}

}  // namespace ocg
