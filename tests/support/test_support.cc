#include "test_support.h"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <set>

#include <unistd.h>

#include "ocg/ocg/observability.h"

namespace ocg::testing {

namespace fs = std::filesystem;

std::string SourceDir() {
  const char* from_environment = std::getenv("OCG_SOURCE_DIR");
  return from_environment != nullptr ? from_environment : OCG_TEST_SOURCE_DIR;
}

std::optional<std::string> SharedDataDir() {
  const char* override_dir = std::getenv("OCG_SHARED_DATA");
  const fs::path path = override_dir != nullptr ? fs::path(override_dir)
                                                : fs::path(SourceDir()) / ".." / "shared" / "data";
  if (!fs::is_directory(path)) return std::nullopt;
  return fs::canonical(path).string();
}

std::string SharedDataSkipMessage() {
  return "shared data not found at " + (fs::path(SourceDir()) / ".." / "shared" / "data").string() +
         " (set OCG_SHARED_DATA to its location to run this test)";
}

namespace {

// The folders MakeTempDir made, removed when the test program exits (kept with
// OCG_KEEP_TEST_FILES set, to look at a failure's files).
class TempDirs {
 public:
  ~TempDirs() {
    if (std::getenv("OCG_KEEP_TEST_FILES") != nullptr) return;
    for (const fs::path& path : paths_) {
      std::error_code ignored;
      fs::remove_all(path, ignored);
    }
  }
  void Add(const fs::path& path) {
    std::lock_guard<std::mutex> lock(mutex_);
    paths_.push_back(path);
  }

 private:
  std::mutex mutex_;
  std::vector<fs::path> paths_;
};

}  // namespace

std::string MakeTempDir(const std::string& name) {
  static std::atomic<int> counter{0};
  static TempDirs made;
  const fs::path path =
      fs::temp_directory_path() /
      ("ocg_test_" + name + "_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  fs::remove_all(path);
  fs::create_directories(path);
  made.Add(path);
  return path.string();
}

std::uint32_t NaiveOcg::EdgeWeight(ObjectId a, ObjectId b) const {
  const auto it = edges_.find({std::min(a, b), std::max(a, b)});
  return it == edges_.end() ? 0 : it->second;
}

std::vector<ObjectId> NaiveOcg::Process(const KeyframeObservation& observation) {
  const std::set<ObjectId> observed(observation.observed.begin(), observation.observed.end());
  for (ObjectId id : observed) {
    const auto [it, created] = objects_.try_emplace(id);
    const auto pending = pending_.find(id);
    if (created && pending != pending_.end()) {  // geometry given before it entered
      it->second.geometry = pending->second;
      pending_.erase(pending);
    }
  }
  for (auto a = observed.begin(); a != observed.end(); ++a) {
    for (auto b = std::next(a); b != observed.end(); ++b) ++edges_[{*a, *b}];
  }
  for (const auto& [id, update] : observation.updates) {
    auto it = objects_.find(id);
    ObjectGeometry& geometry = it == objects_.end() ? pending_[id] : it->second.geometry;
    if (update.centroid) geometry.centroid = update.centroid;
    if (update.size) geometry.size = update.size;
  }
  const Eigen::Vector3d camera_centre = observation.T_cw.Inverse().translation();
  for (ObjectId id : observed) {
    RecordDetectedView(objects_.at(id).geometry, camera_centre, options_,
                       options_.modes().detected_view);
  }

  // Everything from scratch: one pass over all edges gives every object's evidence.
  const OcgModes modes = options_.modes();
  std::map<ObjectId, ObjectEvidence> evidence;
  std::set<ObjectId> in_view = observed;
  for (const auto& [id, object] : objects_) {
    evidence[id].observed = observed.count(id) > 0;
    if (ExpectedInView(object.geometry, observation.T_cw, observation.camera, options_, modes) > 0)
      in_view.insert(id);
  }
  if (modes.occlusion) {
    std::vector<ImageFootprint> footprints;
    for (const auto& [id, object] : objects_) {
      if (!object.geometry.centroid || !object.geometry.size) continue;
      if (const auto footprint = ProjectBox(*object.geometry.centroid, *object.geometry.size,
                                            observation.T_cw, observation.camera))
        footprints.push_back(*footprint);
    }
    for (const auto& [id, object] : objects_) {
      if (!object.geometry.centroid || !object.geometry.size) continue;
      if (const auto own = ProjectBox(*object.geometry.centroid, *object.geometry.size,
                                      observation.T_cw, observation.camera))
        evidence[id].occluded_share = OccludedShare(*own, footprints, observation.camera);
    }
  }
  for (const auto& [pair, weight] : edges_) {
    for (const auto& [self, other] :
         {std::pair{pair.first, pair.second}, std::pair{pair.second, pair.first}}) {
      ObjectEvidence& entry = evidence.at(self);
      entry.total_weight += weight;
      entry.degree += 1;
      if (observed.count(other) > 0) {
        entry.observed_weight += weight;
        entry.observed_neighbours += 1;
      }
      if (in_view.count(other) > 0) entry.in_view_weight += weight;
    }
  }
  std::vector<ObjectId> removed;
  for (auto& [id, object] : objects_) {
    const Judgement judgement = JudgeObject(object.state, evidence.at(id), object.geometry,
                                            observation.T_cw, observation.camera, options_, modes);
    object.rate = judgement.rate;
    object.state = judgement.next;
    if (judgement.missed) ++object.geometry.missed_keyframes;
    if (judgement.next.state == ObjectState::kOutlier) removed.push_back(id);
  }
  for (ObjectId id : removed) {
    // SPEC 3.1: seen again, it re-enters as a new node with its last centroid (and size).
    ObjectGeometry kept;
    kept.centroid = objects_.at(id).geometry.centroid;
    kept.size = objects_.at(id).geometry.size;
    pending_[id] = kept;
    objects_.erase(id);
    for (auto it = edges_.begin(); it != edges_.end();) {
      it = (it->first.first == id || it->first.second == id) ? edges_.erase(it) : std::next(it);
    }
  }
  return removed;
}

PinholeCamera TestCamera(double focal, double cx, double cy) {
  PinholeCamera camera;
  camera.fx = camera.fy = focal;
  camera.cx = cx;
  camera.cy = cy;
  camera.width = 640;
  camera.height = 480;
  return camera;
}

}  // namespace ocg::testing
