#pragma once
// Helpers shared by the test programs (and the OCG benchmark).

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ocg/ocg/judgement.h"
#include "ocg/ocg/observation.h"
#include "ocg/ocg/options.h"

namespace ocg::testing {

// The paper's OCG (SPEC 3) exactly, for the tests of its algorithm: the default mode is
// "improved" (issue 18).
inline OcgOptions PaperOptions() {
  OcgOptions options;
  options.mode = "paper";
  return options;
}

// The project's source folder (OCG_SOURCE_DIR from CTest, else the compile-time path).
std::string SourceDir();
// ../shared/data beside the project (or $OCG_SHARED_DATA); nullopt when absent, and the
// caller skips with a message saying where it looked.
std::optional<std::string> SharedDataDir();
std::string SharedDataSkipMessage();
// A fresh empty folder under the system temp folder, removed when the program exits
// (unless OCG_KEEP_TEST_FILES is set).
std::string MakeTempDir(const std::string& name);
// A 640 x 480 ideal pinhole camera.
PinholeCamera TestCamera(double focal = 500.0, double cx = 320.0, double cy = 240.0);

// Brute-force reference for the OCG: keeps every edge in one ordered map and recomputes
// every object's sums, degree and state from scratch at every keyframe. Slow, obviously
// right, and used to check the incremental ObjectChangeDetector.
class NaiveOcg {
 public:
  struct Object {
    StateAndDoubt state;
    double rate = 0.0;
    ObjectGeometry geometry;
  };

  explicit NaiveOcg(OcgOptions options) : options_(std::move(options)) {}
  // Returns the ids removed at this keyframe, ascending.
  std::vector<ObjectId> Process(const KeyframeObservation& observation);
  const std::map<ObjectId, Object>& objects() const { return objects_; }
  std::uint32_t EdgeWeight(ObjectId a, ObjectId b) const;
  // Direct seeding, so benchmarks can build large maps without replaying keyframes.
  void Seed(ObjectId id, const Object& object) { objects_[id] = object; }
  void SeedEdge(ObjectId a, ObjectId b, std::uint32_t weight) {
    edges_[{std::min(a, b), std::max(a, b)}] = weight;
  }

 private:
  OcgOptions options_;
  std::map<std::pair<ObjectId, ObjectId>, std::uint32_t> edges_;  // first < second
  std::map<ObjectId, Object> objects_;
  std::map<ObjectId, ObjectGeometry> pending_;  // given before the object entered
};

}  // namespace ocg::testing
