// The incremental ObjectChangeDetector against the brute-force NaiveOcg on thousands of
// random observation streams, in every mode: identical states, doubts, rates and removals.

#include <gtest/gtest.h>

#include <random>

#include "ocg/ocg/change_detector.h"
#include "ocg/ocg/observability.h"
#include "ocg_test_scene.h"
#include "test_support.h"

namespace ocg {
namespace {

// A table scene in which objects vanish, reappear under new ids, and duplicates appear;
// a camera circles it, sometimes looking away, with missed detections.
class RandomStream {
 public:
  explicit RandomStream(unsigned seed) : rng_(seed) {
    std::uniform_int_distribution<int> count(3, 24);
    const int objects = count(rng_);
    for (int i = 0; i < objects; ++i) AddObject();
    miss_probability_ = Uniform(0.0, 0.3);
  }

  KeyframeObservation Next(std::int64_t keyframe) {
    angle_ += Uniform(-0.6, 0.6);
    const Eigen::Vector3d eye(2.5 * std::cos(angle_), 2.5 * std::sin(angle_), Uniform(0.5, 1.5));
    Eigen::Vector3d target(Uniform(-1.0, 1.0), Uniform(-1.0, 1.0), 0.0);
    if (Uniform(0, 1) < 0.15) target = eye + (eye - target);  // looking away from the table
    KeyframeObservation observation =
        testing::MakeObservation(keyframe, testing::LookAt(eye, target), {});
    for (Object& object : objects_) {
      if (!object.present) continue;
      if (!CentroidInImage(object.position, observation.T_cw, observation.camera)) continue;
      auto announce = [&] {
        object.announced = true;
        auto& update = observation.updates[object.id];
        update.centroid =
            object.position + Eigen::Vector3d(Uniform(-0.02, 0.02), Uniform(-0.02, 0.02), 0);
        update.size = Eigen::Vector3d(Uniform(0.05, 0.8), Uniform(0.05, 0.8), Uniform(0.05, 0.5));
      };
      if ((object.position - eye).norm() > 3.5 || Uniform(0, 1) < miss_probability_) {
        // Sometimes the geometry is known before the first observation (SPEC 3.1).
        if (!object.announced && Uniform(0, 1) < 0.3) announce();
        continue;
      }
      observation.observed.push_back(object.id);
      if (!object.announced || Uniform(0, 1) < 0.2) announce();
    }
    if (!observation.observed.empty() && Uniform(0, 1) < 0.08) {  // a duplicate, seen once
      const ObjectId duplicate = next_id_++;
      observation.observed.push_back(duplicate);
      observation.updates[duplicate].centroid = Eigen::Vector3d(Uniform(-1, 1), Uniform(-1, 1), 0);
    }
    if (Uniform(0, 1) < 0.03)
      observation.observed.push_back(observation.observed.empty() ? 0 : observation.observed[0]);
    std::shuffle(observation.observed.begin(), observation.observed.end(), rng_);
    // Semi-static changes: an object vanishes; sometimes it comes back elsewhere (new id).
    if (Uniform(0, 1) < 0.05) objects_[Index()].present = false;
    if (Uniform(0, 1) < 0.03) AddObject();
    return observation;
  }

 private:
  struct Object {
    ObjectId id;
    Eigen::Vector3d position;
    bool present = true;
    bool announced = false;
  };
  double Uniform(double low, double high) {
    return std::uniform_real_distribution<double>(low, high)(rng_);
  }
  std::size_t Index() {
    return std::uniform_int_distribution<std::size_t>(0, objects_.size() - 1)(rng_);
  }
  void AddObject() {
    objects_.push_back({next_id_++, {Uniform(-1.0, 1.0), Uniform(-0.6, 0.6), 0.0}});
  }

  std::mt19937 rng_;
  std::vector<Object> objects_;
  ObjectId next_id_ = 1;
  double angle_ = 0.0;
  double miss_probability_ = 0.1;
};

TEST(Differential, IncrementalMatchesNaiveReferenceOnRandomStreams) {
  const std::vector<std::string> modes = {"paper",    "fallback", "in_image",
                                          "guard",    "dropout",  "occlusion",
                                          "improved", "off",      "visibility"};
  constexpr int kStreams = 2000;
  std::size_t removals = 0, suspicious_seen = 0, keyframes = 0;
  for (int stream = 0; stream < kStreams; ++stream) {
    OcgOptions options;
    options.mode = modes[static_cast<std::size_t>(stream) % modes.size()];
    if (stream % 7 == 0) options.tau_doubt = 20;  // more removals
    ObjectChangeDetector detector(options);
    testing::NaiveOcg reference(options);
    RandomStream generator(static_cast<unsigned>(stream));
    const int length = 20 + stream % 60;
    for (int keyframe = 0; keyframe < length; ++keyframe, ++keyframes) {
      const KeyframeObservation observation = generator.Next(keyframe);
      const KeyframeResult result = detector.Process(observation);
      const std::vector<ObjectId> expected_removed = reference.Process(observation);
      std::vector<ObjectId> removed;
      for (const RemovalEvent& event : result.removed) removed.push_back(event.object_id);
      ASSERT_EQ(removed, expected_removed) << "stream " << stream << " keyframe " << keyframe;
      removals += removed.size();

      const std::vector<ObjectStatus> snapshot = detector.Snapshot();
      ASSERT_EQ(snapshot.size(), reference.objects().size()) << "stream " << stream;
      auto expected = reference.objects().begin();
      for (const ObjectStatus& status : snapshot) {
        ASSERT_EQ(status.id, expected->first) << "stream " << stream;
        const testing::NaiveOcg::Object& object = expected->second;
        ASSERT_EQ(status.state, object.state.state)
            << "stream " << stream << " kf " << keyframe << " id " << status.id;
        ASSERT_EQ(status.doubt, object.state.doubt)
            << "stream " << stream << " kf " << keyframe << " id " << status.id;
        ASSERT_EQ(status.active_edge_rate, object.rate)
            << "stream " << stream << " kf " << keyframe << " id " << status.id;
        suspicious_seen += status.state == ObjectState::kSuspicious;
        ++expected;
      }
      for (const ObjectStatus& status : snapshot) {
        for (const CovisibilityEdge& edge : detector.graph().Neighbours(status.id)) {
          ASSERT_EQ(edge.weight, reference.EdgeWeight(status.id, edge.neighbour));
        }
      }
    }
  }
  // The streams must exercise the interesting transitions, or this test proves little.
  EXPECT_GT(removals, 1000u);
  EXPECT_GT(suspicious_seen, 10000u);
  RecordProperty("keyframes", static_cast<int>(keyframes));
  RecordProperty("removals", static_cast<int>(removals));
}

}  // namespace
}  // namespace ocg
