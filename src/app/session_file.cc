#include "session_file.h"

#include <spdlog/spdlog.h>

#include <cereal/archives/binary.hpp>
#include <cereal/types/string.hpp>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <istream>
#include <ostream>
#include <sstream>

#include "ocg/core/map_file.h"
#include "ocg/core/settings_file.h"

namespace ocg::app_detail {
namespace {

template <class Archive, class Record>
void Fields(Archive& archive, Record& record, std::uint32_t file_version) {
  auto& camera = record.camera;
  archive(record.settings_source, record.settings_text, camera.fx, camera.fy, camera.cx, camera.cy,
          camera.k1, camera.k2, camera.k3, camera.p1, camera.p2, camera.width, camera.height,
          record.vocabulary_words, record.vocabulary_file, record.sessions, record.frames,
          record.has_objects);
  if (file_version >= 4) {
    archive(record.orb.levels, record.orb.scale_factor, record.orb.features,
            record.vocabulary_fingerprint, record.keyframes);
  }
}

// Files before version 4 did not record the ORB settings, but every version saved the
// settings text its keyframes were made with: its ORBextractor keys, or the defaults
// when it gives none (settings made in code, not read from a file).
OrbExtractorOptions OrbOfOlderFile(const SessionRecord& record) {
  OrbExtractorOptions orb;
  if (record.settings_text.empty()) return orb;
  try {
    ReadSettings(SettingsFile::Parse(record.settings_text, record.settings_source), &orb);
  } catch (const std::exception& error) {
    spdlog::warn(
        "the settings saved in the map file cannot be read again ({}); taking the "
        "default ORB pyramid for its keyframes",
        error.what());
  }
  return orb;
}

std::string Describe(const PinholeCamera& camera) {
  std::ostringstream text;
  text << camera.width << "x" << camera.height << " fx " << camera.fx << " fy " << camera.fy
       << " cx " << camera.cx << " cy " << camera.cy << " k1 " << camera.k1 << " k2 " << camera.k2
       << " k3 " << camera.k3 << " p1 " << camera.p1 << " p2 " << camera.p2;
  return text.str();
}

std::string Number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", value);
  return text;
}

std::string Hex(std::uint64_t value) {
  char text[17];
  std::snprintf(text, sizeof text, "%016" PRIx64, value);
  return text;
}

// FNV-1a's step over 64-bit values (as PayloadChecksum), fed field by field.
class Fingerprint {
 public:
  void Add(std::uint64_t value) { hash_ = (hash_ ^ value) * 0x100000001b3ull; }
  void Add(double value) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &value, sizeof bits);
    Add(bits);
  }
  std::uint64_t hash() const { return hash_; }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ull;
};

}  // namespace

void SaveSessionRecord(const SessionRecord& record, std::ostream& out, std::uint32_t file_version) {
  cereal::BinaryOutputArchive archive(out);
  Fields(archive, record, file_version);
}

SessionRecord LoadSessionRecord(std::istream& in, std::uint32_t file_version) {
  cereal::BinaryInputArchive archive(in);
  SessionRecord record;
  Fields(archive, record, file_version);
  if (file_version < 4) record.orb = OrbOfOlderFile(record);
  return record;
}

std::uint64_t VocabularyFingerprint(const Vocabulary& vocabulary) {
  Fingerprint fingerprint;
  fingerprint.Add(static_cast<std::uint64_t>(vocabulary.branching()));
  fingerprint.Add(static_cast<std::uint64_t>(vocabulary.depth()));
  fingerprint.Add(static_cast<std::uint64_t>(vocabulary.NodeCount()));
  for (NodeId node = 0; node < vocabulary.NodeCount(); ++node) {
    fingerprint.Add(static_cast<std::uint64_t>(vocabulary.Parent(node)));
    for (const std::uint64_t word : vocabulary.NodeDescriptor(node)) fingerprint.Add(word);
    fingerprint.Add(vocabulary.Weight(node));
    fingerprint.Add(static_cast<std::uint64_t>(vocabulary.IsLeaf(node)));
  }
  return fingerprint.hash();
}

void CheckSameCamera(const SessionRecord& record, const Settings& settings,
                     const std::string& map_path) {
  const std::string saved = Describe(record.camera);
  const std::string given = Describe(settings.camera.model);
  if (saved == given) return;
  throw MapFileError("map file '" + map_path + "' was made with the camera " + saved + " ('" +
                     record.settings_source + "'), but '" + settings.source + "' gives " + given +
                     ": a map can only be continued with the camera it was made with");
}

void CheckSameOrbPyramid(const SessionRecord& record, const Settings& settings,
                         const std::string& map_path) {
  const auto refuse = [&](const std::string& key, const std::string& saved,
                          const std::string& given) {
    throw MapFileError("map file '" + map_path + "' was made with " + key + ": " + saved + " ('" +
                       record.settings_source + "'), but '" + settings.source + "' gives " + key +
                       ": " + given +
                       ": the map's keypoints lie on the pyramid levels it was made with, so a "
                       "map can only be continued with the same ORBextractor.nLevels and "
                       "ORBextractor.scaleFactor");
  };
  if (record.orb.levels != settings.orb.levels)
    refuse("ORBextractor.nLevels", std::to_string(record.orb.levels),
           std::to_string(settings.orb.levels));
  if (record.orb.scale_factor != settings.orb.scale_factor)
    refuse("ORBextractor.scaleFactor", Number(record.orb.scale_factor),
           Number(settings.orb.scale_factor));
}

void CheckSameVocabulary(const SessionRecord& record, const Vocabulary& vocabulary,
                         const std::string& vocabulary_file, const std::string& map_path) {
  const std::string need = ": its BoW vectors need the vocabulary they were made with";
  if (record.vocabulary_words != vocabulary.WordCount()) {
    throw MapFileError("map file '" + map_path + "' was made with a vocabulary of " +
                       std::to_string(record.vocabulary_words) + " words ('" +
                       record.vocabulary_file + "'), but '" + vocabulary_file + "' has " +
                       std::to_string(vocabulary.WordCount()) + need);
  }
  if (record.vocabulary_fingerprint == 0) {
    spdlog::warn(
        "map file '{}' was written by an older build that did not record its vocabulary's "
        "fingerprint: only the word count ({}) was checked; '{}' must be the vocabulary it was "
        "made with ('{}')",
        map_path, record.vocabulary_words, vocabulary_file, record.vocabulary_file);
    return;
  }
  const std::uint64_t fingerprint = VocabularyFingerprint(vocabulary);
  if (fingerprint == record.vocabulary_fingerprint) return;
  throw MapFileError("map file '" + map_path + "' was made with another vocabulary: '" +
                     record.vocabulary_file + "' (fingerprint " +
                     Hex(record.vocabulary_fingerprint) + "), but '" + vocabulary_file +
                     "' has other words (fingerprint " + Hex(fingerprint) + ", the same count " +
                     std::to_string(vocabulary.WordCount()) + ")" + need);
}

void CheckNotEmpty(std::uint64_t keyframes, const std::string& map_path) {
  if (keyframes > 0) return;
  throw MapFileError("map file '" + map_path +
                     "': the map is empty (no keyframe: the sessions that made it never "
                     "initialized), so there is nothing to relocalize in; make the map again "
                     "from a sequence that initializes");
}

}  // namespace ocg::app_detail
