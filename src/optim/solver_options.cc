#include "solver_options.h"

#include "ocg/optim/solver_logging.h"

namespace ocg {

ceres::Solver::Options SolverOptions(int iterations, LinearSolver solver) {
  RouteSolverLogging();  // whatever Ceres still says goes through our logger
  ceres::Solver::Options options;
  options.max_num_iterations = iterations;
  options.num_threads = 1;  // reproducible sums
  const bool sparse = ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE);
  switch (solver) {
    case LinearSolver::kDenseSchur:
      options.linear_solver_type = ceres::DENSE_SCHUR;
      break;
    case LinearSolver::kSparseSchur:
      options.linear_solver_type = sparse ? ceres::SPARSE_SCHUR : ceres::DENSE_SCHUR;
      break;
    case LinearSolver::kSparse:
      options.linear_solver_type = sparse ? ceres::SPARSE_NORMAL_CHOLESKY : ceres::DENSE_QR;
      break;
    case LinearSolver::kDense:
      options.linear_solver_type = ceres::DENSE_QR;
      break;
  }
  options.logging_type = ceres::SILENT;
  options.minimizer_progress_to_stdout = false;
  return options;
}

}  // namespace ocg
