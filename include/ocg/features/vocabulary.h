#pragma once
// A hierarchical bag-of-words vocabulary of binary descriptors: a tree of k-majority
// clusters (k branches, L levels) whose leaves are the words, TF-IDF weights, L1 scores.
// Reads ORB-SLAM2's text vocabulary (ORBvoc.txt) and our compact binary format.
//
// Thread safety: a loaded Vocabulary is immutable; Transform and Score may be called
// from any number of threads at once.

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "ocg/core/option_fields.h"
#include "ocg/features/descriptor.h"

namespace ocg {

class SettingsFile;

using WordId = std::uint32_t;
using NodeId = std::uint32_t;

// Word weights, L1-normalized, sorted by word id.
struct BowVector {
  std::vector<std::pair<WordId, double>> entries;
  bool empty() const { return entries.empty(); }
  std::size_t size() const { return entries.size(); }
};

// Vocabulary node (at a chosen depth) -> indices of the features under it, ascending.
using FeatureVector = std::map<NodeId, std::vector<int>>;

// Calls visit(node, features_of_a, features_of_b) for every node both feature vectors
// hold, in ascending node order: the candidates of BoW-accelerated matching.
template <typename Visit>
void ForEachSharedNode(const FeatureVector& a, const FeatureVector& b, Visit visit) {
  auto it_a = a.begin();
  auto it_b = b.begin();
  while (it_a != a.end() && it_b != b.end()) {
    if (it_a->first < it_b->first) {
      ++it_a;
    } else if (it_b->first < it_a->first) {
      ++it_b;
    } else {
      visit(it_a->first, it_a->second, it_b->second);
      ++it_a;
      ++it_b;
    }
  }
}

// 1 - |a - b|_1 / 2 for L1-normalized vectors: 1 for equal vectors, 0 for disjoint ones.
double ScoreL1(const BowVector& a, const BowVector& b);

struct VocabularyTrainingOptions {
  int branching = 10;       // k: children per node
  int depth = 5;            // L: levels below the root
  int max_iterations = 10;  // k-majority rounds per node (stops earlier when stable)
  std::uint64_t seed = 42;  // k-means++ seeding
  void Check() const;       // throws std::invalid_argument
};

class Vocabulary {
 public:
  static constexpr NodeId kRoot = 0;
  static constexpr NodeId kNoParent = 0xffffffffu;
  static constexpr WordId kNoWord = 0xffffffffu;

  Vocabulary() = default;

  // Trains on the descriptors of a set of images (one vector per image; the images
  // decide the IDF weights). Deterministic for a given seed; single-threaded.
  static Vocabulary Train(const std::vector<std::vector<Descriptor>>& images,
                          const VocabularyTrainingOptions& options);

  // Builds a vocabulary from its nodes in any order where parents come before children
  // (ORB-SLAM2's text order); node 0 is the root. Throws std::invalid_argument when the
  // nodes do not form a tree.
  static Vocabulary FromNodes(int branching, int depth, const std::vector<NodeId>& parents,
                              const std::vector<Descriptor>& descriptors,
                              const std::vector<double>& weights, const std::vector<bool>& is_leaf);

  // Load: binary or ORB-SLAM2 text, told apart by the first bytes. Errors are
  // std::runtime_error naming the file (and the line, for text).
  static Vocabulary Load(const std::string& path);
  static Vocabulary LoadBinary(const std::string& path);
  static Vocabulary LoadOrbSlamText(const std::string& path);
  // Written to a temporary file, then renamed: an existing file is never half-replaced.
  void SaveBinary(const std::string& path) const;
  void SaveOrbSlamText(const std::string& path) const;

  bool empty() const { return parents_.empty(); }
  int branching() const { return branching_; }
  int depth() const { return depth_; }
  std::size_t NodeCount() const { return parents_.size(); }
  std::size_t WordCount() const { return word_nodes_.size(); }

  NodeId Parent(NodeId node) const { return parents_[node]; }
  const Descriptor& NodeDescriptor(NodeId node) const { return descriptors_[node]; }
  double Weight(NodeId node) const { return weights_[node]; }
  bool IsLeaf(NodeId node) const { return word_of_node_[node] != kNoWord; }
  int NodeDepth(NodeId node) const { return node_depth_[node]; }
  NodeId WordNode(WordId word) const { return word_nodes_[word]; }
  double WordWeight(WordId word) const { return weights_[word_nodes_[word]]; }

  // The word of a descriptor; node_at_depth (optional) receives the ancestor of the word
  // at feature_depth (or the leaf when it is shallower).
  WordId Quantize(const Descriptor& descriptor, int feature_depth = 2,
                  NodeId* node_at_depth = nullptr) const;

  // BoW vector (TF-IDF, L1-normalized) of an image's descriptors, and (optionally) its
  // feature vector at feature_depth below the root.
  void Transform(const std::vector<Descriptor>& descriptors, BowVector* bow,
                 FeatureVector* features = nullptr, int feature_depth = 2) const;

  // Same tree, descriptors, weights and leaves.
  bool operator==(const Vocabulary& other) const;
  bool operator!=(const Vocabulary& other) const { return !(*this == other); }

 private:
  void BuildIndex();  // children lists, depths and word ids from parents_ and leaves

  int branching_ = 0;
  int depth_ = 0;
  std::vector<NodeId> parents_;
  std::vector<Descriptor> descriptors_;
  std::vector<double> weights_;
  std::vector<WordId> word_of_node_;  // kNoWord for inner nodes
  // Derived by BuildIndex:
  std::vector<std::uint32_t> first_child_;  // children of n: child_list_[first_child_[n] ..
  std::vector<std::uint32_t> child_count_;  //   first_child_[n] + child_count_[n])
  std::vector<NodeId> child_list_;
  std::vector<std::uint8_t> node_depth_;
  std::vector<NodeId> word_nodes_;
};

// Vocabulary.* settings.
struct VocabularyOptions {
  // Vocabulary.path: binary or ORB-SLAM2 text vocabulary; empty: DefaultVocabularyPath().
  std::string path;

  // The settings keys, once (ocg/core/option_fields.h).
  template <typename Self, typename Visitor>
  static void VisitFields(Self& self, Visitor&& visit) {
    visit("Vocabulary.path", self.path, OptionBound::Any(),
          "binary or ORB-SLAM2 text vocabulary; empty: `$OCG_VOCABULARY`, then the installed "
          "`share/ocg/ocg_orb_vocabulary.ocgvoc`, then the source tree's "
          "`thirdparty/vocabulary/`");
  }
  void Check() const {}  // the file is checked when it is loaded
  // path, or the default; throws std::runtime_error listing where it looked when none.
  std::string Resolve() const;
};

void ReadSettings(const SettingsFile& file, VocabularyOptions* options);

// Where the default vocabulary is looked for: $OCG_VOCABULARY, then the installed data
// folder, then thirdparty/ of the source tree the library was built from. Returns the
// first existing file, or an empty string.
std::string DefaultVocabularyPath();
// Every place DefaultVocabularyPath looks, for error messages.
std::vector<std::string> VocabularySearchPaths();

}  // namespace ocg
