#include <gtest/gtest.h>

#include "ocg/ocg/graph.h"

namespace ocg {
namespace {

TEST(Graph, CovisibilityIncrementsEveryPairOnce) {
  ObjectCovisibilityGraph graph;
  graph.AddCovisibility({3, 1, 2});
  graph.AddCovisibility({1, 2, 2});  // duplicate id counts once
  EXPECT_EQ(graph.NodeCount(), 3u);
  EXPECT_EQ(graph.EdgeCount(), 3u);
  EXPECT_EQ(graph.EdgeWeight(1, 2), 2u);
  EXPECT_EQ(graph.EdgeWeight(2, 1), 2u);
  EXPECT_EQ(graph.EdgeWeight(1, 3), 1u);
  EXPECT_EQ(graph.EdgeWeight(1, 1), 0u);
  EXPECT_EQ(graph.WeightSum(1), 3u);
  EXPECT_EQ(graph.WeightSum(3), 2u);
  ASSERT_EQ(graph.Neighbours(1).size(), 2u);
  EXPECT_EQ(graph.Neighbours(1)[0].neighbour, 2);  // sorted
  EXPECT_EQ(graph.NodeIds(), (std::vector<ObjectId>{1, 2, 3}));
}

TEST(Graph, SingleObservationAddsAnIsolatedNode) {
  ObjectCovisibilityGraph graph;
  graph.AddCovisibility({9});
  EXPECT_TRUE(graph.Contains(9));
  EXPECT_EQ(graph.Degree(9), 0u);
  EXPECT_EQ(graph.EdgeCount(), 0u);
}

TEST(Graph, RemoveNodeDeletesItsEdgesAndUpdatesNeighbourSums) {
  ObjectCovisibilityGraph graph;
  graph.AddCovisibility({1, 2, 3});
  graph.AddCovisibility({1, 2});
  EXPECT_TRUE(graph.RemoveNode(1));
  EXPECT_FALSE(graph.Contains(1));
  EXPECT_FALSE(graph.RemoveNode(1));
  EXPECT_EQ(graph.EdgeWeight(2, 1), 0u);
  EXPECT_EQ(graph.WeightSum(2), 1u);  // only 2-3 left
  EXPECT_EQ(graph.WeightSum(3), 1u);
  EXPECT_EQ(graph.EdgeCount(), 1u);
  EXPECT_EQ(graph.Degree(2), 1u);
}

TEST(Graph, SetEdgeCreatesChangesAndDeletes) {
  ObjectCovisibilityGraph graph;
  graph.SetEdge(1, 2, 5);
  EXPECT_EQ(graph.EdgeWeight(2, 1), 5u);
  EXPECT_EQ(graph.WeightSum(1), 5u);
  graph.SetEdge(1, 2, 2);
  EXPECT_EQ(graph.WeightSum(2), 2u);
  EXPECT_EQ(graph.EdgeCount(), 1u);
  graph.SetEdge(2, 1, 0);
  EXPECT_EQ(graph.EdgeCount(), 0u);
  EXPECT_EQ(graph.Degree(1), 0u);
  EXPECT_THROW(graph.SetEdge(4, 4, 1), std::invalid_argument);
}

}  // namespace
}  // namespace ocg
