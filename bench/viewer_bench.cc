// Viewer speed (issue 8 target: a 1280x720 snapshot of 50,000 points and 100 cuboids in
// at most 100 ms), and the frame view.

#include <benchmark/benchmark.h>

#include <random>

#include "ocg/viewer/frame_view.h"
#include "ocg/viewer/map_view.h"

namespace {

ocg::MapScene LargeScene(int points, int cuboids, int keyframes) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> room(-3.0, 3.0), height(0.0, 2.5);
  ocg::MapScene scene;
  for (int i = 0; i < points; ++i)
    scene.points.emplace_back(room(random), room(random), height(random));
  for (int i = 0; i < cuboids; ++i) {
    ocg::ObjectView object;
    object.id = i + 1;
    object.class_id = 41 + i % 30;
    object.cuboid.centre = Eigen::Vector3d(room(random), room(random), 0.8);
    object.cuboid.size = Eigen::Vector3d(0.2, 0.3, 0.15);
    object.cuboid.yaw = 0.1 * i;
    object.state = 1 + i % 4;
    object.removed = i % 10 == 0;
    scene.objects.push_back(object);
  }
  for (int i = 0; i < keyframes; ++i) {
    const double angle = 6.28 * i / keyframes;
    const Eigen::Vector3d eye(2.0 * std::cos(angle), 2.0 * std::sin(angle), 1.4);
    scene.keyframes.push_back(ocg::LookAt(eye, {0, 0, 0.8}).Inverse());
    scene.trajectory.push_back(eye);
  }
  return scene;
}

void BM_MapSnapshot(benchmark::State& state) {
  ocg::ViewerOptions options;  // 1280 x 720
  ocg::Renderer renderer(options.snapshot_width, options.snapshot_height);
  const ocg::MapScene scene =
      LargeScene(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), 400);
  const auto viewpoint = static_cast<ocg::MapViewpoint>(state.range(2));
  for (auto _ : state) {
    benchmark::DoNotOptimize(ocg::RenderMapView(renderer, scene, options, viewpoint));
  }
  state.SetLabel(std::string(ocg::ToString(viewpoint)) + ", 1280x720");
}
BENCHMARK(BM_MapSnapshot)
    ->Args({50000, 100, static_cast<int>(ocg::MapViewpoint::kThreeQuarter)})
    ->Args({50000, 100, static_cast<int>(ocg::MapViewpoint::kTopDown)})
    ->Args({10000, 30, static_cast<int>(ocg::MapViewpoint::kThreeQuarter)})
    ->Unit(benchmark::kMillisecond);

// The labels alone: placed so that none overlaps another (100 objects in a 6 m room).
void BM_MapLabels(benchmark::State& state) {
  const ocg::ViewerOptions options;
  const ocg::MapScene scene = LargeScene(0, static_cast<int>(state.range(0)), 400);
  std::size_t placed = 0;
  for (auto _ : state) {
    placed = ocg::MapViewLabels(scene, options, ocg::MapViewpoint::kThreeQuarter).size();
    benchmark::DoNotOptimize(placed);
  }
  state.SetLabel(std::to_string(placed) + " labels placed, three_quarter, 1280x720");
}
BENCHMARK(BM_MapLabels)->Arg(30)->Arg(100)->Unit(benchmark::kMillisecond);

void BM_FrameView(benchmark::State& state) {
  const ocg::MapScene scene = LargeScene(0, 100, 1);
  ocg::PinholeCamera camera;
  camera.width = 640;
  camera.height = 480;
  const cv::Mat image(480, 640, CV_8UC3, cv::Scalar(90, 90, 90));
  std::vector<ocg::FrameDetection> detections(10);
  for (int i = 0; i < 10; ++i)
    detections[static_cast<std::size_t>(i)].box = {40.0 * i, 50, 40.0 * i + 35, 120};
  const ocg::SE3 T_cw = ocg::LookAt({0, -3, 1.5}, {0, 0, 0.8});
  for (auto _ : state) {
    benchmark::DoNotOptimize(ocg::RenderFrameView(image, detections, scene.objects, T_cw, camera,
                                                  Eigen::Vector3d::UnitZ()));
  }
}
BENCHMARK(BM_FrameView)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
