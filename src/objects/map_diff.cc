#include "ocg/objects/map_diff.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>
#include <tuple>

#include "ocg/core/coco.h"
#include "ocg/core/file_io.h"
#include "ocg/io/change_entries.h"
#include "ocg/io/text_lines.h"
#include "ocg/objects/cuboid_json.h"

namespace ocg {
namespace {

namespace fs = std::filesystem;

// A candidate pair: its distance in units of the larger extent, then the ids, so the
// greedy choice is the same whatever order the inputs come in.
struct Candidate {
  double relative = 0.0;
  std::size_t a = 0, b = 0;
  ObjectId id_a = 0, id_b = 0;
  bool operator<(const Candidate& other) const {
    return std::tie(relative, id_a, id_b) < std::tie(other.relative, other.id_a, other.id_b);
  }
};

// Greedy one-to-one pairing of the candidates, nearest first.
std::vector<Candidate> PairNearest(std::vector<Candidate> candidates) {
  std::sort(candidates.begin(), candidates.end());
  std::set<std::size_t> used_a, used_b;
  std::vector<Candidate> pairs;
  for (const Candidate& candidate : candidates) {
    if (used_a.count(candidate.a) > 0 || used_b.count(candidate.b) > 0) continue;
    used_a.insert(candidate.a);
    used_b.insert(candidate.b);
    pairs.push_back(candidate);
  }
  return pairs;
}

MoveLink Link(const ObjectRecord& from, const ObjectRecord& to) {
  return {from, to, (from.cuboid.centre - to.cuboid.centre).norm()};
}

nlohmann::json RecordJson(const ObjectRecord& record) {
  return {{"id", record.id},
          {"class_id", record.class_id},
          {"class", CocoClassName(record.class_id)},
          {"cuboid", CuboidJson(record.cuboid)}};
}

nlohmann::json LinkJson(const MoveLink& link) {
  return {{"from", RecordJson(link.from)},
          {"to", RecordJson(link.to)},
          {"distance", link.distance},
          {"recorded", link.recorded}};
}

std::string ObjectsJsonPath(const std::string& path) {
  return fs::is_directory(path) ? path + "/objects.json" : path;
}

// run.json's session section and command, and changes.json's moves, of a run folder.
RunRecord ReadRunRecord(const std::string& folder) {
  RunRecord record;
  record.folder = folder;
  const std::string run_path = folder + "/run.json";
  try {
    const nlohmann::json run = nlohmann::json::parse(ReadTextFile(run_path));
    record.poses_given = run.value("command", "") == "objects";
    if (run.contains("session") && run.at("session").is_object()) {
      const nlohmann::json& session = run.at("session");
      record.session = session.value("index", 0);
      const auto path = [&session](const char* key) {
        return session.contains(key) && session.at(key).is_string()
                   ? session.at(key).get<std::string>()
                   : std::string();
      };
      record.map_loaded = path("map_loaded");
      record.map_saved = path("map_saved");
    }
  } catch (const nlohmann::json::exception& error) {
    throw ParseError(run_path + ": " + error.what());
  }
  const std::string changes_path = folder + "/changes.json";
  if (!fs::exists(changes_path)) return record;
  try {
    const nlohmann::json changes = nlohmann::json::parse(ReadTextFile(changes_path));
    const nlohmann::json& list = changes.at("changes");
    const std::vector<bool> standing = StandingRemovals(list);
    for (std::size_t i = 0; i < list.size(); ++i) {
      if (!standing[i] || list[i].at("type") != "moved") continue;
      record.moves.push_back({list[i].at("object_id").get<ObjectId>(),
                              list[i].at("to").at("object_id").get<ObjectId>(),
                              list[i].value("session", 0)});
    }
  } catch (const nlohmann::json::exception& error) {
    throw ParseError(changes_path + ": " + error.what());
  }
  return record;
}

}  // namespace

void MoveLinkOptions::Check() const {
  if (!(search_factor > 0)) throw std::invalid_argument("moves.search_factor must be positive");
  if (!(same_place_factor >= 0 && same_place_factor < search_factor))
    throw std::invalid_argument("moves.same_place_factor must be in [0, search_factor)");
}

void MapDiffOptions::Check() const {
  if (!(same_place_factor > 0)) throw std::invalid_argument("same_place_factor must be positive");
  moves.Check();
}

double LargerExtent(const ObjectRecord& a, const ObjectRecord& b) {
  return std::max({a.cuboid.size.maxCoeff(), b.cuboid.size.maxCoeff(), 1e-6});
}

double RelativeDistance(const ObjectRecord& a, const ObjectRecord& b) {
  return (a.cuboid.centre - b.cuboid.centre).norm() / LargerExtent(a, b);
}

std::vector<MoveLink> LinkMoves(const std::vector<ObjectRecord>& removed,
                                const std::vector<ObjectRecord>& appeared,
                                const MoveLinkOptions& options) {
  options.Check();
  std::vector<Candidate> candidates;
  for (std::size_t r = 0; r < removed.size(); ++r) {
    for (std::size_t a = 0; a < appeared.size(); ++a) {
      const ObjectRecord& from = removed[r];
      const ObjectRecord& to = appeared[a];
      if (from.class_id != to.class_id) continue;
      const double relative = RelativeDistance(from, to);
      if (relative <= options.same_place_factor || relative > options.search_factor) continue;
      candidates.push_back({relative, r, a, from.id, to.id});
    }
  }
  std::vector<MoveLink> moves;
  for (const Candidate& pair : PairNearest(std::move(candidates)))
    moves.push_back(Link(removed[pair.a], appeared[pair.b]));
  return moves;
}

MapDiff DiffObjectMaps(const std::vector<ObjectRecord>& before,
                       const std::vector<ObjectRecord>& after, const MapDiffOptions& options,
                       const std::vector<RecordedMove>& recorded) {
  options.Check();
  MapDiff diff;
  std::vector<bool> kept_before(before.size(), false), kept_after(after.size(), false);
  const auto index_of = [](const std::vector<ObjectRecord>& records, ObjectId id) {
    const auto found = std::find_if(records.begin(), records.end(),
                                    [id](const ObjectRecord& record) { return record.id == id; });
    return found == records.end() ? records.size()
                                  : static_cast<std::size_t>(found - records.begin());
  };
  for (const RecordedMove& move : recorded) {
    const std::size_t b = index_of(before, move.from), a = index_of(after, move.to);
    if (b == before.size() || a == after.size() || kept_before[b] || kept_after[a]) continue;
    kept_before[b] = kept_after[a] = true;
    diff.moved.push_back(Link(before[b], after[a]));
    diff.moved.back().recorded = true;
  }
  // Same place: equal ids rank before any other pair (relative - 1 < 0).
  std::vector<Candidate> candidates;
  for (std::size_t b = 0; b < before.size(); ++b) {
    for (std::size_t a = 0; a < after.size(); ++a) {
      if (kept_before[b] || kept_after[a] || before[b].class_id != after[a].class_id) continue;
      const double relative = RelativeDistance(before[b], after[a]);
      if (relative > options.same_place_factor) continue;
      const double rank = before[b].id == after[a].id ? relative - 1.0 : relative;
      candidates.push_back({rank, b, a, before[b].id, after[a].id});
    }
  }
  for (const Candidate& pair : PairNearest(std::move(candidates))) {
    kept_before[pair.a] = kept_after[pair.b] = true;
    diff.unchanged.push_back(Link(before[pair.a], after[pair.b]));
  }
  std::vector<ObjectRecord> gone, appeared;
  for (std::size_t b = 0; b < before.size(); ++b)
    if (!kept_before[b]) gone.push_back(before[b]);
  for (std::size_t a = 0; a < after.size(); ++a)
    if (!kept_after[a]) appeared.push_back(after[a]);
  MoveLinkOptions moves = options.moves;
  moves.same_place_factor = std::min(moves.same_place_factor, options.same_place_factor);
  std::set<ObjectId> moved_from, moved_to;
  for (const MoveLink& link : LinkMoves(gone, appeared, moves)) {
    moved_from.insert(link.from.id);
    moved_to.insert(link.to.id);
    diff.moved.push_back(link);
  }
  for (const ObjectRecord& record : gone)
    if (moved_from.count(record.id) == 0) diff.removed.push_back(record);
  for (const ObjectRecord& record : appeared)
    if (moved_to.count(record.id) == 0) diff.added.push_back(record);
  return diff;
}

std::string MapDiffJson(const MapDiff& diff, const std::string& distance_unit,
                        const std::string& frame) {
  nlohmann::json removed = nlohmann::json::array(), added = nlohmann::json::array(),
                 moved = nlohmann::json::array(), unchanged = nlohmann::json::array();
  for (const ObjectRecord& record : diff.removed) removed.push_back(RecordJson(record));
  for (const ObjectRecord& record : diff.added) added.push_back(RecordJson(record));
  for (const MoveLink& link : diff.moved) moved.push_back(LinkJson(link));
  for (const MoveLink& link : diff.unchanged) unchanged.push_back(LinkJson(link));
  return nlohmann::json({{"format", "ocg-map-diff"},
                         {"version", 1},
                         {"counts",
                          {{"removed", diff.removed.size()},
                           {"added", diff.added.size()},
                           {"moved", diff.moved.size()},
                           {"unchanged", diff.unchanged.size()}}},
                         {"distance_unit", distance_unit},
                         {"frame", frame},
                         {"removed", removed},
                         {"added", added},
                         {"moved", moved},
                         {"unchanged", unchanged}})
             .dump(1) +
         "\n";
}

bool ObjectsJsonReader::Accepts(const std::string& path) const {
  const std::string file = ObjectsJsonPath(path);
  std::ifstream stream(file);
  char start[512] = {};
  stream.read(start, sizeof(start) - 1);
  return std::string(start).find("\"ocg-objects\"") != std::string::npos;
}

SavedObjectMap ParseObjectsJson(const std::string& text, const std::string& name) {
  SavedObjectMap map;
  try {
    const nlohmann::json root = nlohmann::json::parse(text);
    if (root.value("format", "") != "ocg-objects")
      throw std::invalid_argument("\"format\" is not \"ocg-objects\"");
    if (root.contains("up")) map.up = VectorFromJson(root.at("up"));
    for (const nlohmann::json& entry : root.at("objects")) {
      ObjectRecord record;
      record.id = entry.at("id").get<ObjectId>();
      record.class_id = entry.at("class_id").get<int>();
      record.cuboid = CuboidFromJson(entry.at("cuboid"));
      record.first_seen = entry.value("first_seen", 0.0);
      record.first_session = entry.value("first_session", 0);
      record.observations = entry.value("observations", 0);
      record.last_seen = entry.value("last_seen", 0.0);
      if (entry.contains("state") && !entry.at("state").is_null())
        record.state = entry.at("state").get<int>();
      map.objects.push_back(record);
    }
  } catch (const std::exception& error) {
    throw ParseError(name + ": " + error.what() +
                     " (expected objects.json as ocg_slam writes it: {\"format\": "
                     "\"ocg-objects\", \"objects\": [{\"id\", \"class_id\", \"cuboid\": "
                     "{\"centre\", \"size\", \"yaw\"}}]})");
  }
  return map;
}

SavedObjectMap ObjectsJsonReader::Read(const std::string& path) const {
  const std::string file = ObjectsJsonPath(path);
  SavedObjectMap map = ParseObjectsJson(ReadTextFile(file), file);
  if (fs::is_directory(path) && fs::exists(path + "/run.json")) map.run = ReadRunRecord(path);
  return map;
}

bool ContinuesMapOf(const RunRecord& later, const RunRecord& earlier) {
  if (later.map_loaded.empty() || earlier.map_saved.empty()) return false;
  if (later.map_loaded == earlier.map_saved) return true;
  std::error_code error;
  return fs::equivalent(later.map_loaded, earlier.map_saved, error) && !error;
}

std::vector<RecordedMove> MovesSince(const SavedObjectMap& before, const SavedObjectMap& after) {
  std::vector<RecordedMove> moves;
  if (!before.run || !after.run || !ContinuesMapOf(*after.run, *before.run)) return moves;
  for (const RecordedMove& move : after.run->moves) {
    if (move.session > before.run->session) moves.push_back(move);
  }
  return moves;
}

std::string DistanceUnit(const SavedObjectMap& before, const SavedObjectMap& after) {
  return before.run && after.run && before.run->poses_given && after.run->poses_given ? "m"
                                                                                      : "map units";
}

std::vector<std::unique_ptr<ObjectMapReader>> ObjectMapReaders() {
  std::vector<std::unique_ptr<ObjectMapReader>> readers;
  readers.push_back(std::make_unique<ObjectsJsonReader>());
  return readers;
}

SavedObjectMap ReadObjectMap(const std::string& path,
                             const std::vector<std::unique_ptr<ObjectMapReader>>& readers) {
  if (!fs::exists(path)) throw FileError("'" + path + "': no such file or folder");
  std::string kinds;
  for (const auto& reader : readers) {
    if (reader->Accepts(path)) return reader->Read(path);
    kinds += (kinds.empty() ? "" : ", ") + reader->Name();
  }
  throw FileError("'" + path + "' is not an object map this build reads (" + kinds +
                  ", or a run folder holding objects.json)");
}

}  // namespace ocg
