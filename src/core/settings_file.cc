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
    value.order = static_cast<int>(file.values_.size()) - 1;
  }
  return file;
}

void SettingsFile::Set(const std::string& key, const std::string& text, const std::string& origin) {
  if (key.empty() || key.find_first_of(" \t:#") != std::string::npos) {
    throw SettingsError(origin + ": '" + key + "' is not a settings key (e.g. OCG.tau_doubt)");
  }
  YAML::Node node;
  try {
    node = YAML::Load(text);
  } catch (const YAML::Exception& error) {
    throw SettingsError(origin + ": value '" + text + "' is not a YAML value: " + error.msg);
  }
  Value value;
  value.origin = origin;
  if (node.IsSequence()) {
    value.is_sequence = true;
    for (const auto& item : node) {
      if (!item.IsScalar()) {
        throw SettingsError(origin + ": value '" + text + "': nested lists are not supported");
      }
      value.items.push_back(item.Scalar());
    }
  } else if (node.IsScalar() || node.IsNull()) {
    value.items.push_back(node.IsNull() ? std::string() : node.Scalar());
  } else {
    throw SettingsError(origin + ": value '" + text +
                        "': expected a value or a list of values, not a map");
  }
  const auto it = values_.find(key);
  value.order = it != values_.end() ? it->second.order : static_cast<int>(values_.size());
  values_[key] = std::move(value);
}

std::string SettingsFile::ToFlatYaml(const std::string& comment) const {
  std::vector<std::string> keys;
  for (const auto& entry : values_) keys.push_back(entry.first);
  YAML::Emitter out;
  out << YAML::BeginMap;
  for (const std::string& key : KeysInOrder(keys)) {
    const Value& value = values_.at(key);
    out << YAML::Key << key << YAML::Value;
    if (value.is_sequence) {
      out << YAML::Flow << YAML::BeginSeq;
      for (const std::string& item : value.items) out << item;
      out << YAML::EndSeq;
    } else {
      out << value.items[0];
    }
  }
  out << YAML::EndMap;
  std::string one_line = comment;
  std::replace(one_line.begin(), one_line.end(), '\n', ' ');
  return "# " + one_line + "\n" + out.c_str() + "\n";
}

std::vector<std::string> SettingsFile::KeysInOrder(const std::vector<std::string>& keys) const {
  std::vector<std::pair<int, std::string>> ordered;
  for (const std::string& key : keys) ordered.emplace_back(values_.at(key).order, key);
  std::sort(ordered.begin(), ordered.end());
  std::vector<std::string> result;
  for (auto& entry : ordered) result.push_back(std::move(entry.second));
  return result;
}

std::vector<std::string> SettingsFile::AskedKeys() const { return asked_; }

std::string SettingsFile::Where(const std::string& key) const {
  const auto it = values_.find(key);
  if (it == values_.end()) return name_;
  if (!it->second.origin.empty()) return it->second.origin;
  return FileLocation(name_, it->second.line);
}

int SettingsFile::LineOf(const std::string& key) const {
  const auto it = values_.find(key);
  return it == values_.end() ? 0 : it->second.line;
}

std::string SettingsFile::Describe(const std::string& key, const std::string& message) const {
  return Where(key) + ": key '" + key + "': " + message;
}

void SettingsFile::Fail(const std::string& key, const std::string& message) const {
  throw SettingsError(Describe(key, message));
}

const SettingsFile::Value* SettingsFile::Find(const std::string& key, bool expect_sequence) const {
  if (asked_set_.insert(key).second) asked_.push_back(key);
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
  std::vector<std::string> found;
  for (auto it = values_.lower_bound(prefix); it != values_.end(); ++it) {
    if (it->first.compare(0, prefix.size(), prefix) != 0) break;
    found.push_back(it->first);
  }
  return KeysInOrder(found);
}

std::vector<std::string> SettingsFile::UnreadKeys() const {
  std::vector<std::string> unread;
  for (const auto& entry : values_) {
    if (read_.count(entry.first) == 0) unread.push_back(entry.first);
  }
  return KeysInOrder(unread);
}

namespace {

// Edits (insert, delete, replace, or swap two neighbouring letters) from a to b.
std::size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t replace = d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, replace});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    }
  }
  return d[a.size()][b.size()];
}

}  // namespace

std::string ClosestKey(const std::string& key, const std::vector<std::string>& known) {
  const std::string lower = Lowercase(key);
  // A few edits, fewer for short keys: "fx" is not a misspelling of "cy".
  std::size_t best = std::max<std::size_t>(1, std::min<std::size_t>(3, key.size() / 6)) + 1;
  std::string closest;
  for (const std::string& candidate : known) {
    const std::string candidate_lower = Lowercase(candidate);
    if (candidate_lower == lower) return candidate;
    const std::size_t distance = EditDistance(lower, candidate_lower);
    if (distance < best) {
      best = distance;
      closest = candidate;
    }
  }
  return closest;
}

}  // namespace ocg
