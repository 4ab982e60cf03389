// SPDX-License-Identifier: GPL-3.0-or-later
// Sparse SPD solves: LDL^T with reused factors, or preconditioned conjugate gradients.
#include "fluid/fv/spd_solver.hpp"

#include <cmath>

#include "core/error.hpp"

namespace gf::fluid {

int entry_position(const SpdSolver::Matrix& m, int row, int col) {
  const int* rows = m.innerIndexPtr();
  for (int k = m.outerIndexPtr()[col]; k < m.outerIndexPtr()[col + 1]; ++k)
    if (rows[k] == row) return k;
  ASSERT(false);
  return -1;
}

void zero_column(SpdSolver::Matrix& m, int col) {
  double* v = m.valuePtr();
  for (int k = m.outerIndexPtr()[col]; k < m.outerIndexPtr()[col + 1]; ++k) v[k] = 0.0;
}

void SpdSolver::setup(LinearSolver method, const Matrix& a) {
  REQUIRE(method != LinearSolver::Auto, "SpdSolver::setup needs a resolved method");
  method_ = method;
  const auto n = a.rows();
  r_.resize(n);
  z_.resize(n);
  p_.resize(n);
  q_.resize(n);
  tmp_.resize(n);
  // The symbolic analysis (ordering, elimination tree) depends on the pattern only.
  if (method_ == LinearSolver::Direct) ldlt_.analyzePattern(a);
  if (method_ == LinearSolver::IncompleteCholeskyCG) ic_.analyzePattern(a);
  if (method_ == LinearSolver::JacobiCG) inv_diag_.resize(n);
  changed_ = true;
}

void SpdSolver::refresh(const Matrix& a) {
  switch (method_) {
    case LinearSolver::Direct:
      ldlt_.factorize(a);
      REQUIRE(ldlt_.info() == Eigen::Success, "sparse LDL^T factorisation failed (matrix not SPD)");
      inv_d_ = ldlt_.vectorD().cwiseInverse();
      break;
    case LinearSolver::IncompleteCholeskyCG:
      ic_.factorize(a);
      REQUIRE(ic_.info() == Eigen::Success, "incomplete Cholesky factorisation failed");
      break;
    case LinearSolver::JacobiCG:
      inv_diag_ = a.diagonal().cwiseInverse();
      break;
    case LinearSolver::Auto:
      break;
  }
  ++n_factorizations_;
  changed_ = false;
}

// The steps of SimplicialLDLT::solve written out so that no temporary is allocated (Eigen's
// in-place permutation allocates a mask on every call): x = P^T L^-T D^-1 L^-1 P b.
void SpdSolver::direct_solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  tmp_ = ldlt_.permutationP() * b;
  ldlt_.matrixL().solveInPlace(tmp_);
  tmp_.array() *= inv_d_.array();
  ldlt_.matrixU().solveInPlace(tmp_);
  x = ldlt_.permutationPinv() * tmp_;
}

void SpdSolver::precondition(const Eigen::VectorXd& r, Eigen::VectorXd& z) {
  switch (method_) {
    case LinearSolver::Direct:
      direct_solve(r, z);
      break;
    case LinearSolver::IncompleteCholeskyCG:
      z = ic_.solve(r);
      break;
    case LinearSolver::JacobiCG:
    case LinearSolver::Auto:
      z = inv_diag_.cwiseProduct(r);
      break;
  }
}

SolveStats SpdSolver::solve(const Matrix& a, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                            double rtol, double atol, int max_iterations) {
  SolveStats s;
  if (changed_) {
    refresh(a);
    s.factorized = true;
  }
  if (method_ == LinearSolver::Direct) {
    direct_solve(b, x);
    r_ = b;
    r_.noalias() -= a * x;
    s.residual = r_.norm();
    return s;
  }
  // Preconditioned conjugate gradients (Hestenes & Stiefel 1952). This is the loop of Eigen's
  // internal::conjugate_gradient with the work vectors kept between calls (Eigen's allocates
  // four vectors per solve) and with an absolute floor on the residual, so that a right-hand
  // side that is already round-off (a converged steady state) stops at once.
  r_ = b;
  r_.noalias() -= a * x;
  const double tol = std::max(rtol * b.norm(), atol);
  double rnorm = r_.norm();
  if (rnorm <= tol) {
    s.residual = rnorm;
    return s;
  }
  precondition(r_, z_);
  p_ = z_;
  double rz = r_.dot(z_);
  for (int it = 1; it <= max_iterations; ++it) {
    q_.noalias() = a * p_;
    const double alpha = rz / p_.dot(q_);
    x += alpha * p_;
    r_ -= alpha * q_;
    rnorm = r_.norm();
    if (rnorm <= tol) {
      s.iterations = it;
      s.residual = rnorm;
      return s;
    }
    precondition(r_, z_);
    const double rz_new = r_.dot(z_);
    p_ = z_ + (rz_new / rz) * p_;
    rz = rz_new;
  }
  REQUIRE(false, "conjugate gradients did not converge in {} iterations (residual {:.3e} > {:.3e})",
          max_iterations, rnorm, tol);
  return s;
}

}  // namespace gf::fluid
