#pragma once
// One field list per options struct: each struct says once, in a static VisitFields, its
// settings keys, where each value goes, what values it takes and what it means. That one
// list drives the settings reader (ReadOptionFields), the value checks (CheckOptionFields),
// the known keys (a key is known because a reader asked for it) and the settings tables of
// docs/settings.md (DescribeOptionFields, printed by `ocg_slam settings --markdown`).
//
//   struct TrackingOptions {
//     int min_keyframes = 5;
//     template <typename Self, typename Visitor>
//     static void VisitFields(Self& self, Visitor&& visit) {
//       visit("Tracking.minKeyFrames", self.min_keyframes, OptionBound::AtLeast(2),
//             "lost with at most this many live keyframes: reset the map");
//     }
//   };
//
// Self is the struct or a const one; visit(key, member, bound, meaning) is called for
// every field in one fixed order (the order of the docs table). Rules between fields
// (max_rays >= candidate_min_observations) stay in the struct's Check().

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "ocg/core/options.h"
#include "ocg/core/settings_file.h"

namespace ocg {

// The values a numeric field accepts: an interval, each end open, closed or absent. Every
// bounded number must also be finite. Non-numeric fields take OptionBound::Any().
class OptionBound {
 public:
  static OptionBound Any() { return OptionBound(); }
  // value >= low ("must be at least 2").
  static OptionBound AtLeast(double low) { return Interval(low, false, kNone, false); }
  // value > low ("must be more than 1").
  static OptionBound MoreThan(double low) { return Interval(low, true, kNone, false); }
  // value > 0 ("must be positive").
  static OptionBound Positive() { return Interval(0, true, kNone, false); }
  // value >= 0 ("must not be negative").
  static OptionBound NonNegative() { return Interval(0, false, kNone, false); }
  // Between low and high; each end open (excluded) or closed ("must be in (0, 1]").
  static OptionBound Between(double low, bool low_open, double high, bool high_open) {
    return Interval(low, low_open, high, high_open);
  }
  // [low, high] ("must be in [0, 1]").
  static OptionBound Closed(double low, double high) { return Interval(low, false, high, false); }
  // (low, high) ("must be in (0, 1)").
  static OptionBound Open(double low, double high) { return Interval(low, true, high, true); }

  // The same bound, its message followed by why (" (a centre needs two rays)").
  OptionBound Because(std::string reason) const {
    OptionBound bound = *this;
    bound.reason_ = std::move(reason);
    return bound;
  }

  bool IsAny() const { return !bounded_; }

  bool Accepts(double value) const {
    if (!bounded_) return true;
    if (!std::isfinite(value)) return false;
    if (has_low_ && (low_open_ ? value <= low_ : value < low_)) return false;
    if (has_high_ && (high_open_ ? value >= high_ : value > high_)) return false;
    return true;
  }

  // What Check() says of a value outside the bound: "must be in (0, 1]".
  std::string Message() const {
    std::string text;
    if (has_low_ && has_high_) {
      text = std::string("must be in ") + (low_open_ ? "(" : "[") + Number(low_) + ", " +
             Number(high_) + (high_open_ ? ")" : "]");
    } else if (has_low_ && low_ == 0) {
      text = low_open_ ? "must be positive" : "must not be negative";
    } else if (has_low_) {
      text = (low_open_ ? "must be more than " : "must be at least ") + Number(low_);
    } else {
      text = "must be a finite number";
    }
    return reason_.empty() ? text : text + " (" + reason_ + ")";
  }

  // Values just outside the bound (and NaN), for tests that every bound is enforced; empty
  // for Any.
  std::vector<double> RejectedExamples() const {
    if (!bounded_) return {};
    std::vector<double> values = {std::numeric_limits<double>::quiet_NaN()};
    if (has_low_) values.push_back(low_open_ ? low_ : low_ - 1);
    if (has_high_) values.push_back(high_open_ ? high_ : high_ + 1);
    return values;
  }

  // The values taken, for the docs table: "(0, 1]", ">= 2", "> 0", "" for Any.
  std::string Text() const {
    if (!bounded_) return "";
    if (has_low_ && has_high_) {
      return std::string(low_open_ ? "(" : "[") + Number(low_) + ", " + Number(high_) +
             (high_open_ ? ")" : "]");
    }
    if (has_low_) return (low_open_ ? "> " : ">= ") + Number(low_);
    return "finite";
  }

  static std::string Number(double value) {
    std::ostringstream out;
    out << value;
    return out.str();
  }

 private:
  static constexpr double kNone = std::numeric_limits<double>::quiet_NaN();

  static OptionBound Interval(double low, bool low_open, double high, bool high_open) {
    OptionBound bound;
    bound.bounded_ = true;
    bound.has_low_ = !std::isnan(low);
    bound.low_ = low;
    bound.low_open_ = low_open;
    bound.has_high_ = !std::isnan(high);
    bound.high_ = high;
    bound.high_open_ = high_open;
    return bound;
  }

  bool bounded_ = false;
  bool has_low_ = false;
  double low_ = 0;
  bool low_open_ = false;
  bool has_high_ = false;
  double high_ = 0;
  bool high_open_ = false;
  std::string reason_;
};

// Reads a value of the types the settings file does not read itself.
inline bool ReadOptionValue(const SettingsFile& file, const std::string& key,
                            Eigen::Vector3d* value) {
  std::vector<double> numbers;
  if (!file.Read(key, &numbers)) return false;
  RequireOption(numbers.size() == 3, key, "needs 3 numbers");
  *value = Eigen::Vector3d(numbers[0], numbers[1], numbers[2]);
  return true;
}

inline bool ReadOptionValue(const SettingsFile& file, const std::string& key,
                            std::vector<int>* value) {
  std::vector<double> numbers;
  if (!file.Read(key, &numbers)) return false;
  value->clear();
  for (double number : numbers) {
    RequireOption(number == std::floor(number) && std::abs(number) < 1e9, key,
                  "needs whole numbers");
    value->push_back(static_cast<int>(number));
  }
  return true;
}

template <typename T>
bool ReadOptionValue(const SettingsFile& file, const std::string& key, T* value) {
  return file.Read(key, value);
}

// Reads every field of options that the file holds; the others keep their values.
// Throws SettingsError for a value of the wrong type, OptionError for a wrong shape.
template <typename Options>
void ReadOptionFields(const SettingsFile& file, Options* options) {
  Options::VisitFields(*options, [&file](const char* key, auto& member, const OptionBound&,
                                         const char*) { ReadOptionValue(file, key, &member); });
}

// Throws OptionError naming the key of the first field outside its bound.
template <typename Options>
void CheckOptionFields(const Options& options) {
  Options::VisitFields(
      options, [](const char* key, const auto& member, const OptionBound& bound, const char*) {
        using Member = std::decay_t<decltype(member)>;
        if constexpr (std::is_arithmetic_v<Member> && !std::is_same_v<Member, bool>) {
          RequireOption(bound.Accepts(static_cast<double>(member)), key, bound.Message());
        }
      });
}

// One row of a settings table: key, default value, values taken, meaning.
struct OptionFieldDescription {
  std::string key;
  std::string default_value;
  std::string values;
  std::string meaning;
};

inline std::string OptionValueText(bool value) { return value ? "true" : "false"; }
inline std::string OptionValueText(const std::string& value) {
  return value.empty() ? "(empty)" : "`" + value + "`";
}
inline std::string OptionValueText(const Eigen::Vector3d& value) {
  return "`[" + OptionBound::Number(value.x()) + ", " + OptionBound::Number(value.y()) + ", " +
         OptionBound::Number(value.z()) + "]`";
}
inline std::string OptionValueText(const std::vector<int>& value) {
  std::string text = "`[";
  for (std::size_t i = 0; i < value.size(); ++i) {
    text += (i ? ", " : "") + std::to_string(value[i]);
  }
  return text + "]`";
}
template <typename T>
std::string OptionValueText(const T& value) {
  static_assert(std::is_arithmetic_v<T>, "give the field type an OptionValueText");
  return OptionBound::Number(static_cast<double>(value));
}

// Every field of a default-constructed Options, in the order of its list.
template <typename Options>
std::vector<OptionFieldDescription> DescribeOptionFields() {
  const Options defaults{};
  std::vector<OptionFieldDescription> rows;
  Options::VisitFields(defaults, [&rows](const char* key, const auto& member,
                                         const OptionBound& bound, const char* meaning) {
    rows.push_back({key, OptionValueText(member), bound.Text(), meaning});
  });
  return rows;
}

}  // namespace ocg
