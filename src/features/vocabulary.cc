#include "ocg/features/vocabulary.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <limits>
#include <random>
#include <stdexcept>

#include "ocg/core/file_io.h"
#include "ocg/core/settings_file.h"

#if !defined(__BYTE_ORDER__) || __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "the binary vocabulary format is little-endian; add byte swapping for this machine"
#endif

namespace ocg {
namespace {

constexpr char kBinaryMagic[8] = {'O', 'C', 'G', 'V', 'O', 'C', '1', '\n'};
constexpr char kBinaryEnd[8] = {'O', 'C', 'G', 'V', 'E', 'N', 'D', '\n'};
constexpr std::uint32_t kScoringL1 = 0;  // ORB-SLAM2 / DBoW2 numbering
constexpr std::uint32_t kWeightingTfIdf = 0;

struct BinaryHeader {
  char magic[8];
  std::uint32_t branching;
  std::uint32_t depth;
  std::uint32_t scoring;
  std::uint32_t weighting;
  std::uint64_t node_count;
};
static_assert(sizeof(BinaryHeader) == 32, "header layout");

std::size_t BinarySize(std::uint64_t nodes) {
  return sizeof(BinaryHeader) + nodes * (sizeof(NodeId) + 1 + kDescriptorBytes + sizeof(double)) +
         sizeof(kBinaryEnd);
}

// A FIFO would block fopen, a directory read as empty: both named, as a missing file.
void RequireVocabularyFile(const std::string& path) {
  try {
    RequireRegularFile(path);
  } catch (const FileError& error) {
    throw FileError(std::string("vocabulary: ") + error.what());
  }
}

std::string ReadWholeFile(const std::string& path) {
  RequireVocabularyFile(path);
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) {
    throw FileError("cannot open vocabulary '" + path + "': " + std::strerror(errno));
  }
  std::string content;
  std::error_code error;
  const auto size = std::filesystem::file_size(path, error);
  if (!error) content.resize(static_cast<std::size_t>(size));
  const std::size_t read = std::fread(content.data(), 1, content.size(), file);
  std::fclose(file);
  if (read != content.size()) throw FileError("error while reading vocabulary '" + path + "'");
  return content;
}

// One clustering step of hierarchical k-majority: k-means++ seeding, then rounds of
// nearest-centre assignment and bitwise-majority centres until nothing moves.
struct Clusters {
  std::vector<Descriptor> centres;
  std::vector<std::vector<int>> members;  // indices into the descriptors
};

Clusters KMajority(const std::vector<Descriptor>& all, const std::vector<int>& members, int k,
                   int max_iterations, std::mt19937_64& rng) {
  Clusters clusters;
  if (static_cast<int>(members.size()) <= k) {
    for (const int member : members) {
      clusters.centres.push_back(all[static_cast<std::size_t>(member)]);
      clusters.members.push_back({member});
    }
    return clusters;
  }
  // k-means++: each next centre drawn with probability proportional to the squared
  // distance to the nearest centre chosen so far.
  std::vector<Descriptor>& centres = clusters.centres;
  std::uniform_int_distribution<std::size_t> first(0, members.size() - 1);
  centres.push_back(all[static_cast<std::size_t>(members[first(rng)])]);
  std::vector<double> nearest(members.size(), std::numeric_limits<double>::max());
  while (static_cast<int>(centres.size()) < k) {
    double total = 0.0;
    for (std::size_t i = 0; i < members.size(); ++i) {
      const double d = HammingDistance(all[static_cast<std::size_t>(members[i])], centres.back());
      nearest[i] = std::min(nearest[i], d * d);
      total += nearest[i];
    }
    if (total <= 0.0) break;  // every descriptor equals a centre already
    std::uniform_real_distribution<double> pick(0.0, total);
    double target = pick(rng);
    std::size_t chosen = 0;
    for (; chosen + 1 < members.size(); ++chosen) {
      target -= nearest[chosen];
      if (target <= 0.0 && nearest[chosen] > 0.0) break;
    }
    centres.push_back(all[static_cast<std::size_t>(members[chosen])]);
  }
  std::vector<int> assignment(members.size(), -1);
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    bool changed = false;
    for (std::size_t i = 0; i < members.size(); ++i) {
      const Descriptor& d = all[static_cast<std::size_t>(members[i])];
      int best = 0;
      int best_distance = HammingDistance(d, centres[0]);
      for (std::size_t c = 1; c < centres.size(); ++c) {
        const int distance = HammingDistance(d, centres[c]);
        if (distance < best_distance) {
          best_distance = distance;
          best = static_cast<int>(c);
        }
      }
      if (assignment[i] != best) {
        assignment[i] = best;
        changed = true;
      }
    }
    if (!changed) break;
    std::vector<std::vector<const Descriptor*>> grouped(centres.size());
    for (std::size_t i = 0; i < members.size(); ++i) {
      grouped[static_cast<std::size_t>(assignment[i])].push_back(
          &all[static_cast<std::size_t>(members[i])]);
    }
    for (std::size_t c = 0; c < centres.size(); ++c) {
      if (!grouped[c].empty()) centres[c] = MajorityDescriptor(grouped[c]);
    }
  }
  std::vector<std::vector<int>> grouped(centres.size());
  for (std::size_t i = 0; i < members.size(); ++i) {
    grouped[static_cast<std::size_t>(assignment[i])].push_back(members[i]);
  }
  Clusters kept;
  for (std::size_t c = 0; c < centres.size(); ++c) {
    if (grouped[c].empty()) continue;
    kept.centres.push_back(centres[c]);
    kept.members.push_back(std::move(grouped[c]));
  }
  return kept;
}

// Finds the next field of the line in [cursor, end): false when none is left.
bool NextField(const char*& cursor, const char* end, const char** field_end) {
  while (cursor < end && (*cursor == ' ' || *cursor == '\t' || *cursor == '\r')) ++cursor;
  if (cursor >= end) return false;
  *field_end = cursor;
  while (*field_end < end && **field_end != ' ' && **field_end != '\t' && **field_end != '\r') {
    ++*field_end;
  }
  return true;
}

}  // namespace

double ScoreL1(const BowVector& a, const BowVector& b) {
  double shared = 0.0;
  auto i = a.entries.begin();
  auto j = b.entries.begin();
  while (i != a.entries.end() && j != b.entries.end()) {
    if (i->first < j->first) {
      ++i;
    } else if (j->first < i->first) {
      ++j;
    } else {
      shared += std::min(i->second, j->second);
      ++i;
      ++j;
    }
  }
  return shared;
}

void VocabularyTrainingOptions::Check() const {
  if (branching < 2 || branching > 64) {
    throw std::invalid_argument("vocabulary branching factor k must be in [2, 64]");
  }
  if (depth < 1 || depth > 12) throw std::invalid_argument("vocabulary depth L must be in [1, 12]");
  if (std::pow(static_cast<double>(branching), depth) > 2e9) {
    throw std::invalid_argument("vocabulary too large: k^L must stay below 2e9 words");
  }
  if (max_iterations < 1) throw std::invalid_argument("max_iterations must be positive");
}

Vocabulary Vocabulary::Train(const std::vector<std::vector<Descriptor>>& images,
                             const VocabularyTrainingOptions& options) {
  options.Check();
  std::vector<Descriptor> all;
  for (const auto& image : images) all.insert(all.end(), image.begin(), image.end());
  if (all.empty()) throw std::invalid_argument("no descriptors to train a vocabulary on");
  std::mt19937_64 rng(options.seed);
  std::vector<NodeId> parents = {kNoParent};
  std::vector<Descriptor> descriptors = {Descriptor{}};
  std::vector<bool> is_leaf = {false};
  std::vector<int> depth_of = {0};
  struct Pending {
    NodeId node;
    std::vector<int> members;
  };
  // Breadth first, so that node ids grow level by level.
  std::deque<Pending> pending;
  std::vector<int> everything(all.size());
  for (std::size_t i = 0; i < all.size(); ++i) everything[i] = static_cast<int>(i);
  pending.push_back({kRoot, std::move(everything)});
  while (!pending.empty()) {
    Pending job = std::move(pending.front());
    pending.pop_front();
    const Clusters clusters =
        KMajority(all, job.members, options.branching, options.max_iterations, rng);
    const int child_depth = depth_of[job.node] + 1;
    for (std::size_t c = 0; c < clusters.centres.size(); ++c) {
      const NodeId child = static_cast<NodeId>(parents.size());
      parents.push_back(job.node);
      descriptors.push_back(clusters.centres[c]);
      depth_of.push_back(child_depth);
      const bool leaf = child_depth == options.depth || clusters.members[c].size() <= 1;
      is_leaf.push_back(leaf);
      if (!leaf) pending.push_back({child, clusters.members[c]});
    }
  }
  std::vector<double> weights(parents.size(), 0.0);
  Vocabulary vocabulary =
      FromNodes(options.branching, options.depth, parents, descriptors, weights, is_leaf);
  // IDF: log(images / images containing the word). A word no image reaches by descent
  // gets the largest weight, as if one image had it.
  std::vector<int> images_with_word(vocabulary.WordCount(), 0);
  std::vector<int> last_image(vocabulary.WordCount(), -1);
  for (std::size_t image = 0; image < images.size(); ++image) {
    for (const Descriptor& d : images[image]) {
      const WordId word = vocabulary.Quantize(d);
      if (last_image[word] != static_cast<int>(image)) {
        last_image[word] = static_cast<int>(image);
        ++images_with_word[word];
      }
    }
  }
  const double image_count = static_cast<double>(images.size());
  for (WordId word = 0; word < vocabulary.WordCount(); ++word) {
    vocabulary.weights_[vocabulary.word_nodes_[word]] =
        std::log(image_count / std::max(1, images_with_word[word]));
  }
  return vocabulary;
}

Vocabulary Vocabulary::FromNodes(int branching, int depth, const std::vector<NodeId>& parents,
                                 const std::vector<Descriptor>& descriptors,
                                 const std::vector<double>& weights,
                                 const std::vector<bool>& is_leaf) {
  const std::size_t n = parents.size();
  if (n == 0 || descriptors.size() != n || weights.size() != n || is_leaf.size() != n) {
    throw std::invalid_argument(
        "vocabulary nodes: parents, descriptors, weights and leaves differ "
        "in count");
  }
  if (parents[0] != kNoParent) throw std::invalid_argument("vocabulary node 0 must be the root");
  if (n >= kNoParent) throw std::invalid_argument("vocabulary has too many nodes");
  Vocabulary vocabulary;
  vocabulary.branching_ = branching;
  vocabulary.depth_ = depth;
  vocabulary.parents_ = parents;
  vocabulary.descriptors_ = descriptors;
  vocabulary.weights_ = weights;
  vocabulary.word_of_node_.assign(n, kNoWord);
  for (std::size_t i = 1; i < n; ++i) {
    if (parents[i] >= i) {
      throw std::invalid_argument("vocabulary node " + std::to_string(i) + " names parent " +
                                  std::to_string(parents[i]) + ", which does not come before it");
    }
    if (is_leaf[parents[i]]) {
      throw std::invalid_argument("vocabulary node " + std::to_string(i) + " has a leaf (" +
                                  std::to_string(parents[i]) + ") as parent");
    }
  }
  WordId next_word = 0;
  for (std::size_t i = 1; i < n; ++i) {
    if (is_leaf[i]) vocabulary.word_of_node_[i] = next_word++;
  }
  vocabulary.BuildIndex();
  for (std::size_t i = 0; i < n; ++i) {
    if (!is_leaf[i] && vocabulary.child_count_[i] == 0 && n > 1) {
      throw std::invalid_argument("vocabulary node " + std::to_string(i) +
                                  " is neither a leaf nor has children");
    }
  }
  return vocabulary;
}

void Vocabulary::BuildIndex() {
  const std::size_t n = parents_.size();
  child_count_.assign(n, 0);
  for (std::size_t i = 1; i < n; ++i) ++child_count_[parents_[i]];
  first_child_.assign(n, 0);
  std::uint32_t offset = 0;
  for (std::size_t i = 0; i < n; ++i) {
    first_child_[i] = offset;
    offset += child_count_[i];
  }
  child_list_.assign(offset, 0);
  std::vector<std::uint32_t> filled(n, 0);
  node_depth_.assign(n, 0);
  word_nodes_.clear();
  for (std::size_t i = 1; i < n; ++i) {
    const NodeId parent = parents_[i];
    child_list_[first_child_[parent] + filled[parent]++] = static_cast<NodeId>(i);
    node_depth_[i] = static_cast<std::uint8_t>(node_depth_[parent] + 1);
    if (word_of_node_[i] != kNoWord) word_nodes_.push_back(static_cast<NodeId>(i));
  }
}

WordId Vocabulary::Quantize(const Descriptor& descriptor, int feature_depth,
                            NodeId* node_at_depth) const {
  NodeId node = kRoot;
  NodeId at_depth = kRoot;
  while (word_of_node_[node] == kNoWord) {
    const std::uint32_t first = first_child_[node];
    const std::uint32_t count = child_count_[node];
    if (count == 0) return kNoWord;  // an empty vocabulary's root
    NodeId best = child_list_[first];
    int best_distance = HammingDistance(descriptor, descriptors_[best]);
    for (std::uint32_t c = 1; c < count; ++c) {
      const NodeId child = child_list_[first + c];
      const int distance = HammingDistance(descriptor, descriptors_[child]);
      if (distance < best_distance) {
        best_distance = distance;
        best = child;
      }
    }
    node = best;
    if (node_depth_[node] <= feature_depth) at_depth = node;
  }
  if (node_at_depth != nullptr) *node_at_depth = at_depth;
  return word_of_node_[node];
}

void Vocabulary::Transform(const std::vector<Descriptor>& descriptors, BowVector* bow,
                           FeatureVector* features, int feature_depth) const {
  bow->entries.clear();
  if (features != nullptr) features->clear();
  std::vector<std::pair<WordId, double>> raw;
  raw.reserve(descriptors.size());
  for (std::size_t i = 0; i < descriptors.size(); ++i) {
    NodeId node = kRoot;
    const WordId word = Quantize(descriptors[i], feature_depth, &node);
    if (word == kNoWord) continue;
    const double weight = WordWeight(word);
    // A word every training image had says nothing about the place.
    if (weight <= 0.0) continue;
    raw.emplace_back(word, weight);
    if (features != nullptr) (*features)[node].push_back(static_cast<int>(i));
  }
  std::sort(raw.begin(), raw.end());
  double total = 0.0;
  for (const auto& [word, weight] : raw) {
    if (!bow->entries.empty() && bow->entries.back().first == word) {
      bow->entries.back().second += weight;
    } else {
      bow->entries.emplace_back(word, weight);
    }
    total += weight;
  }
  if (total > 0.0) {
    for (auto& entry : bow->entries) entry.second /= total;
  }
}

bool Vocabulary::operator==(const Vocabulary& other) const {
  return branching_ == other.branching_ && depth_ == other.depth_ && parents_ == other.parents_ &&
         descriptors_ == other.descriptors_ && weights_ == other.weights_ &&
         word_of_node_ == other.word_of_node_;
}

void Vocabulary::SaveBinary(const std::string& path) const {
  const std::uint64_t n = parents_.size();
  std::string bytes(BinarySize(n), '\0');
  BinaryHeader header{};
  std::memcpy(header.magic, kBinaryMagic, sizeof(kBinaryMagic));
  header.branching = static_cast<std::uint32_t>(branching_);
  header.depth = static_cast<std::uint32_t>(depth_);
  header.scoring = kScoringL1;
  header.weighting = kWeightingTfIdf;
  header.node_count = n;
  char* out = bytes.data();
  std::memcpy(out, &header, sizeof(header));
  out += sizeof(header);
  std::memcpy(out, parents_.data(), n * sizeof(NodeId));
  out += n * sizeof(NodeId);
  for (std::size_t i = 0; i < n; ++i) *out++ = word_of_node_[i] == kNoWord ? 0 : 1;
  for (std::size_t i = 0; i < n; ++i) {
    DescriptorToBytes(descriptors_[i], reinterpret_cast<std::uint8_t*>(out));
    out += kDescriptorBytes;
  }
  std::memcpy(out, weights_.data(), n * sizeof(double));
  out += n * sizeof(double);
  std::memcpy(out, kBinaryEnd, sizeof(kBinaryEnd));
  WriteFileAtomically(path, bytes);
}

Vocabulary Vocabulary::LoadBinary(const std::string& path) {
  const std::string bytes = ReadWholeFile(path);
  BinaryHeader header{};
  if (bytes.size() < sizeof(header) ||
      std::memcmp(bytes.data(), kBinaryMagic, sizeof(kBinaryMagic)) != 0) {
    throw FileError("'" + path + "' is not an OCG-SLAM binary vocabulary");
  }
  std::memcpy(&header, bytes.data(), sizeof(header));
  const std::uint64_t n = header.node_count;
  if (n == 0 || n >= kNoParent || bytes.size() != BinarySize(n) ||
      std::memcmp(bytes.data() + bytes.size() - sizeof(kBinaryEnd), kBinaryEnd,
                  sizeof(kBinaryEnd)) != 0) {
    throw FileError("vocabulary '" + path + "' is truncated or corrupt (" +
                    std::to_string(bytes.size()) + " bytes for " + std::to_string(n) + " nodes)");
  }
  if (header.scoring != kScoringL1 || header.weighting != kWeightingTfIdf) {
    throw FileError("vocabulary '" + path + "' uses a scoring or weighting other than L1 / TF-IDF");
  }
  const char* in = bytes.data() + sizeof(header);
  std::vector<NodeId> parents(n);
  std::memcpy(parents.data(), in, n * sizeof(NodeId));
  in += n * sizeof(NodeId);
  std::vector<bool> is_leaf(n);
  for (std::size_t i = 0; i < n; ++i) is_leaf[i] = *in++ != 0;
  std::vector<Descriptor> descriptors(n);
  for (std::size_t i = 0; i < n; ++i) {
    descriptors[i] = DescriptorFromBytes(reinterpret_cast<const std::uint8_t*>(in));
    in += kDescriptorBytes;
  }
  std::vector<double> weights(n);
  std::memcpy(weights.data(), in, n * sizeof(double));
  try {
    return FromNodes(static_cast<int>(header.branching), static_cast<int>(header.depth), parents,
                     descriptors, weights, is_leaf);
  } catch (const std::invalid_argument& error) {
    throw FileError("vocabulary '" + path + "': " + error.what());
  }
}

Vocabulary Vocabulary::LoadOrbSlamText(const std::string& path) {
  const std::string text = ReadWholeFile(path);
  const char* cursor = text.data();
  const char* const end = text.data() + text.size();
  int line_number = 0;
  auto fail = [&](const std::string& what) {
    throw FileError(path + ":" + std::to_string(line_number) + ": " + what);
  };
  // Reads the fields of one line into numbers; the last one (weight) may be a double.
  std::vector<NodeId> parents = {kNoParent};
  std::vector<Descriptor> descriptors = {Descriptor{}};
  std::vector<double> weights = {0.0};
  std::vector<bool> is_leaf = {false};
  int header[4] = {0, 0, 0, 0};
  bool header_read = false;
  while (cursor < end) {
    const char* line_end = static_cast<const char*>(std::memchr(cursor, '\n', end - cursor));
    if (line_end == nullptr) line_end = end;
    ++line_number;
    const char* field = cursor;
    cursor = line_end + 1;
    const char* field_end = nullptr;
    if (!NextField(field, line_end, &field_end)) continue;  // blank line
    auto read_int = [&](long long low, long long high, const char* name) {
      long long value = 0;
      if (!NextField(field, line_end, &field_end)) fail(std::string("missing ") + name);
      const auto result = std::from_chars(field, field_end, value);
      if (result.ec != std::errc() || result.ptr != field_end || value < low || value > high) {
        fail(std::string("bad ") + name + " '" + std::string(field, field_end) + "'");
      }
      field = field_end;
      return value;
    };
    if (!header_read) {
      header[0] = static_cast<int>(read_int(2, 64, "branching factor k"));
      header[1] = static_cast<int>(read_int(1, 12, "depth L"));
      header[2] = static_cast<int>(read_int(0, 10, "scoring type"));
      header[3] = static_cast<int>(read_int(0, 10, "weighting type"));
      if (header[2] != static_cast<int>(kScoringL1) ||
          header[3] != static_cast<int>(kWeightingTfIdf)) {
        fail("only L1 scoring (0) with TF-IDF weighting (0) is supported, as in ORBvoc.txt");
      }
      header_read = true;
      continue;
    }
    const NodeId node = static_cast<NodeId>(parents.size());
    parents.push_back(static_cast<NodeId>(read_int(0, node - 1, "parent id")));
    is_leaf.push_back(read_int(0, 1, "leaf flag") == 1);
    std::uint8_t bytes[kDescriptorBytes];
    for (int b = 0; b < kDescriptorBytes; ++b) {
      bytes[b] = static_cast<std::uint8_t>(read_int(0, 255, "descriptor byte"));
    }
    descriptors.push_back(DescriptorFromBytes(bytes));
    if (!NextField(field, line_end, &field_end)) fail("missing weight");
    const std::string weight_text(field, field_end);
    char* parsed_end = nullptr;
    const double weight = std::strtod(weight_text.c_str(), &parsed_end);
    if (parsed_end != weight_text.c_str() + weight_text.size() || !std::isfinite(weight)) {
      fail("bad weight '" + weight_text + "'");
    }
    weights.push_back(weight);
    field = field_end;
    if (NextField(field, line_end, &field_end)) fail("unexpected text after the weight");
  }
  if (!header_read) throw FileError("vocabulary '" + path + "' is empty");
  try {
    return FromNodes(header[0], header[1], parents, descriptors, weights, is_leaf);
  } catch (const std::invalid_argument& error) {
    throw FileError("vocabulary '" + path + "': " + error.what());
  }
}

void Vocabulary::SaveOrbSlamText(const std::string& path) const {
  std::string text = std::to_string(branching_) + " " + std::to_string(depth_) + " " +
                     std::to_string(kScoringL1) + " " + std::to_string(kWeightingTfIdf) + "\n";
  char number[40];
  std::uint8_t bytes[kDescriptorBytes];
  for (std::size_t i = 1; i < parents_.size(); ++i) {
    text += std::to_string(parents_[i]);
    text += word_of_node_[i] == kNoWord ? " 0" : " 1";
    DescriptorToBytes(descriptors_[i], bytes);
    for (const std::uint8_t b : bytes) {
      text += ' ';
      text += std::to_string(b);
    }
    std::snprintf(number, sizeof(number), " %.17g\n", weights_[i]);
    text += number;
  }
  WriteFileAtomically(path, text);
}

Vocabulary Vocabulary::Load(const std::string& path) {
  RequireVocabularyFile(path);
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) {
    throw FileError("cannot open vocabulary '" + path + "': " + std::strerror(errno));
  }
  char magic[sizeof(kBinaryMagic)] = {};
  const std::size_t read = std::fread(magic, 1, sizeof(magic), file);
  std::fclose(file);
  if (read == sizeof(magic) && std::memcmp(magic, kBinaryMagic, sizeof(magic)) == 0) {
    return LoadBinary(path);
  }
  return LoadOrbSlamText(path);
}

std::vector<std::string> VocabularySearchPaths() {
  std::vector<std::string> paths;
  if (const char* variable = std::getenv("OCG_VOCABULARY"); variable != nullptr && *variable) {
    paths.emplace_back(variable);
  }
  paths.emplace_back(OCG_VOCABULARY_INSTALL_PATH);
  paths.emplace_back(OCG_VOCABULARY_SOURCE_PATH);
  return paths;
}

std::string DefaultVocabularyPath() {
  for (const std::string& path : VocabularySearchPaths()) {
    std::error_code error;
    if (std::filesystem::is_regular_file(path, error)) return path;
  }
  return {};
}

void ReadSettings(const SettingsFile& file, VocabularyOptions* options) {
  ReadOptionFields(file, options);
}

std::string VocabularyOptions::Resolve() const {
  if (!path.empty()) return path;
  const std::string found = DefaultVocabularyPath();
  if (!found.empty()) return found;
  std::string looked;
  for (const std::string& place : VocabularySearchPaths()) looked += "\n  " + place;
  throw FileError(
      "no vocabulary: Vocabulary.path is not set and the default is in none of:" + looked +
      "\n(set OCG_VOCABULARY or Vocabulary.path, or see thirdparty/README.md)");
}

}  // namespace ocg
