#include "ocg/core/settings_file.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <regex>
#include <sstream>

#include "ocg/core/file_io.h"

namespace ocg {
namespace {

// OpenCV's YAML dialect differs from YAML 1.2 in two ways that appear in ORB-SLAM2's
// settings files: the "%YAML:1.0" directive, and "Key:value" with no space after the
// colon (ORB-SLAM2's "Viewer.PointSize:2"). Fix both while keeping line numbers.
std::string NormalizeOpenCvYaml(const std::string& text) {
  std::istringstream input(text);
  std::ostringstream output;
  std::string line;
  bool first = true;
  static const std::regex kTightKey(R"(^(\s*[A-Za-z_][A-Za-z0-9_.]*):([^\s:/].*)$)");
  while (std::getline(input, line)) {
    if (first && line.rfind("%YAML:", 0) == 0) {
      line = "# " + line;
    } else if (line.find('#') != 0) {
      line = std::regex_replace(line, kTightKey, "$1: $2");
    }
    first = false;
    output << line << '\n';
  }
  return output.str();
}

std::string Lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

bool ParseDouble(const std::string& text, double* value) {
  if (text.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const double parsed = std::strtod(text.c_str(), &end);
  if (errno != 0 || end != text.c_str() + text.size() || !std::isfinite(parsed)) return false;
  *value = parsed;
  return true;
}

bool ParseInteger(const std::string& text, long long* value) {
  if (text.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const long long parsed = std::strtoll(text.c_str(), &end, 10);
  if (errno != 0 || end != text.c_str() + text.size()) return false;
  *value = parsed;
  return true;
}

SettingsError KeySetTwice(const std::string& name, const std::string& key, int first_line,
                          int second_line) {
  return SettingsError(FileLocation(name, second_line) + ": key '" + key +
                       "' is set a second time; first set at " + FileLocation(name, first_line) +
                       " (keep one of the two)");
}

struct FlatEntry {
  std::string key;
  std::vector<std::string> items;
  bool is_sequence = false;
  int line = 0;
};

void FlattenNode(const YAML::Node& node, const std::string& prefix, const std::string& name,
                 std::vector<FlatEntry>* entries) {
  std::map<std::string, int> lines;  // of this map's keys, to report a key given twice
  for (const auto& child : node) {
    FlatEntry entry;
    if (!child.first.IsScalar()) {  // a YAML complex key ("? ..."): as<string> would throw
      throw SettingsError(FileLocation(name, child.first.Mark().line + 1) +
                          ": settings keys must be plain names, not lists or maps");
    }
    entry.key = prefix + child.first.Scalar();
    // The key's line, not the value's: a null value has no mark, a block list starts below.
    entry.line = child.first.Mark().line + 1;
    // Checked here too, not only after flattening: "Camera: {fx: 1}" given twice with
    // different keys flattens without a clash, yet most YAML readers keep the last map only.
    const auto [seen, first_time] = lines.emplace(entry.key, entry.line);
    if (!first_time) throw KeySetTwice(name, entry.key, seen->second, entry.line);
    const YAML::Node& value = child.second;
    if (value.IsMap()) {
      FlattenNode(value, entry.key + ".", name, entries);
      continue;
    }
    if (value.IsSequence()) {
      entry.is_sequence = true;
      for (const auto& item : value) {
        if (!item.IsScalar()) {
          throw SettingsError(FileLocation(name, entry.line) + ": key '" + entry.key +
                              "': nested lists are not supported");
        }
        entry.items.push_back(item.Scalar());
      }
    } else {
      entry.items.push_back(value.IsNull() ? std::string() : value.Scalar());
    }
    entries->push_back(std::move(entry));
  }
}

}  // namespace

SettingsFile SettingsFile::Load(const std::string& path) {
  std::string text;
  try {
    text = ReadTextFile(path);
  } catch (const FileError& error) {
    throw SettingsError(std::string("settings: ") + error.what());
  }
  return Parse(text, path);
}

SettingsFile SettingsFile::Parse(const std::string& text, const std::string& name) {
  SettingsFile file;
  file.name_ = name;
  YAML::Node root;
  try {
    root = YAML::Load(NormalizeOpenCvYaml(text));
  } catch (const YAML::Exception& error) {
    throw SettingsError(FileLocation(name, error.mark.line + 1) + ": not valid YAML: " + error.msg);
  }
  if (root.IsNull()) return file;
  if (!root.IsMap()) {
    throw SettingsError(name + ": expected a map of settings keys at the top level");
  }
  std::vector<FlatEntry> entries;
  FlattenNode(root, "", name, &entries);
  for (FlatEntry& entry : entries) {
    // "Camera: {fx: 1}" and "Camera.fx: 2" flatten to one key; so do two equal keys in one
    // map, which YAML parsers resolve differently (first or last wins). Either way one of
    // the two values would be dropped without a word.
    const auto [it, inserted] = file.values_.try_emplace(entry.key);
    if (!inserted) throw KeySetTwice(name, entry.key, it->second.line, entry.line);
    Value& value = it->second;
    value.items = std::move(entry.items);
    value.is_sequence = entry.is_sequence;
    value.line = entry.line;
  }
  return file;
}

int SettingsFile::LineOf(const std::string& key) const {
  const auto it = values_.find(key);
  return it == values_.end() ? 0 : it->second.line;
}

std::string SettingsFile::Describe(const std::string& key, const std::string& message) const {
  const int line = LineOf(key);
  const std::string where = line > 0 ? FileLocation(name_, line) : name_;
  return where + ": key '" + key + "': " + message;
}

void SettingsFile::Fail(const std::string& key, const std::string& message) const {
  throw SettingsError(Describe(key, message));
}

const SettingsFile::Value* SettingsFile::Find(const std::string& key, bool expect_sequence) const {
  const auto it = values_.find(key);
  if (it == values_.end()) return nullptr;
  read_.insert(key);
  if (it->second.is_sequence != expect_sequence) {
    Fail(key, expect_sequence ? "expected a list like [1, 2, 3]" : "expected a single value");
  }
  return &it->second;
}

bool SettingsFile::Read(const std::string& key, double* value) const {
  const Value* found = Find(key, false);
  if (found == nullptr) return false;
  if (!ParseDouble(found->items[0], value)) {
    Fail(key, "expected a number, got '" + found->items[0] + "'");
  }
  return true;
}

bool SettingsFile::Read(const std::string& key, int* value) const {
  const Value* found = Find(key, false);
  if (found == nullptr) return false;
  long long parsed = 0;
  if (!ParseInteger(found->items[0], &parsed) || parsed < INT32_MIN || parsed > INT32_MAX) {
    Fail(key, "expected an integer, got '" + found->items[0] + "'");
  }
  *value = static_cast<int>(parsed);
  return true;
}

bool SettingsFile::Read(const std::string& key, std::uint64_t* value) const {
  const Value* found = Find(key, false);
  if (found == nullptr) return false;
  long long parsed = 0;
  if (!ParseInteger(found->items[0], &parsed) || parsed < 0) {
    Fail(key, "expected a non-negative integer, got '" + found->items[0] + "'");
  }
  *value = static_cast<std::uint64_t>(parsed);
  return true;
}

bool SettingsFile::Read(const std::string& key, bool* value) const {
  const Value* found = Find(key, false);
  if (found == nullptr) return false;
  const std::string text = Lowercase(found->items[0]);
  if (text == "true" || text == "yes" || text == "on" || text == "1") {
    *value = true;
  } else if (text == "false" || text == "no" || text == "off" || text == "0") {
    *value = false;
  } else {
    Fail(key, "expected true/false (or 1/0), got '" + found->items[0] + "'");
  }
  return true;
}

bool SettingsFile::Read(const std::string& key, std::string* value) const {
  const Value* found = Find(key, false);
  if (found == nullptr) return false;
  *value = found->items[0];
  return true;
}

bool SettingsFile::Read(const std::string& key, std::vector<double>* value) const {
  const Value* found = Find(key, true);
  if (found == nullptr) return false;
  std::vector<double> parsed(found->items.size());
  for (size_t i = 0; i < parsed.size(); ++i) {
    if (!ParseDouble(found->items[i], &parsed[i])) {
      Fail(key, "item " + std::to_string(i) + ": expected a number, got '" + found->items[i] + "'");
    }
  }
  *value = std::move(parsed);
  return true;
}

std::vector<std::string> SettingsFile::KeysUnder(const std::string& prefix) const {
  std::vector<std::pair<int, std::string>> found;
  for (auto it = values_.lower_bound(prefix); it != values_.end(); ++it) {
    if (it->first.compare(0, prefix.size(), prefix) != 0) break;
    found.emplace_back(it->second.line, it->first);
  }
  std::sort(found.begin(), found.end());
  std::vector<std::string> keys;
  for (auto& entry : found) keys.push_back(std::move(entry.second));
  return keys;
}

std::vector<std::string> SettingsFile::UnreadKeys() const {
  std::vector<std::pair<int, std::string>> unread;
  for (const auto& [key, value] : values_) {
    if (read_.count(key) == 0) unread.emplace_back(value.line, key);
  }
  std::sort(unread.begin(), unread.end());
  std::vector<std::string> keys;
  for (auto& entry : unread) keys.push_back(std::move(entry.second));
  return keys;
}

}  // namespace ocg
