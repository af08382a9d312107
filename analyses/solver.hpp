/// Sparse linear solves for the runner: UMFPACK (SuiteSparse) LU with an iterative fallback
/// (BiCGSTAB with incomplete LUT), reporting fill, reciprocal condition estimate and residual.
#pragma once
#include <string>

#include <Eigen/Sparse>

#include "analyses/case.hpp"

namespace mfv {

/// "auto": UMFPACK, falling back to BiCGSTAB+ILUT if the factorization runs out of memory or
/// fails for a reason other than singularity; "direct": UMFPACK only; "iterative": BiCGSTAB;
/// "petsc": PETSc's CG or GMRES with algebraic multigrid (analyses/petsc_solver.hpp), the
/// essential conditions by penalty or elimination (solve_constrained).
inline const char* const kSolverChoices[] = {"auto", "direct", "iterative", "petsc"};

/// The linear solver of a static solve: the static-solve analysis's parameters `solver`,
/// `ksp_rtol` and `petsc_options`.
struct SolverChoice {
  std::string kind = "auto";  ///< one of kSolverChoices
  /// solver=petsc: relative tolerance of the Krylov solve on the true residual ‖b − A x‖/‖b‖.
  double ksp_rtol = 1e-10;
  /// solver=petsc: PETSc options ("-ksp_type gmres -pc_type hypre"), read after the defaults
  /// and after the PETSC_OPTIONS environment variable, so they override both.
  std::string petsc_options;
};

/// Throws InputError naming the parameter and what is valid: an unknown kind, ksp_rtol
/// outside (0, 1) or NaN, petsc_options with a solver other than petsc.
void check_solver_choice(const SolverChoice& choice);

/// Why a PETSc options text would read or write a file or start a program, or "" if it does
/// not: options that do so by name (-options_file, -log_view, -info, -history, the debugger
/// and display options, also behind a prefix), and viewer values that name a file
/// ("ascii:out.txt") or open a file, window or socket (binary, hdf5, vtk, draw, socket, …).
/// check_solver_choice refuses them (issue 26): a manifest must not touch the user's files.
std::string petsc_option_touching_files(const std::string& text);

/// Solves A x = b. Fills info.solver, unknowns, nonzeros, fill, rcond, iterations, residual.
/// Throws SingularError with the cause (and what to change) for a singular or numerically
/// singular matrix, or when the result is not finite; InputError for an unknown `kind`.
Eigen::VectorXd solve_sparse(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& b,
                             const std::string& kind, SolveInfo& info);

}  // namespace mfv
