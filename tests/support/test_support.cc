#include "test_support.h"

#include <algorithm>
#include <any>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <mutex>
#include <set>

#include <unistd.h>

#include "ocg/ocg/judgement_terms.h"
#include "ocg/ocg/observability.h"

namespace ocg::testing {

namespace fs = std::filesystem;

namespace {

// The graph as the judgement terms read it, from scratch: every object's edges listed anew.
class NaiveGraphView : public GraphView {
 public:
  NaiveGraphView(const std::map<ObjectId, NaiveOcg::Object>& objects,
                 const std::map<std::pair<ObjectId, ObjectId>, std::uint32_t>& edges,
                 const std::set<ObjectId>& observed, const OcgModes& modes)
      : objects_(objects), observed_(observed), modes_(modes) {
    for (const auto& entry : objects) neighbours_[entry.first];
    for (const auto& [pair, weight] : edges) {
      neighbours_[pair.first].push_back({pair.second, weight});
      neighbours_[pair.second].push_back({pair.first, weight});
    }
  }
  const std::vector<CovisibilityEdge>& Neighbours(ObjectId id) const override {
    return neighbours_.at(id);
  }
  const ObjectGeometry& Geometry(ObjectId id) const override { return objects_.at(id).geometry; }
  bool Detected(ObjectId id) const override { return observed_.count(id) > 0; }
  void ForEachObject(
      const std::function<void(ObjectId, const ObjectGeometry&)>& visit) const override {
    for (const auto& [id, object] : objects_) visit(id, object.geometry);
  }
  const OcgModes& modes() const override { return modes_; }
  std::any& KeyframeMemo(const char* key) const override { return memo_[key]; }

 private:
  const std::map<ObjectId, NaiveOcg::Object>& objects_;
  const std::set<ObjectId>& observed_;
  const OcgModes& modes_;
  std::map<ObjectId, std::vector<CovisibilityEdge>> neighbours_;
  mutable std::map<std::string, std::any> memo_;
};

}  // namespace

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
  for (const auto& entry : objects_)
    evidence[entry.first].observed = observed.count(entry.first) > 0;
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
    }
  }
  const NaiveGraphView view(objects_, edges_, observed, modes);
  std::vector<ObjectId> removed;
  for (auto& [id, object] : objects_) {
    const Judgement judgement =
        JudgeObject(object.state, evidence.at(id), object.geometry, observation.T_cw,
                    observation.camera, options_, modes, &observation, id, &view);
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
