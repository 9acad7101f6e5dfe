#pragma once
// A settings file: our own YAML files and ORB-SLAM2's OpenCV-YAML settings files
// (first line "%YAML:1.0", flat dotted keys such as "Camera.fx") read unchanged.
//
// Nested maps are flattened to dotted keys, so "OCG: {tau_doubt: 50}" and
// "OCG.tau_doubt: 50" are the same key. The file remembers which keys were read, so the
// loader can warn about the rest (typos, options of another program). A key set twice
// (twice in one map, or nested and dotted) is an error naming both lines.

#include <cstdint>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace ocg {

class SettingsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class SettingsFile {
 public:
  // Throws SettingsError naming the file (and line) when it is missing, not YAML, or sets
  // a key twice.
  static SettingsFile Load(const std::string& path);
  // Parses text; name stands for the file in messages.
  static SettingsFile Parse(const std::string& text, const std::string& name);

  const std::string& name() const { return name_; }
  bool Has(const std::string& key) const { return values_.count(key) > 0; }
  // 1-based line of the key in the file, 0 when absent.
  int LineOf(const std::string& key) const;

  // Each Read leaves *value untouched and returns false when the key is absent, and
  // throws SettingsError naming file, line and key when the value has the wrong type.
  bool Read(const std::string& key, double* value) const;
  bool Read(const std::string& key, int* value) const;
  bool Read(const std::string& key, std::uint64_t* value) const;
  bool Read(const std::string& key, bool* value) const;
  bool Read(const std::string& key, std::string* value) const;
  bool Read(const std::string& key, std::vector<double>* value) const;

  // Sets key to value, a YAML scalar or flow list ("false", "0.5", "[0, -1, 0]", "'a b'"),
  // over the file's value if it has one (a new key goes after the file's keys). Messages
  // about the key then name origin (e.g. "--set OCG.mode") instead of a line. Throws
  // SettingsError naming origin when value is not a scalar or a list of scalars.
  void Set(const std::string& key, const std::string& value, const std::string& origin);
  // The file as flat YAML, one "key: value" line per key in file order (Set's new keys
  // last), after a comment line "# comment". Read back, every key gives the same text.
  std::string ToFlatYaml(const std::string& comment) const;

  // Keys that start with prefix (e.g. "Camera."), in file order.
  std::vector<std::string> KeysUnder(const std::string& prefix) const;
  // Keys present in the file that no Read asked for, in file order.
  std::vector<std::string> UnreadKeys() const;
  // Every key a Read asked for, present in the file or not, in the order first asked: after
  // every module has read its options, the keys the program knows.
  std::vector<std::string> AskedKeys() const;
  // Where the key's value comes from: "file:line", Set's origin, or the file's name.
  std::string Where(const std::string& key) const;
  // "file:line: key 'K': message".
  std::string Describe(const std::string& key, const std::string& message) const;

 private:
  struct Value {
    std::vector<std::string> items;  // one item for a scalar
    bool is_sequence = false;
    int line = 0;
    int order = 0;       // position in the file; Set's new keys after the file's
    std::string origin;  // Set's origin, "" for a value from the file
  };
  std::vector<std::string> KeysInOrder(const std::vector<std::string>& keys) const;
  const Value* Find(const std::string& key, bool expect_sequence) const;
  [[noreturn]] void Fail(const std::string& key, const std::string& message) const;

  std::string name_;
  std::map<std::string, Value> values_;
  mutable std::set<std::string> read_;
  mutable std::vector<std::string> asked_;
  mutable std::set<std::string> asked_set_;
};

// The known key a misspelt key most likely meant ("Camera1.Fx" -> "Camera1.fx",
// "LoopClosing.enabeld" -> "LoopClosing.enabled"): equal but for case, else within a few
// edits (letters swapped, missing, extra or wrong); "" when no known key is that close.
std::string ClosestKey(const std::string& key, const std::vector<std::string>& known);

}  // namespace ocg
