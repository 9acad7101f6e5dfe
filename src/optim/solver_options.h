#pragma once
// Ceres solver settings shared by the project's problems (internal to optim).

#include <ceres/ceres.h>

namespace ocg {

// Single-threaded (sums in a fixed order, so runs repeat exactly), silent; the Schur
// complement for bundle adjustment (dense or sparse, see SchurComplement in
// bundle_adjustment.h), sparse Cholesky for graphs, dense QR otherwise.
enum class LinearSolver { kDenseSchur, kSparseSchur, kSparse, kDense };
ceres::Solver::Options SolverOptions(int iterations, LinearSolver solver);

}  // namespace ocg
