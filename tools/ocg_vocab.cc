// ocg_vocab: train a bag-of-words vocabulary of ORB descriptors, convert ORB-SLAM2's
// ORBvoc.txt to our binary format (and back), describe a vocabulary file, and compare
// vocabularies on frame pairs of real sequences.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "cli_common.h"
#include "ocg/app/settings.h"
#include "ocg/core/file_io.h"
#include "ocg/features/bow_pairs.h"
#include "ocg/features/orb_extractor.h"
#include "ocg/features/vocabulary.h"

namespace {

namespace fs = std::filesystem;

bool IsImageFile(const fs::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == ".png" || extension == ".jpg" || extension == ".jpeg" ||
         extension == ".pgm" || extension == ".bmp";
}

// A folder of images, a TUM rgb.txt ("timestamp path"), or a plain list of paths; paths
// in a list are relative to the list's folder. '#' starts a comment line.
std::vector<std::string> ListImages(const std::string& source) {
  std::vector<std::string> images;
  if (fs::is_directory(source)) {
    for (const auto& entry : fs::directory_iterator(source)) {
      if (entry.is_regular_file() && IsImageFile(entry.path())) {
        images.push_back(entry.path().string());
      }
    }
    std::sort(images.begin(), images.end());
    if (images.empty())
      throw ocg::FileError("no images (.png, .jpg, .pgm, .bmp) in '" + source + "'");
    return images;
  }
  const fs::path base = fs::path(source).parent_path();
  std::istringstream lines(ocg::ReadTextFile(source));
  std::string line;
  int number = 0;
  while (std::getline(lines, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::string first, second;
    fields >> first >> second;
    const std::string name = second.empty() ? first : second;
    if (!IsImageFile(name)) {
      throw ocg::FileError(source + ":" + std::to_string(number) + ": '" + name +
                           "' is not an image file name");
    }
    images.push_back(fs::path(name).is_absolute() ? name : (base / name).string());
  }
  if (images.empty()) throw ocg::FileError("'" + source + "' lists no images");
  return images;
}

void Describe(const ocg::Vocabulary& vocabulary, const std::string& path, double seconds) {
  std::cout << path << ": k = " << vocabulary.branching() << ", L = " << vocabulary.depth() << ", "
            << vocabulary.NodeCount() << " nodes, " << vocabulary.WordCount()
            << " words, loaded in " << seconds << " s\n";
}

// ORB descriptors of every image, in order.
std::vector<std::vector<ocg::Descriptor>> ExtractAll(const std::vector<std::string>& images,
                                                     const ocg::OrbExtractorOptions& orb) {
  ocg::OrbExtractor extractor(orb);
  std::vector<std::vector<ocg::Descriptor>> descriptors;
  ocg::ProgressLine progress("images", images.size());
  for (std::size_t i = 0; i < images.size(); ++i) {
    const cv::Mat gray = cv::imread(images[i], cv::IMREAD_GRAYSCALE);
    if (gray.empty()) throw ocg::FileError("cannot read image '" + images[i] + "'");
    std::vector<cv::KeyPoint> keypoints;
    descriptors.emplace_back();
    extractor.Detect(gray, &keypoints, &descriptors.back());
    progress.Update(i + 1);
  }
  progress.Finish();
  return descriptors;
}

void PrintPairStats(const std::string& source, const std::string& vocabulary,
                    const ocg::BowPairStats& stats) {
  std::printf("| %s | %s | %zu / %zu | %.4f / %.4f | %.3f |", source.c_str(), vocabulary.c_str(),
              stats.true_pairs, stats.false_pairs, stats.mean_true, stats.mean_false, stats.auc);
  for (const double auc : stats.auc_by_gap) std::printf(" %.3f", auc);
  std::printf(" | %.3f |\n", stats.recall_at_near);
}

double Since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ocg_vocab: ORB bag-of-words vocabularies (docs/features.md)", "ocg_vocab"};
  std::string log_level;
  ocg::tools::AddLogLevelOption(app, &log_level);
  app.require_subcommand(1);
  app.fallthrough();  // --log-level may follow the subcommand too

  auto* train = app.add_subcommand("train", "train a vocabulary on images");
  std::vector<std::string> sources;
  std::string output, settings_path;
  ocg::VocabularyTrainingOptions training;
  int every = 1;
  bool text = false;
  train
      ->add_option("--images", sources,
                   "a folder of images, a TUM rgb.txt, or a file listing image paths "
                   "(repeat for several)")
      ->required();
  train->add_option("--k", training.branching, "branches per node")->capture_default_str();
  train->add_option("--L", training.depth, "levels below the root")->capture_default_str();
  train->add_option("--seed", training.seed, "k-means++ seed")->capture_default_str();
  train->add_option("--iterations", training.max_iterations, "k-majority rounds per node at most")
      ->capture_default_str();
  train->add_option("--every", every, "use every N-th image of each source")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  train
      ->add_option("--settings", settings_path,
                   "settings file whose ORBextractor.* keys configure the features")
      ->check(CLI::ExistingFile);
  train->add_option("--out", output, "output vocabulary file")->required();
  train->add_flag("--text", text, "write ORB-SLAM2's text format instead of the binary one");

  auto* convert = app.add_subcommand("convert", "convert a vocabulary file");
  std::string orbvoc, input;
  auto* orbvoc_option =
      convert->add_option("--orbvoc", orbvoc, "ORB-SLAM2 text vocabulary (ORBvoc.txt)")
          ->check(CLI::ExistingFile);
  convert->add_option("--in", input, "a vocabulary in either format")
      ->check(CLI::ExistingFile)
      ->excludes(orbvoc_option);
  convert->add_option("--out", output, "output file (binary unless --text)")->required();
  convert->add_flag("--text", text, "write ORB-SLAM2's text format");

  auto* info = app.add_subcommand("info", "load a vocabulary and describe it");
  std::string info_path;
  info->add_option("file", info_path, "vocabulary file (binary or ORB-SLAM2 text)")
      ->required()
      ->check(CLI::ExistingFile);

  auto* pairs = app.add_subcommand(
      "pairs",
      "compare vocabularies on frame pairs of sequences that never revisit a place: BoW "
      "scores of frames 1..near apart (same place) against frames >= far apart");
  std::vector<std::string> vocabularies, pair_sources;
  ocg::BowPairOptions pair_options;
  pairs->add_option("--vocabulary", vocabularies, "vocabulary file (repeat to compare several)")
      ->required()
      ->check(CLI::ExistingFile);
  pairs->add_option("--images", pair_sources, "a sequence: folder, TUM rgb.txt or list (repeat)")
      ->required();
  pairs->add_option("--near", pair_options.near, "frames 1..near apart see the same place")
      ->capture_default_str();
  pairs->add_option("--far", pair_options.far, "frames at least far apart see other places")
      ->capture_default_str();
  pairs
      ->add_option("--settings", settings_path,
                   "settings file whose ORBextractor.* keys configure the features")
      ->check(CLI::ExistingFile);

  return ocg::tools::RunTool(app, argc, argv, log_level, [&] {
    if (*pairs) {
      pair_options.Check();
      ocg::OrbExtractorOptions orb;
      if (!settings_path.empty()) orb = ocg::LoadSettings(settings_path).settings.orb;
      std::vector<ocg::Vocabulary> loaded;
      for (const std::string& path : vocabularies) loaded.push_back(ocg::Vocabulary::Load(path));
      std::printf(
          "| sequence | vocabulary | true / false pairs | mean score true / false | AUC "
          "| AUC at gap 1..%d | recall at gap %d |\n|---|---|---|---|---|---|---|\n",
          pair_options.near, pair_options.near);
      for (const std::string& source : pair_sources) {
        const auto descriptors = ExtractAll(ListImages(source), orb);
        for (std::size_t v = 0; v < loaded.size(); ++v) {
          std::vector<ocg::BowVector> bows(descriptors.size());
          for (std::size_t i = 0; i < descriptors.size(); ++i) {
            loaded[v].Transform(descriptors[i], &bows[i]);
          }
          PrintPairStats(source, vocabularies[v], ocg::CompareBowPairs(bows, pair_options));
        }
      }
      return;
    }
    if (*info) {
      const auto start = std::chrono::steady_clock::now();
      const ocg::Vocabulary vocabulary = ocg::Vocabulary::Load(info_path);
      Describe(vocabulary, info_path, Since(start));
      return;
    }
    if (*convert) {
      const std::string from = orbvoc.empty() ? input : orbvoc;
      if (from.empty()) throw std::invalid_argument("convert needs --orbvoc FILE or --in FILE");
      const auto start = std::chrono::steady_clock::now();
      const ocg::Vocabulary vocabulary =
          orbvoc.empty() ? ocg::Vocabulary::Load(from) : ocg::Vocabulary::LoadOrbSlamText(from);
      Describe(vocabulary, from, Since(start));
      text ? vocabulary.SaveOrbSlamText(output) : vocabulary.SaveBinary(output);
      std::cout << "wrote " << output << "\n";
      return;
    }
    training.Check();
    ocg::OrbExtractorOptions orb;
    if (!settings_path.empty()) orb = ocg::LoadSettings(settings_path).settings.orb;
    std::vector<std::string> images;
    for (const std::string& source : sources) {
      const std::vector<std::string> listed = ListImages(source);
      for (std::size_t i = 0; i < listed.size(); i += static_cast<std::size_t>(every)) {
        images.push_back(listed[i]);
      }
    }
    std::cout << "extracting ORB features (" << orb.features << " per image) from " << images.size()
              << " images\n";
    const auto descriptors = ExtractAll(images, orb);
    std::size_t total = 0;
    for (const auto& image : descriptors) total += image.size();
    std::cout << "clustering " << total << " descriptors (k = " << training.branching
              << ", L = " << training.depth << ", seed " << training.seed << ")\n";
    const auto start = std::chrono::steady_clock::now();
    const ocg::Vocabulary vocabulary = ocg::Vocabulary::Train(descriptors, training);
    std::cout << "trained in " << Since(start) << " s: " << vocabulary.NodeCount() << " nodes, "
              << vocabulary.WordCount() << " words\n";
    text ? vocabulary.SaveOrbSlamText(output) : vocabulary.SaveBinary(output);
    std::cout << "wrote " << output << "\n";
  });
}
