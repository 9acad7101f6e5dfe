// Feature benchmarks: ORB extraction per 640x480 frame at 1000 features, matching,
// vocabulary transform and load times (docs/features.md quotes the figures).
//
// Real frames come from ../shared/data when present (else only procedural images).

#include <benchmark/benchmark.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "ocg/features/bow_database.h"
#include "ocg/features/matcher.h"
#include "ocg/features/orb_extractor.h"
#include "ocg/features/vocabulary.h"
#include "ocg/io/sequence.h"
#include "ocg/sim/texture.h"
#include "test_support.h"

namespace {

cv::Mat ProceduralFrame(std::uint64_t seed) {
  cv::Mat gray;
  cv::cvtColor(ocg::sim::MakeTexture(seed, 640, 1.5)(cv::Rect(0, 80, 640, 480)), gray,
               cv::COLOR_BGR2GRAY);
  return gray;
}

std::vector<cv::Mat> TumFrames() {
  std::vector<cv::Mat> frames;
  if (const auto data = ocg::testing::SharedDataDir()) {
    for (const auto& image : ocg::ReadTumSequence(*data + "/tum_fr3_long_office").images) {
      frames.push_back(cv::imread(image.path, cv::IMREAD_GRAYSCALE));
    }
  }
  return frames;
}

const ocg::Vocabulary& DefaultVocabulary() {
  static const ocg::Vocabulary vocabulary =
      ocg::Vocabulary::Load(ocg::VocabularyOptions{}.Resolve());
  return vocabulary;
}

void BM_ExtractProcedural(benchmark::State& state) {
  ocg::OrbExtractorOptions options;
  options.features = static_cast<int>(state.range(0));
  ocg::OrbExtractor extractor(options);
  const cv::Mat image = ProceduralFrame(1);
  const ocg::PinholeCamera camera;
  std::size_t count = 0;
  for (auto _ : state) count = extractor.Extract(image, camera).size();
  state.counters["keypoints"] = static_cast<double>(count);
}
BENCHMARK(BM_ExtractProcedural)->Arg(1000)->Arg(2000)->Unit(benchmark::kMillisecond);

void BM_ExtractTum(benchmark::State& state) {
  const std::vector<cv::Mat> frames = TumFrames();
  if (frames.empty()) {
    state.SkipWithError(ocg::testing::SharedDataSkipMessage().c_str());
    return;
  }
  ocg::OrbExtractor extractor{ocg::OrbExtractorOptions{}};
  const ocg::PinholeCamera camera;
  std::size_t i = 0;
  for (auto _ : state)
    benchmark::DoNotOptimize(extractor.Extract(frames[i++ % frames.size()], camera));
}
BENCHMARK(BM_ExtractTum)->Unit(benchmark::kMillisecond);

struct Pair {
  ocg::ExtractedFeatures a, b;
};
const Pair& ShiftedPair() {
  static const Pair pair = [] {
    ocg::OrbExtractor extractor{ocg::OrbExtractorOptions{}};
    const ocg::PinholeCamera camera;
    const cv::Mat image = ProceduralFrame(2);
    // The next frame of a slow pan: the image shifted by (3, 2) pixels.
    cv::Mat shifted;
    const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, 3, 0, 1, 2);
    cv::warpAffine(image, shifted, shift, image.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT_101);
    return Pair{extractor.Extract(image, camera), extractor.Extract(shifted, camera)};
  }();
  return pair;
}

void BM_MatchBruteForce(benchmark::State& state) {
  const Pair& pair = ShiftedPair();
  for (auto _ : state) {
    benchmark::DoNotOptimize(ocg::MatchBruteForce(pair.a.descriptors, pair.b.descriptors, 0.8, 64));
  }
}
BENCHMARK(BM_MatchBruteForce)->Unit(benchmark::kMillisecond);

void BM_SearchByProjection(benchmark::State& state) {
  const Pair& pair = ShiftedPair();
  std::vector<ocg::ProjectedPoint> points;
  for (std::size_t i = 0; i < pair.a.size(); ++i) {
    ocg::ProjectedPoint point;
    point.pixel = pair.a.undistorted[i];  // predicted 3.6 pixels off: no motion model
    point.radius = static_cast<double>(state.range(0));
    point.min_level = std::max(0, pair.a.keypoints[i].octave - 1);
    point.max_level = pair.a.keypoints[i].octave + 1;
    point.descriptor = pair.a.descriptors[i];
    points.push_back(point);
  }
  const ocg::MatcherOptions options;
  std::size_t matched = 0;
  for (auto _ : state) {
    const std::vector<int> matches =
        ocg::SearchByProjection(pair.b, points, nullptr, 0.8, options.loose_distance, options);
    matched = static_cast<std::size_t>(
        std::count_if(matches.begin(), matches.end(), [](int m) { return m != ocg::kNoMatch; }));
  }
  state.counters["matches"] = static_cast<double>(matched);
}
BENCHMARK(BM_SearchByProjection)->Arg(7)->Arg(15)->Unit(benchmark::kMillisecond);

void BM_Transform(benchmark::State& state) {
  const ocg::Vocabulary& vocabulary = DefaultVocabulary();
  const Pair& pair = ShiftedPair();
  ocg::BowVector bow;
  ocg::FeatureVector features;
  for (auto _ : state) vocabulary.Transform(pair.a.descriptors, &bow, &features, 2);
  state.counters["words"] = static_cast<double>(bow.size());
}
BENCHMARK(BM_Transform)->Unit(benchmark::kMillisecond);

void BM_SearchByBow(benchmark::State& state) {
  const ocg::Vocabulary& vocabulary = DefaultVocabulary();
  const Pair& pair = ShiftedPair();
  ocg::BowVector bow_a, bow_b;
  ocg::FeatureVector fv_a, fv_b;
  vocabulary.Transform(pair.a.descriptors, &bow_a, &fv_a, 2);
  vocabulary.Transform(pair.b.descriptors, &bow_b, &fv_b, 2);
  const ocg::BowFeatures a{&fv_a, &pair.a.descriptors, &pair.a.keypoints, nullptr};
  const ocg::BowFeatures b{&fv_b, &pair.b.descriptors, &pair.b.keypoints, nullptr};
  const ocg::MatcherOptions options;
  for (auto _ : state) benchmark::DoNotOptimize(ocg::SearchByBow(a, b, options));
}
BENCHMARK(BM_SearchByBow)->Unit(benchmark::kMillisecond);

void BM_DatabaseQuery(benchmark::State& state) {
  // A database of state.range(0) images of 1000 random descriptors each.
  const ocg::Vocabulary& vocabulary = DefaultVocabulary();
  ocg::BowDatabase database(vocabulary.WordCount());
  std::mt19937_64 rng(3);
  ocg::BowVector bow;
  for (int image = 0; image < state.range(0); ++image) {
    std::vector<ocg::Descriptor> descriptors(1000);
    for (auto& d : descriptors) d = {rng(), rng(), rng(), rng()};
    vocabulary.Transform(descriptors, &bow);
    database.Add(image, bow);
  }
  for (auto _ : state) benchmark::DoNotOptimize(database.Query(bow, 10));
}
BENCHMARK(BM_DatabaseQuery)->Arg(100)->Arg(1000)->Unit(benchmark::kMillisecond);

void BM_LoadDefaultVocabulary(benchmark::State& state) {
  const std::string path = ocg::VocabularyOptions{}.Resolve();
  for (auto _ : state) benchmark::DoNotOptimize(ocg::Vocabulary::Load(path));
  state.counters["nodes"] = static_cast<double>(DefaultVocabulary().NodeCount());
}
BENCHMARK(BM_LoadDefaultVocabulary)->Unit(benchmark::kMillisecond);

// ORBvoc.txt's size: k = 10, L = 6, about a million words. Random descriptors and
// weights; the load time depends only on the size.
struct TemporaryFolder {
  std::string path = ocg::testing::MakeTempDir("vocabulary_bench");
  ~TemporaryFolder() { std::filesystem::remove_all(path); }
};

std::string MillionNodeVocabulary(bool text) {
  static const TemporaryFolder temporary;
  const std::string& folder = temporary.path;
  const std::string path = folder + (text ? "/million.txt" : "/million.ocgvoc");
  if (std::filesystem::exists(path)) return path;
  std::mt19937_64 rng(4);
  std::vector<ocg::NodeId> parents = {ocg::Vocabulary::kNoParent};
  std::vector<int> depth = {0};
  for (std::size_t node = 0; node < parents.size(); ++node) {
    if (depth[node] == 6) continue;
    for (int c = 0; c < 10; ++c) {
      parents.push_back(static_cast<ocg::NodeId>(node));
      depth.push_back(depth[node] + 1);
    }
  }
  const std::size_t n = parents.size();
  std::vector<ocg::Descriptor> descriptors(n);
  for (auto& d : descriptors) d = {rng(), rng(), rng(), rng()};
  std::vector<double> weights(n);
  std::vector<bool> leaf(n);
  std::uniform_real_distribution<double> weight(0.0, 5.0);
  for (std::size_t i = 0; i < n; ++i) {
    leaf[i] = depth[i] == 6;
    weights[i] = leaf[i] ? weight(rng) : 0.0;
  }
  const ocg::Vocabulary vocabulary =
      ocg::Vocabulary::FromNodes(10, 6, parents, descriptors, weights, leaf);
  text ? vocabulary.SaveOrbSlamText(path) : vocabulary.SaveBinary(path);
  return path;
}

// state.range(0): 0 binary, 1 ORB-SLAM2 text.
void BM_LoadMillionWordVocabulary(benchmark::State& state) {
  const std::string path = MillionNodeVocabulary(state.range(0) == 1);
  std::size_t nodes = 0;
  for (auto _ : state) nodes = ocg::Vocabulary::Load(path).NodeCount();
  state.counters["nodes"] = static_cast<double>(nodes);
  state.counters["MB"] = static_cast<double>(std::filesystem::file_size(path)) / 1e6;
}
BENCHMARK(BM_LoadMillionWordVocabulary)
    ->ArgName("text")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
