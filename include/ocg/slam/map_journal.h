#pragma once
// What changed in the SLAM map, told to a reader that keeps a copy of it (the object layer)
// instead of copying the whole map at every keyframe: a journal of the points and keyframes
// changed, each change one version, and the state now of those changed since a version.
//
// Every change of a point's position, descriptor or life (added, culled, replaced, its map
// reset) and of a keyframe's pose or life is noted where the map changes it (Map's own
// methods, the bundle adjustments' write-back); what moves the whole map (a loop
// correction, a global adjustment, a merge of maps, a reset, a switch to another map of the
// atlas, a loaded map) is noted as "everything", and a reader behind it reads the whole
// map once. The journal keeps at most `capacity` entries: a reader further behind reads
// the whole map too, so memory stays bounded when nobody reads.

#include <Eigen/Core>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <vector>

#include "ocg/features/descriptor.h"

namespace ocg {

class Map;

class MapJournal {
 public:
  static constexpr std::size_t kDefaultCapacity = 1 << 16;
  explicit MapJournal(std::size_t capacity = kDefaultCapacity) : capacity_(capacity) {}

  // Note a change (after making it: a reader that saw the version reads the new state).
  void Point(std::uint64_t id);
  // Map units: an adjustment's move of a point is noted once the point is more than this
  // from where the reader last read it (Map::NotePointMoved), so the reader's copy of a
  // point stays within this of the map's without hearing of every tiny move (most moves
  // of a local bundle adjustment are below 0.001 map units). 0 (the default): every move.
  // The object layer sets it to its Objects.follow_tolerance. Readers that read at the
  // same moments (the object layers of several OCG modes) each stay within it; one that
  // reads at other moments may lag by a few tolerances.
  void SetPointTolerance(double tolerance) { point_tolerance_ = tolerance; }
  double point_tolerance() const { return point_tolerance_; }
  void KeyFrame(std::uint64_t id);
  void Everything();

  std::uint64_t version() const;
  // The points and keyframes changed after version, each once, by id; false when the
  // journal cannot say (everything changed since, or it no longer holds the entries).
  // *now: the version the answer is up to.
  bool ChangedSince(std::uint64_t version, std::vector<std::uint64_t>* points,
                    std::vector<std::uint64_t>* keyframes, std::uint64_t* now) const;

 private:
  enum class Kind : std::uint8_t { kPoint, kKeyFrame };
  struct Entry {
    std::uint64_t id;
    Kind kind;
  };
  mutable std::mutex mutex_;
  std::size_t capacity_;
  std::deque<Entry> entries_;  // versions version_ - entries_.size() + 1 .. version_
  std::uint64_t version_ = 0;
  std::uint64_t everything_ = 0;  // the version of the last Everything()
  double point_tolerance_ = 0.0;
};

// The state now of a point or keyframe of the current map; live false when it is gone
// (culled, replaced, reset, or in another map of the atlas).
struct MapPointState {
  std::uint64_t id = 0;
  bool live = false;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Descriptor descriptor{};
};
struct KeyFrameState {
  std::uint64_t id = 0;
  bool live = false;
  Eigen::Matrix3d R_wc = Eigen::Matrix3d::Identity();  // camera to world
  Eigen::Vector3d t_wc = Eigen::Vector3d::Zero();      // the camera centre in the world
};

struct MapChanges {
  std::uint64_t version = 0;  // give it to the next call
  // The lists hold every live point and keyframe of the current map (by id): a reader's
  // copy starts over from them. Otherwise they hold what changed, live or gone.
  bool everything = false;
  std::vector<MapPointState> points;
  std::vector<KeyFrameState> keyframes;
};

// What changed in the current map since version (none: a reader without a copy), read with
// map.mutex() held. Proportional to the changes, but for everything.
MapChanges ChangesSince(const Map& map, std::optional<std::uint64_t> version);

}  // namespace ocg
