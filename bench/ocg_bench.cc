// Time per keyframe of the OCG update for maps of 10^3 .. 10^6 objects with mean degree
// 20 and 10 objects observed per keyframe: the incremental ObjectChangeDetector against
// the brute-force reference that recomputes everything (tests/support NaiveOcg).
//
// The map is a ring: object i was seen with objects i-10 .. i+10, so each object has 20
// neighbours. Each timed keyframe observes 10 consecutive objects at a random place on
// the ring, so neighbours of the window become suspicious and objects left behind go to
// Unknown, as when a camera jumps around a large map. tau_doubt is set out of reach so
// the map keeps its size while every transition still runs.
//
// Run: build/bench/ocg_bench [--benchmark_filter=...]

#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <random>

#include "ocg/ocg/change_detector.h"
#include "test_support.h"

namespace {

using ocg::KeyframeObservation;
using ocg::ObjectId;

constexpr int kNeighboursEachSide = 10;
constexpr int kObservedPerKeyframe = 10;

ocg::OcgOptions BenchOptions() {
  ocg::OcgOptions options;
  options.tau_doubt = 1e15;
  return options;
}

KeyframeObservation Observe(std::int64_t keyframe, ObjectId first, ObjectId map_size, int count) {
  KeyframeObservation observation;
  observation.keyframe_id = keyframe;
  observation.T_cw = ocg::SE3();
  observation.camera = ocg::PinholeCamera();
  for (int i = 0; i < count; ++i) observation.observed.push_back((first + i) % map_size);
  return observation;
}

Eigen::Vector3d CentroidOf(ObjectId id) {
  // In front of the camera and inside the image, so P = 1 and increments are granted.
  return {0.001 * static_cast<double>(id % 1000) - 0.5, 0.0, 5.0};
}

// Builds the ring by replaying one keyframe per object (21 consecutive objects observed
// together), cached per size so repetitions share it.
ocg::ObjectChangeDetector& IncrementalMap(ObjectId size) {
  static std::map<ObjectId, std::unique_ptr<ocg::ObjectChangeDetector>> cache;
  auto& slot = cache[size];
  if (!slot) {
    slot = std::make_unique<ocg::ObjectChangeDetector>(BenchOptions());
    for (ObjectId i = 0; i < size; ++i) {
      KeyframeObservation observation = Observe(i, i, size, kNeighboursEachSide + 1);
      observation.updates[(i + kNeighboursEachSide) % size].centroid = CentroidOf(i);
      slot->Process(observation);
    }
  }
  return *slot;
}

ocg::testing::NaiveOcg& NaiveMap(ObjectId size) {
  static std::map<ObjectId, std::unique_ptr<ocg::testing::NaiveOcg>> cache;
  auto& slot = cache[size];
  if (!slot) {
    slot = std::make_unique<ocg::testing::NaiveOcg>(BenchOptions());
    for (ObjectId i = 0; i < size; ++i) {
      ocg::testing::NaiveOcg::Object object;
      object.state.state = ocg::ObjectState::kUnknown;
      object.geometry.centroid = CentroidOf(i);
      slot->Seed(i, object);
      for (int d = 1; d <= kNeighboursEachSide; ++d) slot->SeedEdge(i, (i + d) % size, 1 + d % 3);
    }
  }
  return *slot;
}

// Times Process() of one keyframe that observes a random window of the ring. The
// observations are made beforehand: pausing the timer per iteration costs more than the
// update itself on this machine.
template <typename Engine>
void TimeKeyframes(benchmark::State& state, Engine& engine, ObjectId size) {
  constexpr std::size_t kPrepared = 4096;
  std::mt19937_64 rng(1);
  std::vector<KeyframeObservation> observations;
  observations.reserve(kPrepared);
  for (std::size_t i = 0; i < kPrepared; ++i) {
    observations.push_back(
        Observe(0, static_cast<ObjectId>(rng() % size), size, kObservedPerKeyframe));
  }
  std::int64_t keyframe = size;
  std::size_t next = 0;
  for (auto _ : state) {
    KeyframeObservation& observation = observations[next];
    next = (next + 1) % kPrepared;
    observation.keyframe_id = keyframe++;
    benchmark::DoNotOptimize(engine.Process(observation));
  }
}

void BM_IncrementalKeyframe(benchmark::State& state) {
  ocg::ObjectChangeDetector& detector = IncrementalMap(state.range(0));
  TimeKeyframes(state, detector, state.range(0));
  state.counters["objects"] = static_cast<double>(detector.ObjectCount());
  state.counters["edges"] = static_cast<double>(detector.graph().EdgeCount());
}

void BM_NaiveKeyframe(benchmark::State& state) {
  ocg::testing::NaiveOcg& naive = NaiveMap(state.range(0));
  TimeKeyframes(state, naive, state.range(0));
  state.counters["objects"] = static_cast<double>(naive.objects().size());
}

BENCHMARK(BM_IncrementalKeyframe)
    ->Arg(1000)
    ->Arg(10000)
    ->Arg(100000)
    ->Arg(1000000)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_NaiveKeyframe)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_NaiveKeyframe)->Arg(1000000)->Iterations(3)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
