/// Sparse linear solves for the runner: UMFPACK (SuiteSparse) LU with an iterative fallback
/// (BiCGSTAB with incomplete LUT), reporting fill, reciprocal condition estimate and residual.
#pragma once
#include <string>

#include <Eigen/Sparse>

#include "analyses/case.hpp"

namespace mfv {

/// "auto": UMFPACK, falling back to BiCGSTAB+ILUT if the factorization runs out of memory or
/// fails for a reason other than singularity; "direct": UMFPACK only; "iterative": BiCGSTAB.
inline const char* const kSolverChoices[] = {"auto", "direct", "iterative"};

/// Solves A x = b. Fills info.solver, unknowns, nonzeros, fill, rcond, iterations, residual.
/// Throws SingularError with the cause (and what to change) for a singular or numerically
/// singular matrix, or when the result is not finite; InputError for an unknown `kind`.
Eigen::VectorXd solve_sparse(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& b,
                             const std::string& kind, SolveInfo& info);

}  // namespace mfv
