#include "ocg/features/vocabulary.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <set>

#include "feature_test_images.h"
#include "ocg/core/file_io.h"
#include "ocg/features/bow_database.h"
#include "ocg/features/matcher.h"
#include "test_support.h"

namespace ocg {
namespace {

// Features of a few procedural images and their slightly changed copies; the
// vocabulary is trained on the originals only.
class VocabularyTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    OrbExtractor extractor{OrbExtractorOptions{}};
    const PinholeCamera camera;
    for (int i = 0; i < kImages; ++i) {
      const cv::Mat image = testing::TexturedImage(100 + static_cast<std::uint64_t>(i));
      originals_.push_back(extractor.Extract(image, camera));
      cv::Mat changed = testing::RotateAndScale(image, 4.0, 1.05);
      changed.convertTo(changed, -1, 0.9, 12.0);  // a little darker, less contrast
      copies_.push_back(extractor.Extract(changed, camera));
    }
    VocabularyTrainingOptions options;
    options.branching = 10;
    options.depth = 4;
    vocabulary_ = new Vocabulary(Vocabulary::Train(Descriptors(), options));
  }
  static void TearDownTestSuite() {
    delete vocabulary_;
    originals_.clear();
    copies_.clear();
  }
  static std::vector<std::vector<Descriptor>> Descriptors() {
    std::vector<std::vector<Descriptor>> images;
    for (const ExtractedFeatures& f : originals_) images.push_back(f.descriptors);
    return images;
  }

  static constexpr int kImages = 8;
  static std::vector<ExtractedFeatures> originals_;
  static std::vector<ExtractedFeatures> copies_;
  static Vocabulary* vocabulary_;
};
std::vector<ExtractedFeatures> VocabularyTest::originals_;
std::vector<ExtractedFeatures> VocabularyTest::copies_;
Vocabulary* VocabularyTest::vocabulary_ = nullptr;

// A vocabulary path that is a named pipe or a directory is named, not waited on or read
// as an empty file.
TEST(VocabularyFile, ANamedPipeOrADirectoryIsNamed) {
  const std::string dir = testing::MakeTempDir("fifo_vocabulary");
  ASSERT_EQ(::mkfifo((dir + "/voc.ocgvoc").c_str(), 0600), 0);
  for (const std::string& path : {dir + "/voc.ocgvoc", dir}) {
    try {
      Vocabulary::Load(path);
      ADD_FAILURE() << "no FileError for " << path;
    } catch (const FileError& error) {
      EXPECT_NE(std::string(error.what()).find("cannot read '" + path + "': it is a "),
                std::string::npos)
          << error.what();
    }
  }
}

TEST_F(VocabularyTest, TrainingBuildsATreeOfTheRequestedShape) {
  const Vocabulary& v = *vocabulary_;
  EXPECT_EQ(v.branching(), 10);
  EXPECT_EQ(v.depth(), 4);
  EXPECT_LE(v.NodeCount(), 1u + 10u + 100u + 1000u + 10000u);
  EXPECT_GT(v.WordCount(), 3000u);
  for (WordId word = 0; word < v.WordCount(); ++word) {
    const NodeId node = v.WordNode(word);
    EXPECT_TRUE(v.IsLeaf(node));
    EXPECT_LE(v.NodeDepth(node), 4);
    EXPECT_GE(v.WordWeight(word), 0.0);
    EXPECT_LE(v.WordWeight(word), std::log(8.0) + 1e-12);
  }
  for (NodeId node = 1; node < v.NodeCount(); ++node) {
    EXPECT_LT(v.Parent(node), node);
    EXPECT_EQ(v.NodeDepth(node), v.NodeDepth(v.Parent(node)) + 1);
  }
}

TEST_F(VocabularyTest, TrainingIsDeterministicInTheSeed) {
  VocabularyTrainingOptions options;
  options.branching = 10;
  options.depth = 4;
  EXPECT_TRUE(Vocabulary::Train(Descriptors(), options) == *vocabulary_);
  options.seed = 7;
  EXPECT_FALSE(Vocabulary::Train(Descriptors(), options) == *vocabulary_);
}

TEST_F(VocabularyTest, IdfWeightIsZeroForAWordInEveryImage) {
  // Two images that share one descriptor; the other descriptors differ.
  std::vector<std::vector<Descriptor>> images(2);
  const Descriptor shared{1, 2, 3, 4};
  images[0] = {shared, Descriptor{~0ull, ~0ull, 0, 0}};
  images[1] = {shared, Descriptor{0, 0, ~0ull, ~0ull}};
  VocabularyTrainingOptions options;
  options.branching = 3;
  options.depth = 1;
  const Vocabulary v = Vocabulary::Train(images, options);
  ASSERT_EQ(v.WordCount(), 3u);
  EXPECT_EQ(v.WordWeight(v.Quantize(shared)), 0.0);
  EXPECT_NEAR(v.WordWeight(v.Quantize(images[0][1])), std::log(2.0), 1e-12);
}

TEST_F(VocabularyTest, TransformGivesNormalizedVectorsAndCoversEveryWeightedFeature) {
  BowVector bow;
  FeatureVector features;
  vocabulary_->Transform(originals_[0].descriptors, &bow, &features, 2);
  ASSERT_FALSE(bow.empty());
  double total = 0.0;
  for (std::size_t i = 0; i < bow.size(); ++i) {
    total += bow.entries[i].second;
    if (i > 0) {
      EXPECT_LT(bow.entries[i - 1].first, bow.entries[i].first);
    }
  }
  EXPECT_NEAR(total, 1.0, 1e-12);
  std::set<int> covered;
  for (const auto& [node, indices] : features) {
    EXPECT_EQ(vocabulary_->NodeDepth(node), 2);
    for (const int i : indices) EXPECT_TRUE(covered.insert(i).second) << "feature twice";
  }
  EXPECT_GT(covered.size(), originals_[0].size() * 8 / 10);
  EXPECT_NEAR(ScoreL1(bow, bow), 1.0, 1e-12);
  BowVector other;
  vocabulary_->Transform(originals_[1].descriptors, &other);
  const double cross = ScoreL1(bow, other);
  EXPECT_GE(cross, 0.0);
  EXPECT_LT(cross, 0.5);
}

TEST_F(VocabularyTest, BinaryAndTextFilesRoundTrip) {
  const std::string folder = testing::MakeTempDir("vocabulary");
  vocabulary_->SaveBinary(folder + "/v.ocgvoc");
  vocabulary_->SaveOrbSlamText(folder + "/v.txt");
  EXPECT_TRUE(Vocabulary::LoadBinary(folder + "/v.ocgvoc") == *vocabulary_);
  EXPECT_TRUE(Vocabulary::LoadOrbSlamText(folder + "/v.txt") == *vocabulary_);
  EXPECT_TRUE(Vocabulary::Load(folder + "/v.ocgvoc") == *vocabulary_);  // told apart by magic
  EXPECT_TRUE(Vocabulary::Load(folder + "/v.txt") == *vocabulary_);
  // The text is ORB-SLAM2's: "k L scoring weighting", then "parent leaf 32 bytes weight".
  std::ifstream text(folder + "/v.txt");
  std::string header;
  std::getline(text, header);
  EXPECT_EQ(header, "10 4 0 0");
  std::string first;
  std::getline(text, first);
  std::istringstream fields(first);
  int count = 0;
  std::string field;
  while (fields >> field) ++count;
  EXPECT_EQ(count, 35);
  std::filesystem::remove_all(folder);
}

void ExpectLoadError(const std::string& path, const std::string& expected) {
  try {
    Vocabulary::Load(path);
    ADD_FAILURE() << "expected an error loading " << path;
  } catch (const FileError& error) {
    EXPECT_NE(std::string(error.what()).find(expected), std::string::npos) << error.what();
  }
}

TEST_F(VocabularyTest, DamagedFilesGiveErrorsNamingTheFile) {
  const std::string folder = testing::MakeTempDir("vocabulary_damage");
  vocabulary_->SaveBinary(folder + "/v.ocgvoc");
  std::string bytes = ReadTextFile(folder + "/v.ocgvoc");
  WriteFile(folder + "/cut.ocgvoc", bytes.substr(0, bytes.size() - 100));
  ExpectLoadError(folder + "/cut.ocgvoc", "cut.ocgvoc' is truncated");
  WriteFile(folder + "/bad.txt", "10 6 0 0\n0 0 1 2 3\n");
  ExpectLoadError(folder + "/bad.txt", "bad.txt:2: missing descriptor byte");
  WriteFile(folder + "/orphan.txt",
            "2 1 0 0\n5 1 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0.5\n");
  ExpectLoadError(folder + "/orphan.txt", "orphan.txt:2: bad parent id '5'");
  WriteFile(folder + "/scoring.txt", "10 6 2 0\n");
  ExpectLoadError(folder + "/scoring.txt", "scoring.txt:1: only L1 scoring");
  ExpectLoadError(folder + "/missing.ocgvoc",
                  "vocabulary: cannot read '" + folder + "/missing.ocgvoc': it does not exist");
  std::filesystem::remove_all(folder);
}

TEST_F(VocabularyTest, DatabaseReturnsTheImageItselfThenItsChangedCopy) {
  BowDatabase database(vocabulary_->WordCount());
  std::vector<BowVector> original(kImages), copy(kImages);
  for (int i = 0; i < kImages; ++i) {
    vocabulary_->Transform(originals_[static_cast<std::size_t>(i)].descriptors,
                           &original[static_cast<std::size_t>(i)]);
    vocabulary_->Transform(copies_[static_cast<std::size_t>(i)].descriptors,
                           &copy[static_cast<std::size_t>(i)]);
    database.Add(i, original[static_cast<std::size_t>(i)]);
    database.Add(100 + i, copy[static_cast<std::size_t>(i)]);
  }
  EXPECT_EQ(database.size(), 2u * kImages);
  for (int i = 0; i < kImages; ++i) {
    const std::vector<BowQueryResult> results =
        database.Query(original[static_cast<std::size_t>(i)], 3);
    ASSERT_EQ(results.size(), 3u);
    EXPECT_EQ(results[0].id, i);
    EXPECT_NEAR(results[0].score, 1.0, 1e-9);
    EXPECT_EQ(results[1].id, 100 + i);
    EXPECT_GT(results[1].score, 2.0 * results[2].score);
    // The score is the L1 score of the two vectors.
    EXPECT_NEAR(results[1].score,
                ScoreL1(original[static_cast<std::size_t>(i)], copy[static_cast<std::size_t>(i)]),
                1e-12);
  }
  // Erase and exclude.
  database.Erase(0);
  EXPECT_EQ(database.Query(original[0], 1)[0].id, 100);
  EXPECT_EQ(database.Query(original[0], 1, 1, {100})[0].id == 100, false);
  database.Clear();
  EXPECT_TRUE(database.Query(original[0], 0).empty());
}

TEST_F(VocabularyTest, BowMatchingFindsCorrespondencesOfTheChangedCopy) {
  BowVector bow_a, bow_b;
  FeatureVector fv_a, fv_b;
  vocabulary_->Transform(originals_[2].descriptors, &bow_a, &fv_a, 2);
  vocabulary_->Transform(copies_[2].descriptors, &bow_b, &fv_b, 2);
  BowFeatures a{&fv_a, &originals_[2].descriptors, &originals_[2].keypoints, nullptr};
  BowFeatures b{&fv_b, &copies_[2].descriptors, &copies_[2].keypoints, nullptr};
  const MatcherOptions options;
  const std::vector<int> matches = SearchByBow(a, b, options);
  int found = 0;
  int correct = 0;
  const cv::Size size(640, 480);
  for (std::size_t i = 0; i < matches.size(); ++i) {
    if (matches[i] == kNoMatch) continue;
    ++found;
    const cv::Point2f expected = testing::WarpPoint(originals_[2].keypoints[i].pt, size, 4.0, 1.05);
    if (cv::norm(copies_[2].keypoints[static_cast<std::size_t>(matches[i])].pt - expected) <
        3.0 * originals_[2].keypoints[i].size / 31.0) {
      ++correct;
    }
  }
  EXPECT_GE(found, 200);
  EXPECT_GE(correct, found * 95 / 100);
  // A mask keeps the masked-out features unmatched.
  std::vector<bool> usable(originals_[2].size(), false);
  for (std::size_t i = 0; i < usable.size(); i += 3) usable[i] = true;
  a.usable = &usable;
  const std::vector<int> masked = SearchByBow(a, b, options);
  for (std::size_t i = 0; i < masked.size(); ++i) {
    if (!usable[i]) {
      EXPECT_EQ(masked[i], kNoMatch);
    }
  }
}

TEST(DefaultVocabulary, IsFoundAndLoads) {
  const std::string path = DefaultVocabularyPath();
  ASSERT_FALSE(path.empty()) << "no default vocabulary in any of the search paths";
  const Vocabulary vocabulary = Vocabulary::Load(path);
  EXPECT_EQ(vocabulary.branching(), 10);
  EXPECT_EQ(vocabulary.depth(), 5);
  EXPECT_GT(vocabulary.WordCount(), 10000u);
}

}  // namespace
}  // namespace ocg
