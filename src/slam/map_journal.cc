#include "ocg/slam/map_journal.h"

#include <algorithm>

#include "ocg/slam/map.h"

namespace ocg {
namespace {

void SortUnique(std::vector<std::uint64_t>* ids) {
  std::sort(ids->begin(), ids->end());
  ids->erase(std::unique(ids->begin(), ids->end()), ids->end());
}

// point: the map's point with this id, or null.
MapPointState StateOf(const Map& map, MapPointId id, MapPoint* point) {
  MapPointState state;
  state.id = id;
  if (point == nullptr || point->bad || point->map != map.current_map()) return state;
  state.live = true;
  state.position = point->position;
  point->read_position = point->position;  // the reader holds it from here on
  state.descriptor = point->descriptor;
  return state;
}

// The states of the points with these ids (sorted), each found by hash (Map::FindPoint): a
// keyframe's adjustment changes the points of the local window, which spreads over more
// of the map's ids as the map grows, so a walk along the map's ordered points or a search
// from its root would cost more per point on a long run.
std::vector<MapPointState> StatesOf(const Map& map, const std::vector<std::uint64_t>& ids) {
  std::vector<MapPointState> states;
  states.reserve(ids.size());
  for (const std::uint64_t id : ids) states.push_back(StateOf(map, id, map.FindPoint(id)));
  return states;
}

KeyFrameState StateOf(const Map& map, const KeyFrame& keyframe) {
  KeyFrameState state;
  state.id = keyframe.id;
  if (keyframe.bad || keyframe.map != map.current_map()) return state;
  state.live = true;
  const SE3 T_wc = keyframe.T_cw.Inverse();
  state.R_wc = T_wc.rotation();  // as System::KeyFrameRotations
  state.t_wc = T_wc.translation();
  return state;
}

}  // namespace

void MapJournal::Point(std::uint64_t id) {
  const std::lock_guard<std::mutex> lock(mutex_);
  ++version_;
  entries_.push_back({id, Kind::kPoint});
  if (entries_.size() > capacity_) entries_.pop_front();
}

void MapJournal::KeyFrame(std::uint64_t id) {
  const std::lock_guard<std::mutex> lock(mutex_);
  ++version_;
  entries_.push_back({id, Kind::kKeyFrame});
  if (entries_.size() > capacity_) entries_.pop_front();
}

void MapJournal::Everything() {
  const std::lock_guard<std::mutex> lock(mutex_);
  everything_ = ++version_;
  entries_.clear();  // nobody reads them: a reader behind this reads the whole map
}

std::uint64_t MapJournal::version() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return version_;
}

bool MapJournal::ChangedSince(std::uint64_t version, std::vector<std::uint64_t>* points,
                              std::vector<std::uint64_t>* keyframes, std::uint64_t* now) const {
  points->clear();
  keyframes->clear();
  const std::lock_guard<std::mutex> lock(mutex_);
  *now = version_;
  if (version >= version_) return version == version_;
  if (version < everything_) return false;
  const std::uint64_t first = version_ - entries_.size() + 1;  // the oldest entry's version
  if (version + 1 < first) return false;
  for (auto entry = entries_.begin() + static_cast<std::ptrdiff_t>(version + 1 - first);
       entry != entries_.end(); ++entry) {
    (entry->kind == Kind::kPoint ? points : keyframes)->push_back(entry->id);
  }
  SortUnique(points);
  SortUnique(keyframes);
  return true;
}

MapChanges ChangesSince(const Map& map, std::optional<std::uint64_t> version) {
  MapChanges changes;
  std::vector<std::uint64_t> points, keyframes;
  changes.everything =
      !version || !map.journal().ChangedSince(*version, &points, &keyframes, &changes.version);
  if (changes.everything) {
    changes.version = map.journal().version();
    for (const auto& [id, point] : map.points()) {
      MapPointState state = StateOf(map, id, point.get());
      if (state.live) changes.points.push_back(state);
    }
    for (const auto& [id, keyframe] : map.keyframes()) {
      KeyFrameState state = StateOf(map, *keyframe);
      if (state.live) changes.keyframes.push_back(state);
    }
    return changes;
  }
  changes.points = StatesOf(map, points);
  for (const std::uint64_t id : keyframes) {
    const KeyFramePtr keyframe = map.GetKeyFrame(id);
    if (keyframe) {
      changes.keyframes.push_back(StateOf(map, *keyframe));
    } else {
      KeyFrameState gone;
      gone.id = id;
      changes.keyframes.push_back(gone);
    }
  }
  return changes;
}

}  // namespace ocg
