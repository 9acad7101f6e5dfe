#pragma once
// The object layer's part of a map file (docs/sessions.md): the object map (objects with
// the sightings they keep (SightingHistory) and their sessions, candidates, the change log, id
// counters), the OCG (graph, every object's state, doubt and geometry, removals) and the mapper's
// counters, as a cereal binary archive written into the caller's stream. The modules' options are
// not saved here: they come from the settings (saved by the caller).

#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>

#include "ocg/objects/object_mapper.h"

namespace ocg::app_detail {

// What the object layer counts besides the mapper: OCG keyframe ids continue after
// keyframes, and the OCG's keyframe interval keeps its phase.
struct ObjectLayerCounters {
  std::int64_t keyframes = 0;       // OCG keyframes given
  std::int64_t tracked_frames = 0;  // frames with a pose given
  // changes.json as the session that saved revised it, without "time" (version 2 on;
  // none from a version 1 file).
  std::optional<std::string> change_log;
};

// After ObjectMapper::Finish() (the OCG idle).
void SaveObjectMapper(const ObjectMapper& mapper, const ObjectLayerCounters& counters,
                      std::ostream& out);
// Into a mapper made from the settings, before its first frame; file_version: the map
// file's (kMapFileVersion or older). Throws std::runtime_error (cereal::Exception is one)
// when the stream ends early.
ObjectLayerCounters LoadObjectMapper(std::istream& in, ObjectMapper* mapper,
                                     std::uint32_t file_version);

}  // namespace ocg::app_detail
