#pragma once
// The first part of a map file's payload (docs/sessions.md): what the sessions that made
// the map ran with, read before the SLAM map so that a map made with another camera or
// vocabulary is refused before any long work.

#include <cstdint>
#include <iosfwd>
#include <string>

#include "ocg/app/settings.h"

namespace ocg::app_detail {

inline constexpr const char* kMapFileKind = "ocg_slam session map";
// 1: the first format (SLAM map, object map with sessions, OCG).
// 2: the object layer's part ends with the change log as the last session revised it
// (moves, additions and reasons of earlier sessions; ObjectLayerCounters::change_log).
// 3: then the colour signature of each map object's sightings (ObjectSighting::colour).
// Version 1 files are still read: without that log, earlier sessions' changes are the
// object map's own (their moves show as removals). Version 1 and 2 files have no colours:
// a later session pairs their objects without them.
inline constexpr std::uint32_t kMapFileVersion = 3;
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
};

void SaveSessionRecord(const SessionRecord& record, std::ostream& out);
// Throws std::runtime_error (cereal::Exception is one) when the stream ends early.
SessionRecord LoadSessionRecord(std::istream& in);

// Relocalization in a map needs the camera it was made with: throws MapFileError naming the
// map file and the settings file when the intrinsics, distortion or image size differ.
void CheckSameCamera(const SessionRecord& record, const Settings& settings,
                     const std::string& map_path);

}  // namespace ocg::app_detail
