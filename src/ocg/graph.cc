#include "ocg/ocg/graph.h"

#include <algorithm>
#include <cassert>
#include <stdexcept>
#include <string>

namespace ocg {
namespace {

template <typename Edges>
auto FindEdge(Edges& edges, ObjectId neighbour) {
  return std::lower_bound(
      edges.begin(), edges.end(), neighbour,
      [](const CovisibilityEdge& edge, ObjectId id) { return edge.neighbour < id; });
}

}  // namespace

bool ObjectCovisibilityGraph::AddNode(ObjectId id) { return nodes_.try_emplace(id).second; }

bool ObjectCovisibilityGraph::RemoveNode(ObjectId id) {
  const auto it = nodes_.find(id);
  if (it == nodes_.end()) return false;
  for (const CovisibilityEdge& edge : it->second.edges) {
    Node& neighbour = nodes_.at(edge.neighbour);
    AddToEdgeList(neighbour, id, -static_cast<std::int64_t>(edge.weight));
    --edge_count_;
  }
  nodes_.erase(it);
  return true;
}

std::uint32_t ObjectCovisibilityGraph::AddToEdgeList(Node& node, ObjectId neighbour,
                                                     std::int64_t delta) {
  auto edge = FindEdge(node.edges, neighbour);
  if (edge == node.edges.end() || edge->neighbour != neighbour) {
    assert(delta > 0);
    edge = node.edges.insert(edge, CovisibilityEdge{neighbour, 0});
  }
  assert(static_cast<std::int64_t>(edge->weight) + delta >= 0);
  edge->weight = static_cast<std::uint32_t>(static_cast<std::int64_t>(edge->weight) + delta);
  node.weight_sum = static_cast<std::uint64_t>(static_cast<std::int64_t>(node.weight_sum) + delta);
  const std::uint32_t weight = edge->weight;
  if (weight == 0) node.edges.erase(edge);
  return weight;
}

void ObjectCovisibilityGraph::AddCovisibility(const std::vector<ObjectId>& ids) {
  std::vector<ObjectId> unique = ids;
  std::sort(unique.begin(), unique.end());
  unique.erase(std::unique(unique.begin(), unique.end()), unique.end());
  std::vector<Node*> members;
  members.reserve(unique.size());
  for (ObjectId id : unique) members.push_back(&nodes_[id]);  // references stay valid below
  for (size_t a = 0; a < unique.size(); ++a) {
    for (size_t b = a + 1; b < unique.size(); ++b) {
      if (AddToEdgeList(*members[a], unique[b], 1) == 1) ++edge_count_;
      AddToEdgeList(*members[b], unique[a], 1);
    }
  }
}

void ObjectCovisibilityGraph::SetEdge(ObjectId a, ObjectId b, std::uint32_t weight) {
  if (a == b)
    throw std::invalid_argument("OCG edge from object " + std::to_string(a) + " to itself");
  Node& node_a = nodes_[a];
  Node& node_b = nodes_[b];
  const std::int64_t delta = static_cast<std::int64_t>(weight) - EdgeWeight(a, b);
  if (delta == 0) return;
  const bool existed = EdgeWeight(a, b) > 0;
  AddToEdgeList(node_a, b, delta);
  AddToEdgeList(node_b, a, delta);
  if (!existed) ++edge_count_;
  if (weight == 0) --edge_count_;
}

std::uint32_t ObjectCovisibilityGraph::EdgeWeight(ObjectId a, ObjectId b) const {
  const auto it = nodes_.find(a);
  if (it == nodes_.end()) return 0;
  const auto& edges = it->second.edges;
  const auto edge = FindEdge(edges, b);
  return edge != edges.end() && edge->neighbour == b ? edge->weight : 0;
}

std::uint64_t ObjectCovisibilityGraph::WeightSum(ObjectId id) const {
  const auto it = nodes_.find(id);
  return it == nodes_.end() ? 0 : it->second.weight_sum;
}

const std::vector<CovisibilityEdge>& ObjectCovisibilityGraph::Neighbours(ObjectId id) const {
  return nodes_.at(id).edges;
}

std::size_t ObjectCovisibilityGraph::Degree(ObjectId id) const {
  const auto it = nodes_.find(id);
  return it == nodes_.end() ? 0 : it->second.edges.size();
}

std::vector<ObjectId> ObjectCovisibilityGraph::NodeIds() const {
  std::vector<ObjectId> ids;
  ids.reserve(nodes_.size());
  for (const auto& entry : nodes_) ids.push_back(entry.first);
  std::sort(ids.begin(), ids.end());
  return ids;
}

}  // namespace ocg
