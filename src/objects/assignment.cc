#include "ocg/objects/assignment.h"

#include <algorithm>

namespace ocg {
namespace {

// Shortest augmenting paths with row and column potentials; needs rows <= cols.
// Returns the column of every row.
std::vector<int> AssignRowsToColumns(const Eigen::MatrixXd& cost) {
  const int rows = static_cast<int>(cost.rows());
  const int cols = static_cast<int>(cost.cols());
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  // 1-based arrays; column 0 is the virtual start of each augmenting path.
  std::vector<double> row_potential(static_cast<std::size_t>(rows) + 1, 0.0);
  std::vector<double> col_potential(static_cast<std::size_t>(cols) + 1, 0.0);
  std::vector<int> row_of_col(static_cast<std::size_t>(cols) + 1, 0);
  std::vector<int> previous_col(static_cast<std::size_t>(cols) + 1, 0);
  for (int row = 1; row <= rows; ++row) {
    row_of_col[0] = row;
    int col = 0;
    std::vector<double> slack(static_cast<std::size_t>(cols) + 1, kInfinity);
    std::vector<bool> used(static_cast<std::size_t>(cols) + 1, false);
    do {
      used[static_cast<std::size_t>(col)] = true;
      const int current_row = row_of_col[static_cast<std::size_t>(col)];
      double delta = kInfinity;
      int next_col = 0;
      for (int j = 1; j <= cols; ++j) {
        const auto uj = static_cast<std::size_t>(j);
        if (used[uj]) continue;
        const double reduced = cost(current_row - 1, j - 1) -
                               row_potential[static_cast<std::size_t>(current_row)] -
                               col_potential[uj];
        if (reduced < slack[uj]) {
          slack[uj] = reduced;
          previous_col[uj] = col;
        }
        if (slack[uj] < delta) {
          delta = slack[uj];
          next_col = j;
        }
      }
      for (int j = 0; j <= cols; ++j) {
        const auto uj = static_cast<std::size_t>(j);
        if (used[uj]) {
          row_potential[static_cast<std::size_t>(row_of_col[uj])] += delta;
          col_potential[uj] -= delta;
        } else {
          slack[uj] -= delta;
        }
      }
      col = next_col;
    } while (row_of_col[static_cast<std::size_t>(col)] != 0);
    do {  // flip the augmenting path
      const int previous = previous_col[static_cast<std::size_t>(col)];
      row_of_col[static_cast<std::size_t>(col)] = row_of_col[static_cast<std::size_t>(previous)];
      col = previous;
    } while (col != 0);
  }
  std::vector<int> col_of_row(static_cast<std::size_t>(rows), -1);
  for (int j = 1; j <= cols; ++j) {
    const int row = row_of_col[static_cast<std::size_t>(j)];
    if (row > 0) col_of_row[static_cast<std::size_t>(row - 1)] = j - 1;
  }
  return col_of_row;
}

}  // namespace

std::vector<int> SolveAssignment(const Eigen::MatrixXd& cost) {
  const auto rows = static_cast<std::size_t>(cost.rows());
  std::vector<int> assignment(rows, -1);
  if (cost.rows() == 0 || cost.cols() == 0) return assignment;
  // Forbidden pairs cost the same huge amount, so they are only taken when nothing else
  // completes the assignment, and are dropped afterwards.
  const Eigen::MatrixXd clamped = cost.cwiseMin(kForbiddenCost);
  if (cost.rows() <= cost.cols()) {
    assignment = AssignRowsToColumns(clamped);
  } else {
    const std::vector<int> row_of_col = AssignRowsToColumns(clamped.transpose());
    for (std::size_t col = 0; col < row_of_col.size(); ++col) {
      if (row_of_col[col] >= 0)
        assignment[static_cast<std::size_t>(row_of_col[col])] = static_cast<int>(col);
    }
  }
  for (std::size_t row = 0; row < rows; ++row) {
    const int col = assignment[row];
    if (col >= 0 && cost(static_cast<Eigen::Index>(row), col) >= kForbiddenCost)
      assignment[row] = -1;
  }
  return assignment;
}

}  // namespace ocg
