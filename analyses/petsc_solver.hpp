/// The PETSc backend of the static solves (solver=petsc): the assembled system as a PETSc
/// MPIAIJ matrix split among the ranks in whole particles, solved by a Krylov method with
/// algebraic multigrid, the solution gathered to every rank.
///
/// Algorithm: each rank holds the whole assembled system (set-up and assembly are replicated
/// today; only the solve is distributed) and inserts its own rows, converted from the
/// column-major matrix to CSR, into a matrix preallocated exactly from them
/// (MatMPIAIJSetPreallocationCSR). The rows are split in blocks of `components` unknowns, so a
/// particle's unknowns stay on one rank and the matrix carries the block size GAMG's
/// near-null space needs. Krylov method: CG for symmetric systems (Galerkin forms), GMRES with
/// right preconditioning for the others (Petrov–Galerkin, collocation), both stopping on the
/// unpreconditioned residual so that ksp_rtol bounds the true ‖b − A x‖/‖b‖; preconditioner:
/// smoothed-aggregation AMG (PCGAMG; Adams et al. 2004) with the rigid-body modes as the
/// near-null space for vector problems. PETSc's options (the PETSC_OPTIONS environment
/// variable, then SolverChoice::petsc_options) are read after these defaults and override
/// them (-ksp_type, -pc_type, -ksp_rtol, -ksp_monitor …).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include "analyses/case.hpp"

namespace mfv {

/// What the PETSc solve needs beyond the matrix and the right-hand side.
struct PetscSolveSetup {
  /// CG (the system is symmetric positive definite: a Galerkin form with symmetric
  /// conditions) or GMRES. Decided from the discretization's form, not by testing the matrix.
  bool symmetric = false;
  /// Unknowns per particle: the rows are split among ranks in blocks of this size.
  int components = 1;
  /// dim × particles positions: with components == dim > 1 the rigid-body modes built from
  /// them are GAMG's near-null space. Empty: GAMG's default (the constant).
  Eigen::MatrixXd coordinates;
  /// Unknowns eliminated: their rows and columns zeroed (MatZeroRowsColumns keeps the
  /// symmetry) with `fixed_diagonal` left on the diagonal. The caller moves their values to
  /// the right-hand side (eliminated_rhs).
  std::vector<int> fixed;
  double fixed_diagonal = 1.0;
  double rtol = 1e-10;
  std::string options;  ///< PETSc options text, after the PETSC_OPTIONS environment variable
};

/// One matrix on PETSC_COMM_WORLD with its Krylov solver and preconditioner set up once, for
/// one or several right-hand sides (the augmented-Lagrangian iterations of solve_constrained).
/// Initializes PETSc on first use; every rank must build it and solve with the same data.
class PetscSolver {
 public:
  /// A square, its rows a multiple of setup.components.
  PetscSolver(const Eigen::SparseMatrix<double>& A, const PetscSolveSetup& setup);
  ~PetscSolver();
  PetscSolver(const PetscSolver&) = delete;
  PetscSolver& operator=(const PetscSolver&) = delete;

  /// Solves A x = b from the initial guess x0 (empty: zero), to the set-up's tolerance (after
  /// the options) times `rtol_scale` (a caller measuring the residual against another norm). Sets info.solver ("PETSc CG +
  /// GAMG (rigid-body near-null space) on 2 ranks"), unknowns, nonzeros, converged
  /// (KSPConvergedReason) and residual (the true ‖b − A x‖/‖b‖), adds the iterations to
  /// info.iterations. Throws SingularError naming the reason and what to try when the Krylov
  /// solve diverges or reaches its iteration limit, or the result is not finite; InputError
  /// when PETSc refuses the options.
  Eigen::VectorXd solve(const Eigen::VectorXd& b, SolveInfo& info,
                        const Eigen::VectorXd& x0 = {}, double rtol_scale = 1.0);

 private:
  struct State;
  std::unique_ptr<State> s_;
};

/// PetscSolver(A, setup).solve(b, info): one right-hand side.
Eigen::VectorXd petsc_solve(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& b,
                            const PetscSolveSetup& setup, SolveInfo& info);

/// The right-hand side after eliminating the unknowns `fixed` at `values`:
/// b − A x_fixed on the free rows, diagonal × value on the fixed ones.
Eigen::VectorXd eliminated_rhs(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& b,
                               const std::vector<int>& fixed, const Eigen::VectorXd& values,
                               double diagonal);

}  // namespace mfv
