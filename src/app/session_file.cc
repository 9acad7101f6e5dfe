#include "session_file.h"

#include <cereal/archives/binary.hpp>
#include <cereal/types/string.hpp>
#include <istream>
#include <ostream>
#include <sstream>

#include "ocg/core/map_file.h"

namespace ocg::app_detail {
namespace {

template <class Archive, class Record>
void Fields(Archive& archive, Record& record) {
  auto& camera = record.camera;
  archive(record.settings_source, record.settings_text, camera.fx, camera.fy, camera.cx, camera.cy,
          camera.k1, camera.k2, camera.k3, camera.p1, camera.p2, camera.width, camera.height,
          record.vocabulary_words, record.vocabulary_file, record.sessions, record.frames,
          record.has_objects);
}

std::string Describe(const PinholeCamera& camera) {
  std::ostringstream text;
  text << camera.width << "x" << camera.height << " fx " << camera.fx << " fy " << camera.fy
       << " cx " << camera.cx << " cy " << camera.cy << " k1 " << camera.k1 << " k2 " << camera.k2
       << " k3 " << camera.k3 << " p1 " << camera.p1 << " p2 " << camera.p2;
  return text.str();
}

}  // namespace

void SaveSessionRecord(const SessionRecord& record, std::ostream& out) {
  cereal::BinaryOutputArchive archive(out);
  Fields(archive, record);
}

SessionRecord LoadSessionRecord(std::istream& in) {
  cereal::BinaryInputArchive archive(in);
  SessionRecord record;
  Fields(archive, record);
  return record;
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

}  // namespace ocg::app_detail
