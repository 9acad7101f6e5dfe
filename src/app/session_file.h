#pragma once
// The first part of a map file's payload (docs/sessions.md): what the sessions that made
// the map ran with, read before the SLAM map so that a map made with another camera, ORB
// pyramid or vocabulary is refused before any long work.

#include <cstdint>
#include <iosfwd>
#include <string>

#include "ocg/app/settings.h"
#include "ocg/features/vocabulary.h"

namespace ocg::app_detail {

inline constexpr const char* kMapFileKind = "ocg_slam session map";
// 1: the first format (SLAM map, object map with sessions, OCG).
// 2: the object layer's part ends with the change log as the last session revised it
// (moves, additions and reasons of earlier sessions; ObjectLayerCounters::change_log).
// 3: then the colour signature of each map object's sightings (ObjectSighting::colour).
// 4: the session record ends with what the keyframes were made with besides the camera
// (the ORB pyramid and feature count, the vocabulary's fingerprint) and the keyframe count.
// 5: the SLAM map holds the whole atlas (every map, each keyframe's and point's map, the
// current map and the merges; slam/map_file.h MapFileFormat::kAtlas), and the record's
// keyframe count is the atlas's. Files before version 5 hold one map, loaded as map 0.
// Version 1 files are still read: without that log, earlier sessions' changes are the
// object map's own (their moves show as removals). Version 1 and 2 files have no colours:
// a later session pairs their objects without them. Files before version 4 take their ORB
// settings from the settings text they saved (OrbOfOlderFile) and check the vocabulary's
// word count alone.
// 6: the object layer ends with each map object's estimate bookkeeping
// (Objects.reestimate_share); older files load with none waiting.
inline constexpr std::uint32_t kMapFileVersion = 6;
inline constexpr std::uint32_t kOldestMapFileVersion = 1;

struct SessionRecord {
  std::string settings_source;  // the settings file of the last session
  std::string settings_text;    // its content ("" when it was not a file)
  PinholeCamera camera;         // intrinsics, distortion and image size
  std::uint64_t vocabulary_words = 0;
  std::string vocabulary_file;
  int sessions = 0;         // sessions the map holds
  std::int64_t frames = 0;  // frames given to them all
  bool has_objects = false;
  // Version 4 on. Keypoints carry their pyramid level (octave), and map points their
  // scale-invariance distances from it: a map continues only with the same levels and
  // scale factor. The feature count is recorded, not checked (keyframes with any number
  // of features live together).
  OrbExtractorOptions orb;
  // VocabularyFingerprint of the vocabulary; 0: not recorded (files before version 4).
  std::uint64_t vocabulary_fingerprint = 0;
  std::uint64_t keyframes = 0;  // live keyframes in the SLAM map (version 5: its every map)
};

// file_version: this build's; an older one writes that version's fields alone (for tests
// of older files).
void SaveSessionRecord(const SessionRecord& record, std::ostream& out,
                       std::uint32_t file_version = kMapFileVersion);
// file_version: the map file's. Throws std::runtime_error (cereal::Exception is one) when
// the stream ends early.
SessionRecord LoadSessionRecord(std::istream& in, std::uint32_t file_version = kMapFileVersion);

// A 64-bit hash of everything that decides a vocabulary's words and weights (tree shape,
// every node's descriptor, weight and leaf flag): two vocabularies of the same size but
// other words have different fingerprints.
std::uint64_t VocabularyFingerprint(const Vocabulary& vocabulary);

// Relocalization in a map needs the camera it was made with: throws MapFileError naming the
// map file and the settings file when the intrinsics, distortion or image size differ.
void CheckSameCamera(const SessionRecord& record, const Settings& settings,
                     const std::string& map_path);
// The map's keypoints lie on the pyramid it was made with: throws MapFileError naming the
// map file, the key (ORBextractor.nLevels, ORBextractor.scaleFactor), the map's value and
// the settings' value when they differ.
void CheckSameOrbPyramid(const SessionRecord& record, const Settings& settings,
                         const std::string& map_path);
// The map's BoW vectors index the words of the vocabulary it was made with: throws
// MapFileError naming both vocabulary files when the word count or (version 4 on) the
// fingerprint differs.
void CheckSameVocabulary(const SessionRecord& record, const Vocabulary& vocabulary,
                         const std::string& vocabulary_file, const std::string& map_path);
// A map with no keyframe (its sessions never initialized) holds no place to relocalize
// in: throws MapFileError "the map is empty" naming the file.
void CheckNotEmpty(std::uint64_t keyframes, const std::string& map_path);

}  // namespace ocg::app_detail
