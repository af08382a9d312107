/// The `static-solve` analysis: a BoundaryValueProblem's weak form assembled on the
/// method's tables, its essential conditions imposed, the linear system solved, and the
/// errors on the common and the paper's rules, headline values and sampled fields.
#pragma once
#include <string>

#include <Eigen/Sparse>

#include "analyses/case.hpp"
#include "analyses/solver.hpp"
#include "problems/problem.hpp"

namespace mfv {

/// Solves K u = f with the essential conditions of `sys` imposed as the discretization says
/// (Lagrange multipliers or penalty; particle values directly for SPH/RLM), with
/// solve_sparse (UMFPACK, iterative fallback); fills `info` except `condition`. Throws
/// SingularError with the cause when the system cannot be factorized or the solution is not
/// finite. When `solved` is given it receives the factorized matrix (for condition_number).
///
/// solver.kind == "petsc" (petsc_solve): multipliers would make a saddle point, which CG and
/// AMG cannot take, so the conditions of MLS-type methods are imposed by penalty whatever
/// the method's `bc` (K + β G Gᵀ, β = penalty × the largest diagonal of K, as bc=penalty;
/// the solution differs from the multiplier one by O(1/β)), and the fixed particle values of
/// SPH/RLM are eliminated (MatZeroRowsColumns). The solver line says which.
Eigen::VectorXd solve_constrained(const AssembledSystem& sys, const Discretization& d,
                                  SolveInfo& info, Eigen::SparseMatrix<double>* solved = nullptr,
                                  const SolverChoice& solver = {});

/// 2-norm condition number by dense SVD for up to kMaxConditionSize rows; NaN above, inf
/// when the smallest singular value is zero.
double condition_number(const Eigen::SparseMatrix<double>& A);

}  // namespace mfv
