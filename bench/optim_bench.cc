// Bundle adjustment benchmarks: one local adjustment the size local mapping solves on
// the 640 x 480 presets (docs/history/results-log.md quotes the figures), with each way of solving
// the reduced camera system and with or without the second, outlier-free solve.
//
// The scene: a camera moving sideways along points 1-2 m away, one keyframe every 25 cm,
// so that a point is seen by about seven keyframes (as in the maps of the presets: 100
// new points per keyframe); the newest `free` keyframes are adjusted, the 10 before them
// see some of the same points and hold the gauge. Observations carry 1 px of noise and 2 % gross
// outliers; the free keyframes and the points start perturbed.

#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "ocg/optim/bundle_adjustment.h"

namespace {

constexpr int kFixedKeyframes = 10;

ocg::BundleAdjustmentProblem LocalScene(int free_keyframes, int points_per_keyframe) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, 1.0);
  ocg::BundleAdjustmentProblem problem;
  const int keyframes = kFixedKeyframes + free_keyframes;
  std::vector<ocg::SE3> truth;
  for (int k = 0; k < keyframes; ++k) {
    const ocg::SE3 T_wc(
        Eigen::AngleAxisd(0.02 * std::sin(k), Eigen::Vector3d::UnitY()).toRotationMatrix(),
        Eigen::Vector3d(0.25 * k, 0.0, 0.0));
    truth.push_back(T_wc.Inverse());
    problem.keyframes.push_back({truth.back(), k < kFixedKeyframes});
  }
  const double length = 0.25 * keyframes;
  for (int p = 0; p < points_per_keyframe * keyframes; ++p) {
    const Eigen::Vector3d X(length * 0.5 * (unit(rng) + 1.0), 0.6 * unit(rng),
                            1.5 + 0.5 * unit(rng));
    problem.points.push_back(
        {X + 0.02 * Eigen::Vector3d(noise(rng), noise(rng), noise(rng)), false});
    for (int k = 0; k < keyframes; ++k) {
      const Eigen::Vector3d Xc = truth[static_cast<std::size_t>(k)] * X;
      const Eigen::Vector2d pixel = problem.camera.ProjectUndistorted(Xc);
      if (!problem.camera.IsInImage(pixel)) continue;
      Eigen::Vector2d observed = pixel + Eigen::Vector2d(noise(rng), noise(rng));
      if (unit(rng) > 0.96) observed += Eigen::Vector2d(25.0, -20.0);
      problem.observations.push_back({k, p, observed, 1.0});
    }
  }
  for (ocg::BaKeyframe& keyframe : problem.keyframes) {
    if (keyframe.fixed) continue;
    keyframe.T_cw =
        ocg::SE3(Eigen::AngleAxisd(0.002, Eigen::Vector3d::UnitX()).toRotationMatrix(),
                 Eigen::Vector3d(0.005 * noise(rng), 0.005 * noise(rng), 0.005 * noise(rng))) *
        keyframe.T_cw;
  }
  return problem;
}

// range(0): free keyframes; range(1): 0 sparse, 1 dense Schur; range(2): robust
// iterations; range(3): refine iterations.
void BM_LocalBundleAdjustment(benchmark::State& state) {
  const ocg::BundleAdjustmentProblem scene = LocalScene(static_cast<int>(state.range(0)), 100);
  ocg::BundleAdjustmentOptions options;
  options.schur =
      state.range(1) == 1 ? ocg::SchurComplement::kDense : ocg::SchurComplement::kSparse;
  options.max_iterations = static_cast<int>(state.range(2));
  options.refine_iterations = static_cast<int>(state.range(3));
  ocg::BundleAdjustmentReport report;
  for (auto _ : state) {
    ocg::BundleAdjustmentProblem problem = scene;
    report = ocg::BundleAdjust(&problem, options);
  }
  state.counters["observations"] = static_cast<double>(scene.observations.size());
  state.counters["iterations"] = report.iterations;
  state.counters["final_rms_px"] = report.final_rms_pixels;
}
BENCHMARK(BM_LocalBundleAdjustment)
    ->ArgNames({"free", "dense", "robust", "refine"})
    ->Args({20, 0, 20, 0})
    ->Args({20, 1, 20, 0})
    ->Args({20, 1, 5, 10})
    ->Args({40, 0, 20, 0})
    ->Args({40, 1, 20, 0})
    ->Args({60, 0, 20, 0})
    ->Args({60, 1, 20, 0})
    ->Args({120, 0, 10, 0})
    ->Args({120, 1, 10, 0})
    ->Unit(benchmark::kMillisecond);

// Tracking's pose optimization (twice per frame): a frame matched to range(0) map points
// 1-5 m away, 10 % of them gross outliers, starting 1 cm and 0.3 degrees off.
void BM_PoseOptimization(benchmark::State& state) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, 1.0);
  const ocg::PinholeCamera camera;
  std::vector<ocg::PoseObservation> observations;
  while (observations.size() < static_cast<std::size_t>(state.range(0))) {
    const Eigen::Vector3d X(2.0 * unit(rng), 1.5 * unit(rng), 3.0 + 2.0 * unit(rng));
    const Eigen::Vector2d pixel = camera.ProjectUndistorted(X);
    if (!camera.IsInImage(pixel)) continue;
    ocg::PoseObservation o;
    o.point_world = X;
    o.pixel = pixel + Eigen::Vector2d(noise(rng), noise(rng));
    if (unit(rng) > 0.8) o.pixel += Eigen::Vector2d(20.0, -15.0);
    observations.push_back(o);
  }
  const ocg::SE3 start(Eigen::AngleAxisd(0.005, Eigen::Vector3d::UnitY()).toRotationMatrix(),
                       Eigen::Vector3d(0.01, -0.005, 0.003));
  ocg::PoseOptimizationResult result;
  for (auto _ : state) {
    result = ocg::OptimizePose(camera, start, observations, ocg::PoseOptimizationOptions());
  }
  state.counters["inliers"] = result.inliers;
}
BENCHMARK(BM_PoseOptimization)->Arg(150)->Arg(500)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
