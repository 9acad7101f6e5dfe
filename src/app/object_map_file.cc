#include "object_map_file.h"

#include <algorithm>
#include <cereal/archives/binary.hpp>
#include <cereal/types/array.hpp>
#include <cereal/types/map.hpp>
#include <cereal/types/optional.hpp>
#include <cereal/types/string.hpp>
#include <cereal/types/utility.hpp>
#include <cereal/types/vector.hpp>
#include <istream>
#include <ostream>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "ocg/core/cereal_types.h"
#include "ocg/ocg/observation.h"

namespace ocg {

template <class Archive>
void serialize(Archive& archive, Box2& box) {
  archive(box.x0, box.y0, box.x1, box.y1);
}
template <class Archive>
void serialize(Archive& archive, Cuboid& cuboid) {
  archive(cuboid.centre, cuboid.size, cuboid.yaw);
}
template <class Archive>
void serialize(Archive& archive, ObjectSighting& sighting) {
  archive(sighting.frame, sighting.T_cw, sighting.box, sighting.truncated, sighting.class_id,
          sighting.session);
}
// The kept sightings, as version 1 wrote every sighting; a history read back counts those
// alone (an object seen more than Objects.max_sightings times reports fewer observations).
template <class Archive>
void save(Archive& archive, const SightingHistory& history) {
  archive(history.kept());
}
template <class Archive>
void load(Archive& archive, SightingHistory& history) {
  std::vector<ObjectSighting> kept;
  archive(kept);
  history = SightingHistory(std::move(kept));
}
template <class Archive>
void serialize(Archive& archive, ObjectPoint& point) {
  archive(point.votes, point.position);
}
// As the std::map it holds: map files are the same as before the container counted its
// changes.
template <class Archive>
void save(Archive& archive, const ObjectPoints& points) {
  archive(points.container());
}
template <class Archive>
void load(Archive& archive, ObjectPoints& points) {
  ObjectPoints::Container kept;
  archive(kept);
  points = ObjectPoints(std::move(kept));
}
template <class Archive>
void serialize(Archive& archive, MapObject& object) {
  archive(object.id, object.class_id, object.sightings, object.cuboid, object.has_cuboid,
          object.yaw_from_points, object.first_frame, object.last_frame, object.first_timestamp,
          object.last_timestamp, object.keyframes_in_map, object.points);
}
template <class Archive>
void serialize(Archive& archive, ObjectChange& change) {
  archive(change.type, change.keyframe_id, change.timestamp, change.object_id, change.merged_into,
          change.class_id, change.cuboid, change.sightings, change.doubt, change.last_seen,
          change.session);
}
template <class Archive>
void serialize(Archive& archive, ObjectLayerStats& stats) {
  archive(stats.frames, stats.keyframes, stats.detections_used, stats.detections_matched,
          stats.objects_created, stats.objects_removed, stats.plane_inliers, stats.up);
}
template <class Archive>
void serialize(Archive& archive, ObjectGeometry& geometry) {
  archive(geometry.centroid, geometry.size, geometry.max_observed_distance,
          geometry.view_directions, geometry.detected_keyframes, geometry.missed_keyframes);
}
// The OCG's per-object values as its one field list orders them (the map file keeps those
// of objects not in the graph). A new field changes this layout: kMapFileVersion.
template <class Archive>
void serialize(Archive& archive, ObjectGeometryUpdate& update) {
  VisitObjectUpdateFields([&archive](const ObservationField&, auto& value) { archive(value); },
                          update);
}
template <class Archive>
void serialize(Archive& archive, StateAndDoubt& state) {
  archive(state.state, state.doubt);
}
template <class Archive>
void serialize(Archive& archive, RemovalEvent& event) {
  archive(event.keyframe_id, event.timestamp, event.object_id, event.class_id, event.centroid,
          event.doubt, event.reason);
}

// Friend of ObjectMap, ObjectMapper, OcgManager and ObjectChangeDetector: their state
// goes to map files from here alone, so those modules hold no serialization code.
struct MapFileAccess {
  template <class Archive, class Map>
  static void ObjectMapState(Archive& archive, Map& map) {
    archive(map.R_wg_, map.objects_, map.candidates_, map.observed_since_keyframe_,
            map.geometry_changed_, map.changes_, map.next_object_id_, map.next_candidate_id_);
    // Loaded: FollowMap indexes the points again.
    if constexpr (!std::is_const_v<Map>) map.point_index_valid_ = false;
  }

  template <class Archive, class Record>
  static void RecordState(Archive& archive, Record& record) {
    archive(record.state, record.rate, record.rate_keyframe, record.judged_by_geometry,
            record.class_id, record.geometry, record.observations, record.first_keyframe,
            record.last_observed_keyframe);
  }

  static void SaveDetector(cereal::BinaryOutputArchive& archive,
                           const ObjectChangeDetector& detector) {
    // The graph through its public interface: nodes, then each edge once.
    const ObjectCovisibilityGraph& graph = detector.graph_;
    const std::vector<ObjectId> nodes = graph.NodeIds();
    std::vector<std::pair<std::pair<ObjectId, ObjectId>, std::uint32_t>> edges;
    for (const ObjectId id : nodes) {
      for (const CovisibilityEdge& edge : graph.Neighbours(id)) {
        if (id < edge.neighbour) edges.push_back({{id, edge.neighbour}, edge.weight});
      }
    }
    archive(nodes, edges);
    archive(cereal::make_size_tag(static_cast<cereal::size_type>(detector.records_.size())));
    for (const ObjectId id : SortedKeys(detector.records_)) {
      archive(id);
      RecordState(archive, detector.records_.at(id));
    }
    // Unordered containers in id order: a loaded set iterates in another order than the
    // saved one did, so the same state would not give the same bytes.
    std::vector<std::pair<ObjectId, ObjectGeometryUpdate>> pending;
    for (const ObjectId id : SortedKeys(detector.pending_))
      pending.emplace_back(id, detector.pending_.at(id));
    archive(pending, Sorted(detector.active_), Sorted(detector.isolated_), detector.last_keyframe_,
            detector.any_keyframe_);
  }

  static void LoadDetector(cereal::BinaryInputArchive& archive, ObjectChangeDetector* detector) {
    std::vector<ObjectId> nodes;
    std::vector<std::pair<std::pair<ObjectId, ObjectId>, std::uint32_t>> edges;
    archive(nodes, edges);
    ObjectCovisibilityGraph graph;
    for (const ObjectId id : nodes) graph.AddNode(id);
    for (const auto& [pair, weight] : edges) graph.SetEdge(pair.first, pair.second, weight);
    detector->graph_ = std::move(graph);
    cereal::size_type count = 0;
    archive(cereal::make_size_tag(count));
    detector->records_.clear();
    for (cereal::size_type i = 0; i < count; ++i) {
      ObjectId id = 0;
      archive(id);
      RecordState(archive, detector->records_[id]);
    }
    std::vector<std::pair<ObjectId, ObjectGeometryUpdate>> pending;
    std::vector<ObjectId> active, isolated;
    archive(pending, active, isolated, detector->last_keyframe_, detector->any_keyframe_);
    detector->pending_ = {pending.begin(), pending.end()};
    detector->active_ = {active.begin(), active.end()};
    detector->isolated_ = {isolated.begin(), isolated.end()};
  }

  // The keys of an unordered map in id order, so that the same state gives the same bytes.
  template <class Records>
  static std::vector<ObjectId> SortedKeys(const Records& records) {
    std::vector<ObjectId> ids;
    ids.reserve(records.size());
    for (const auto& entry : records) ids.push_back(entry.first);
    std::sort(ids.begin(), ids.end());
    return ids;
  }
  static std::vector<ObjectId> Sorted(const std::unordered_set<ObjectId>& ids) {
    std::vector<ObjectId> sorted(ids.begin(), ids.end());
    std::sort(sorted.begin(), sorted.end());
    return sorted;
  }

  static void Save(const ObjectMapper& mapper, const app_detail::ObjectLayerCounters& counters,
                   std::ostream& out) {
    std::lock_guard<std::mutex> map_lock(mapper.map_mutex_);
    std::lock_guard<std::mutex> ocg_lock(mapper.manager_.state_mutex_);
    cereal::BinaryOutputArchive archive(out);
    archive(counters.keyframes, counters.tracked_frames);
    ObjectMapState(archive, mapper.map_);
    archive(mapper.stats_, mapper.observations_jsonl_.Text(), mapper.manager_.removals_);
    SaveDetector(archive, mapper.manager_.detector_);
    archive(counters.change_log.value_or(""));
    archive(SightingColours(mapper.map_));
    archive(EstimateBookkeeping(mapper.map_));
  }

  // A list read back with one entry per map object (id order) has as many as the map;
  // what: the list's name with its verb ("the sighting colours are").
  static void RequireOnePerObject(std::size_t entries, const ObjectMap& map, const char* what) {
    if (entries != map.objects_.size())
      throw std::runtime_error(std::string(what) + " for " + std::to_string(entries) +
                               " objects, the map holds " + std::to_string(map.objects_.size()));
  }

  // Version 6: per map object in id order, the changes waiting for an estimate and the
  // sightings its last estimate had (Objects.reestimate_share), so that a loaded map goes
  // on re-estimating as the saved one would have.
  using Bookkeeping = std::pair<int, std::uint64_t>;
  static std::vector<Bookkeeping> EstimateBookkeeping(const ObjectMap& map) {
    std::vector<Bookkeeping> entries;
    for (const auto& [id, object] : map.objects_)
      entries.emplace_back(object.changes_since_estimate, object.sightings_at_estimate);
    return entries;
  }
  static void SetEstimateBookkeeping(const std::vector<Bookkeeping>& entries, ObjectMap* map) {
    RequireOnePerObject(entries.size(), *map, "the estimate bookkeeping is");
    auto entry = entries.begin();
    for (auto& [id, object] : map->objects_) {
      if (entry->first < 0)
        throw std::runtime_error("object " + std::to_string(id) + " has " +
                                 std::to_string(entry->first) + " changes waiting");
      object.changes_since_estimate = entry->first;
      object.sightings_at_estimate = static_cast<std::size_t>(entry->second);
      ++entry;
    }
  }

  // Version 3: the colour signature of each map object's sightings, objects in id order.
  // Apart from the sightings (whose layout is version 1's) so older files still read.
  using ColourList = std::vector<std::optional<ColourHistogram>>;
  static std::vector<ColourList> SightingColours(const ObjectMap& map) {
    std::vector<ColourList> colours;
    for (const auto& [id, object] : map.objects_) {
      ColourList& list = colours.emplace_back();
      for (const ObjectSighting& sighting : object.sightings) list.push_back(sighting.colour);
    }
    return colours;
  }
  static void SetSightingColours(const std::vector<ColourList>& colours, ObjectMap* map) {
    RequireOnePerObject(colours.size(), *map, "the sighting colours are");
    auto list = colours.begin();
    for (auto& [id, object] : map->objects_) {
      if (list->size() != object.sightings.size())
        throw std::runtime_error("object " + std::to_string(id) + " has " +
                                 std::to_string(object.sightings.size()) + " sightings but " +
                                 std::to_string(list->size()) + " sighting colours");
      for (std::size_t i = 0; i < list->size(); ++i) object.sightings[i].colour = (*list)[i];
      ++list;
    }
  }

  static app_detail::ObjectLayerCounters Load(std::istream& in, ObjectMapper* mapper,
                                              std::uint32_t file_version) {
    std::lock_guard<std::mutex> map_lock(mapper->map_mutex_);
    std::lock_guard<std::mutex> ocg_lock(mapper->manager_.state_mutex_);
    cereal::BinaryInputArchive archive(in);
    app_detail::ObjectLayerCounters counters;
    archive(counters.keyframes, counters.tracked_frames);
    ObjectMapState(archive, mapper->map_);
    std::string observations;
    archive(mapper->stats_, observations, mapper->manager_.removals_);
    mapper->observations_jsonl_.Clear();
    mapper->observations_jsonl_.Append(observations);
    LoadDetector(archive, &mapper->manager_.detector_);
    if (file_version >= 2) {
      std::string change_log;
      archive(change_log);
      if (!change_log.empty()) counters.change_log = std::move(change_log);
    }
    if (file_version >= 3) {
      std::vector<ColourList> colours;
      archive(colours);
      SetSightingColours(colours, &mapper->map_);
    }
    if (file_version >= 6) {
      std::vector<Bookkeeping> bookkeeping;
      archive(bookkeeping);
      SetEstimateBookkeeping(bookkeeping, &mapper->map_);
    }
    return counters;
  }
};

}  // namespace ocg

namespace ocg::app_detail {

void SaveObjectMapper(const ObjectMapper& mapper, const ObjectLayerCounters& counters,
                      std::ostream& out) {
  MapFileAccess::Save(mapper, counters, out);
}

ObjectLayerCounters LoadObjectMapper(std::istream& in, ObjectMapper* mapper,
                                     std::uint32_t file_version) {
  return MapFileAccess::Load(in, mapper, file_version);
}

}  // namespace ocg::app_detail
