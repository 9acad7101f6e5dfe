#pragma once
// Shared validation helper for the per-module options structs: every Check() throws an
// OptionError that names the settings key, so the settings loader can point the user at
// the file and line that holds it.

#include <stdexcept>
#include <string>

namespace ocg {

class OptionError : public std::invalid_argument {
 public:
  OptionError(std::string key, std::string message)
      : std::invalid_argument(key + ": " + message),
        key_(std::move(key)),
        message_(std::move(message)) {}
  const std::string& key() const { return key_; }
  // What is wrong, without the key.
  const std::string& message() const { return message_; }

 private:
  std::string key_;
  std::string message_;
};

inline void RequireOption(bool condition, const std::string& key, const std::string& message) {
  if (!condition) throw OptionError(key, message);
}

}  // namespace ocg
