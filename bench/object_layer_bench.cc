// object_layer_bench: the object layer's cost per SLAM keyframe as the map grows, from 100
// to 2,000 keyframes (a timed tool, not Google Benchmark: it prints a table).
//
// The map is constructed (tests/support/growing_slam_map.h): each keyframe adds 100
// points, moves the newest 10 keyframes' points and rotations (the local adjustment's
// window) and culls 60 older points (local mapping culls most new points), so the map
// ends near 80,000 points. An ObjectMapper that mapped the synthetic table scene's objects
// follows it keyframe by keyframe, and keeps seeing them as a real run does: three frames
// of the scene's lap (its boxes, at the frame's pose) before each keyframe, whose poses
// the adjustment moves while they are in its window, so every object gathers sightings
// without end (6,000 frames each by the last row). Timed per keyframe, as run.json's
// timing.object_layer_per_keyframe: those frames' AddFrame, FollowSlamMap (the changes
// into its copy, the supporting plane, the sightings and points moved, the objects they
// moved estimated again) and the OCG keyframe (AddKeyframe). Per size: the median thread
// CPU time of a keyframe over the 100 before it, the plane's refits among them, the
// sightings of the live objects (all, kept or not), and for comparison one keyframe read as the
// whole map (what the object layer did at every keyframe before it kept a copy). Three sweeps: the
// defaults, the plane fitted at every keyframe (Objects.plane_refit_share 0), and the old
// bounds (Objects.max_sightings 4096, no bound on an object's points). Flat: the last
// row's median within 1.3x the first's; exit status 1 when the defaults' is not.
#include <cstdio>
#include <string>
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
  const int lap = scene.options.frames;
  // Frame `frame` (any number): the scene's frame of its lap, as seen at that number.
  const auto add_frame = [&](ObjectMapper* mapper, std::int64_t frame) {
    const auto f = static_cast<std::size_t>(frame % lap);
    const double timestamp = static_cast<double>(frame) / 30.0;
    mapper->AddFrame(frame, timestamp, scene.T_cw[f], scene.detections[f]);
  };
  const auto feed = [&](ObjectMapper* mapper) {
    for (int frame = 0; frame < lap; ++frame) {
      add_frame(mapper, frame);
      if (frame % 5 == 0)
        mapper->AddKeyframe(frame / 5, scene.timestamps[static_cast<std::size_t>(frame)],
                            scene.T_cw[static_cast<std::size_t>(frame)]);
    }
  };
  const auto sweep = [&](const ObjectsOptions& objects, const std::string& name) {
    std::printf("%s\n", name.c_str());
    ObjectMapper mapper(objects, testing::PaperOptions(), scene.options.camera, true);
    feed(&mapper);
    testing::GrowingSlamMapOptions options;
    options.culled_per_keyframe = 60;
    testing::GrowingSlamMap growing(options);
    std::printf("%9s %10s %15s %7s %10s %18s\n", "keyframes", "points", "median_ms/kf", "refits",
                "seen", "whole_map_read_ms");
    std::vector<double> window;
    int refits = 0;
    double first_median = 0.0, last_median = 0.0;
    const std::vector<int> sizes = {100, 250, 500, 1000, 1500, 2000};
    std::size_t next_size = 0;
    std::uint64_t seed = 0;
    std::int64_t frame = lap, ocg_keyframe = lap / 5;
    constexpr int kFramesPerKeyframe = 3, kWindowKeyframes = 10;
    while (next_size < sizes.size()) {
      SlamMapChanges changes = growing.NextKeyframe();
      const double start = ThreadCpuSeconds();
      for (int i = 0; i < kFramesPerKeyframe; ++i) add_frame(&mapper, frame++);
      // The adjustment's window moved the frames of its keyframes a little.
      for (std::int64_t moved =
               std::max<std::int64_t>(lap, frame - kFramesPerKeyframe * kWindowKeyframes);
           moved < frame; ++moved) {
        const SE3 nudge(Eigen::Matrix3d::Identity(),
                        Eigen::Vector3d(1e-4 * static_cast<double>(seed % 7), 0.0, 0.0));
        changes.frame_poses[moved] = nudge * scene.T_cw[static_cast<std::size_t>(moved % lap)];
      }
      mapper.FollowSlamMap(changes, ++seed);
      mapper.AddKeyframe(ocg_keyframe++, static_cast<double>(frame - 1) / 30.0,
                         scene.T_cw[static_cast<std::size_t>((frame - 1) % lap)]);
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
      std::size_t sightings = 0;
      for (const ObjectRecord& object : mapper.LiveObjects())
        sightings += static_cast<std::size_t>(object.observations);
      std::printf("%9d %10zu %15.3f %7d %10zu %18.3f\n", growing.keyframes(), growing.points(),
                  median_ms, refits, sightings, pull_ms);
      std::fflush(stdout);
      refits = 0;
      ++next_size;
    }
    const double ratio = last_median / first_median;
    std::printf("last / first median: %.2f (flat: at most 1.3)\n\n", ratio);
    return ratio;
  };
  const double defaults = sweep(ObjectsOptions(), "defaults");
  ObjectsOptions refit_every_keyframe;
  refit_every_keyframe.plane_refit_share = 0.0;
  sweep(refit_every_keyframe, "Objects.plane_refit_share 0 (plane fitted at every keyframe)");
  ObjectsOptions old_bounds;
  old_bounds.max_sightings = 4096;
  old_bounds.max_object_points = 0;
  sweep(old_bounds, "Objects.max_sightings 4096, max_object_points 0 (the old bounds)");
  return defaults <= 1.3 ? 0 : 1;
}
