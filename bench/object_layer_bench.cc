// object_layer_bench: the object layer's cost per SLAM keyframe as the map grows, from 100
// to 2,000 keyframes (a timed tool, not Google Benchmark: it prints a table).
//
// The map is constructed (tests/support/growing_slam_map.h): each keyframe adds 100
// points, moves the newest 10 keyframes' points and rotations (the local adjustment's
// window) and culls 60 older points (local mapping culls most new points), so the map
// ends near 80,000 points. An ObjectMapper
// that mapped the synthetic table scene's objects follows it keyframe by keyframe
// (FollowSlamMap: the changes into its copy, the supporting plane, the objects moved).
// Per size: the median thread CPU time of a keyframe over the 100 before it, the plane's
// refits among them, and for comparison one keyframe read as the whole map (what the
// object layer did at every keyframe before it kept a copy). Twice: with the plane kept
// (Objects.plane_refit_share 0.1) and fitted at every keyframe (0, the default). Flat: the
// last row's median within 1.3x the first's; exit status 1 when the kept plane's is not.
#include <cstdio>
#include <vector>

#include "growing_slam_map.h"
#include "ocg/core/cpu_time.h"
#include "ocg/core/statistics.h"
#include "ocg/objects/object_mapper.h"
#include "synthetic_scene.h"
#include "test_support.h"

int main() {
  using namespace ocg;
  const testing::SyntheticScene scene = testing::SynthesizeScene(testing::TableWithObjects());
  const auto feed = [&scene](ObjectMapper* mapper) {
    for (int frame = 0; frame < scene.options.frames; ++frame) {
      const auto f = static_cast<std::size_t>(frame);
      mapper->AddFrame(frame, scene.timestamps[f], scene.T_cw[f], scene.detections[f]);
      if (frame % 5 == 0) mapper->AddKeyframe(frame / 5, scene.timestamps[f], scene.T_cw[f]);
    }
  };
  // The plane kept until 10 % of the map changed, then fitted at every keyframe (the
  // default: its cost follows the map's points).
  const auto sweep = [&](double plane_refit_share) {
    ObjectsOptions objects;
    objects.plane_refit_share = plane_refit_share;
    std::printf("Objects.plane_refit_share %.1f\n", plane_refit_share);
    ObjectMapper mapper(objects, testing::PaperOptions(), scene.options.camera, true);
    feed(&mapper);
    testing::GrowingSlamMapOptions options;
    options.culled_per_keyframe = 60;
    testing::GrowingSlamMap growing(options);
    std::printf("%9s %10s %15s %7s %18s\n", "keyframes", "points", "median_ms/kf", "refits",
                "whole_map_read_ms");
    std::vector<double> window;
    int refits = 0;
    double first_median = 0.0, last_median = 0.0;
    const std::vector<int> sizes = {100, 250, 500, 1000, 1500, 2000};
    std::size_t next_size = 0;
    std::uint64_t seed = 0;
    while (next_size < sizes.size()) {
      const SlamMapChanges changes = growing.NextKeyframe();
      const double start = ThreadCpuSeconds();
      mapper.FollowSlamMap(changes, ++seed);
      window.push_back(ThreadCpuSeconds() - start);
      refits += mapper.LastFollowWork().plane_refit ? 1 : 0;
      if (window.size() > 100) window.erase(window.begin());
      if (growing.keyframes() != sizes[next_size]) continue;
      // The whole map read at one keyframe, into a mapper of its own (same objects).
      SlamMapChanges whole;
      whole.everything = true;
      for (const auto& [id, point] : mapper.SlamMap().points())
        whole.points.push_back({id, point.position, point.descriptor});
      for (const auto& [id, rotation] : mapper.SlamMap().camera_rotations())
        whole.camera_rotations.emplace_back(id, rotation);
      ObjectMapper pull(objects, testing::PaperOptions(), scene.options.camera, true);
      feed(&pull);
      const double pull_start = ThreadCpuSeconds();
      pull.FollowSlamMap(whole, seed);
      const double pull_ms = 1000.0 * (ThreadCpuSeconds() - pull_start);
      const double median_ms = 1000.0 * Median(window);
      if (next_size == 0) first_median = median_ms;
      last_median = median_ms;
      std::printf("%9d %10zu %15.3f %7d %18.3f\n", growing.keyframes(), growing.points(), median_ms,
                  refits, pull_ms);
      std::fflush(stdout);
      refits = 0;
      ++next_size;
    }
    const double ratio = last_median / first_median;
    std::printf("last / first median: %.2f (flat: at most 1.3)\n\n", ratio);
    return ratio;
  };
  const double kept = sweep(0.1);
  sweep(0.0);
  return kept <= 1.3 ? 0 : 1;
}
