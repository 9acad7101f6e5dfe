// Map file loading (issue 19 target: a map of 500 keyframes loads in under a second):
// the file read and checked (checksum), the SLAM map rebuilt (feature grids included) and
// the keyframe database filled, as System::LoadMap does. 1000 features per keyframe, as
// ORB-SLAM2's TUM settings extract.

#include <benchmark/benchmark.h>

#include <map>
#include <sstream>
#include <string>

#include "ocg/core/map_file.h"
#include "ocg/features/bow_database.h"
#include "ocg/slam/map_file.h"
#include "random_map.h"
#include "test_support.h"

namespace {

const std::string& MapFilePath(int keyframes) {
  static std::map<int, std::string> paths;
  std::string& path = paths[keyframes];
  if (path.empty()) {
    ocg::Map map;
    ocg::testing::FillRandomMap(keyframes, 1000, 11, &map);
    std::ostringstream out;
    ocg::SaveMap(map, out);
    path = ocg::testing::MakeTempDir("map_file_bench") + "/map.ocgmap";
    ocg::WriteMapFile(path, "bench", 1, out.str());
  }
  return path;
}

void BM_LoadMapFile(benchmark::State& state) {
  const int keyframes = static_cast<int>(state.range(0));
  const std::string& path = MapFilePath(keyframes);
  std::size_t points = 0, bytes = 0;
  for (auto _ : state) {
    ocg::MapFileReader file(path, "bench", 1);
    bytes = file.payload_size();
    ocg::Map map;
    ocg::LoadMap(file.payload(), &map, 8);
    ocg::BowDatabase database(100000);
    for (const auto& [id, keyframe] : map.keyframes()) {
      if (!keyframe->bad) database.Add(static_cast<int>(id), keyframe->bow);
    }
    points = map.points().size();
    benchmark::DoNotOptimize(database.size());
  }
  state.counters["keyframes"] = keyframes;
  state.counters["map_points"] = static_cast<double>(points);
  state.counters["file_MB"] = static_cast<double>(bytes) / 1e6;
}
BENCHMARK(BM_LoadMapFile)->Arg(100)->Arg(500)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
