// SPDX-License-Identifier: GPL-3.0-or-later
// Sparse symmetric positive definite solves of the fluid solver (pressure correction, implicit
// momentum predictor): Eigen's sparse LDL^T or preconditioned conjugate gradients.
#pragma once

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

namespace gf::fluid {

/// How a sparse SPD system is solved (docs/models/fluid_fv.md has the measurements).
enum class LinearSolver {
  Auto,                  ///< pressure: Direct in 2D and on thin 3D grids, else JacobiCG (rule:
                         ///< VolumeAveragedNS); momentum: JacobiCG
  Direct,                ///< Eigen::SimplicialLDLT, numeric factorisation only when A changed
  IncompleteCholeskyCG,  ///< CG preconditioned by Eigen::IncompleteCholesky (natural order)
  JacobiCG,              ///< CG preconditioned by the diagonal
};

/// What one solve did.
struct SolveStats {
  int iterations = 0;       ///< CG iterations (0 for Direct)
  double residual = 0.0;    ///< ||b - A x||_2 at return
  bool factorized = false;  ///< the factorisation / preconditioner was recomputed
};

/// Solver of A x = b for a fixed sparsity pattern and changing values. The work vectors are
/// sized once in setup(), so solve() allocates nothing of its own; Eigen's numeric
/// factorisations (Direct, IncompleteCholeskyCG) allocate their work arrays when A changed.
class SpdSolver {
 public:
  using Matrix = Eigen::SparseMatrix<double>;  ///< column-major, both triangles stored

  /// Chooses the method (Auto must be resolved by the caller) and analyses the pattern of A.
  void setup(LinearSolver method, const Matrix& a);
  /// The values of A changed: the next solve refreshes the factorisation or preconditioner.
  void matrix_changed() { changed_ = true; }
  /// Solves A x = b; on entry x is the initial guess of the CG methods. CG stops when
  /// ||b - A x||_2 <= max(rtol ||b||_2, atol); throws gf::Error after max_iterations.
  SolveStats solve(const Matrix& a, const Eigen::VectorXd& b, Eigen::VectorXd& x, double rtol,
                   double atol, int max_iterations);

  [[nodiscard]] LinearSolver method() const { return method_; }
  [[nodiscard]] int n_factorizations() const { return n_factorizations_; }

 private:
  void refresh(const Matrix& a);
  void precondition(const Eigen::VectorXd& r, Eigen::VectorXd& z);
  void direct_solve(const Eigen::VectorXd& b, Eigen::VectorXd& x);

  LinearSolver method_ = LinearSolver::Direct;
  bool changed_ = true;
  int n_factorizations_ = 0;
  Eigen::SimplicialLDLT<Matrix> ldlt_;
  Eigen::VectorXd inv_d_;  // 1 / D of the LDL^T factors
  Eigen::IncompleteCholesky<double, Eigen::Lower, Eigen::NaturalOrdering<int>> ic_;
  Eigen::VectorXd inv_diag_;  // Jacobi
  Eigen::VectorXd r_, z_, p_, q_, tmp_;
};

/// Position of entry (row, col) in the values of a compressed column-major matrix whose pattern
/// has it (found once, so that re-assembly writes the values directly).
int entry_position(const SpdSolver::Matrix& m, int row, int col);
/// Zeroes column `col` of a compressed column-major matrix (its entries are then accumulated: on
/// a periodic axis of two cells both neighbours are the same unknown, one entry).
void zero_column(SpdSolver::Matrix& m, int col);

}  // namespace gf::fluid
