#pragma once
// One-to-one assignment at least total cost (Hungarian / Kuhn-Munkres, O(n^3)).

#include <limits>
#include <vector>

#include <Eigen/Core>

namespace ocg {

// Costs at or above this are forbidden pairs.
constexpr double kForbiddenCost = 1e9;

// cost: rows x cols, any shape. Returns for every row the assigned column or -1 (more
// rows than columns, or only forbidden pairs left). Ties are broken by index, so the
// result is deterministic.
std::vector<int> SolveAssignment(const Eigen::MatrixXd& cost);

}  // namespace ocg
