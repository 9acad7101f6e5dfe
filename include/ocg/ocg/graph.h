#pragma once
// The Object Covisibility Graph (SPEC 3.1): one node per map object, an undirected edge
// weighted by the number of keyframes in which both objects were observed.
//
// Adjacency lists are kept sorted by neighbour id (deterministic iteration, compact
// memory at a million nodes) and every node keeps the sum of its edge weights, so
// Eq. (1)'s denominator costs nothing. Not thread-safe: the owner serialises access.

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "ocg/ocg/observation.h"

namespace ocg {

struct CovisibilityEdge {
  ObjectId neighbour = 0;
  std::uint32_t weight = 0;
};

class ObjectCovisibilityGraph {
 public:
  bool Contains(ObjectId id) const { return nodes_.count(id) > 0; }
  // Adds an isolated node; returns false when it was already there.
  bool AddNode(ObjectId id);
  // Deletes the node and its edges, updating the neighbours' weight sums. O(degree * log).
  // Returns false when the node was absent.
  bool RemoveNode(ObjectId id);
  // SPEC 3.1: adds missing nodes, then E(i, j) += 1 for every unordered pair of distinct
  // ids. Duplicate ids count once. O(|ids|^2 * degree) worst case.
  void AddCovisibility(const std::vector<ObjectId>& ids);
  // Direct edge edit (import, tests): sets E(a, b) = weight, removing it at 0.
  void SetEdge(ObjectId a, ObjectId b, std::uint32_t weight);

  std::uint32_t EdgeWeight(ObjectId a, ObjectId b) const;
  // Sum of the node's edge weights; 0 for an absent node.
  std::uint64_t WeightSum(ObjectId id) const;
  // Sorted by neighbour id. The node must exist.
  const std::vector<CovisibilityEdge>& Neighbours(ObjectId id) const;
  std::size_t Degree(ObjectId id) const;

  std::size_t NodeCount() const { return nodes_.size(); }
  std::size_t EdgeCount() const { return edge_count_; }
  // All node ids, ascending.
  std::vector<ObjectId> NodeIds() const;
  void Reserve(std::size_t nodes) { nodes_.reserve(nodes); }

 private:
  struct Node {
    std::vector<CovisibilityEdge> edges;  // sorted by neighbour
    std::uint64_t weight_sum = 0;
  };
  // Adds delta to E(a, b) in a's list only; returns the new weight.
  static std::uint32_t AddToEdgeList(Node& node, ObjectId neighbour, std::int64_t delta);

  std::unordered_map<ObjectId, Node> nodes_;
  std::size_t edge_count_ = 0;
};

}  // namespace ocg
