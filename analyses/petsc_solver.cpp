#include "analyses/petsc_solver.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <iostream>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <petscksp.h>

#include "methods/core/errors.hpp"
#include "methods/core/petsc_session.hpp"

namespace mfv {

namespace {

using petsc::check;

/// PETSc objects destroyed on every path out (an exception included).
template <class T, PetscErrorCode (*Destroy)(T*)>
struct Owned {
  T p = nullptr;
  Owned() = default;
  Owned(const Owned&) = delete;
  Owned& operator=(const Owned&) = delete;
  ~Owned() {
    if (p) Destroy(&p);
  }
};
using OwnedMat = Owned<Mat, MatDestroy>;
using OwnedVec = Owned<Vec, VecDestroy>;
using OwnedKsp = Owned<KSP, KSPDestroy>;
using OwnedScatter = Owned<VecScatter, VecScatterDestroy>;
using OwnedNullSpace = Owned<MatNullSpace, MatNullSpaceDestroy>;

/// An options database of this solve's own, made the default while it lives: the
/// PETSC_OPTIONS environment variable, then the case's petsc_options (later ones win). A
/// case's options thus never leak into the next case's solve, as they would through the
/// process-wide database.
class SolverOptions {
 public:
  explicit SolverOptions(const std::string& text) {
    check(PetscOptionsCreate(&options_), "PetscOptionsCreate");
    if (const char* env = std::getenv("PETSC_OPTIONS")) insert(env, "the PETSC_OPTIONS variable");
    insert(text, "petsc_options");
  }
  SolverOptions(const SolverOptions&) = delete;
  SolverOptions& operator=(const SolverOptions&) = delete;
  ~SolverOptions() { PetscOptionsDestroy(&options_); }

  /// This database as PETSc's default while it lives (set-up and solves read it).
  class Pushed {
   public:
    explicit Pushed(const SolverOptions& o) { check(PetscOptionsPush(o.options_), "PetscOptionsPush"); }
    Pushed(const Pushed&) = delete;
    Pushed& operator=(const Pushed&) = delete;
    ~Pushed() { PetscOptionsPop(); }
  };

  /// The options no PETSc object read (a misspelt name, or one for a type not in use).
  std::vector<std::string> unused() const {
    PetscInt n = 0;
    char** names = nullptr;
    char** values = nullptr;
    std::vector<std::string> out;
    if (PetscOptionsLeftGet(options_, &n, &names, &values) != 0) return out;
    for (PetscInt i = 0; i < n; ++i) out.push_back(std::string("-") + names[i]);
    PetscOptionsLeftRestore(options_, &n, &names, &values);
    return out;
  }

 private:
  void insert(const std::string& text, const char* what) {
    if (text.empty()) return;
    if (PetscOptionsInsertString(options_, text.c_str()) != 0)
      throw InputError(fmt::format("PETSc refused {} '{}': give PETSc's command-line options, "
                                   "e.g. '-ksp_type gmres -pc_type hypre'",
                                   what, text));
  }
  PetscOptions options_ = nullptr;
};

std::string upper(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::toupper(c); });
  return s;
}

}  // namespace

struct PetscSolver::State {
  explicit State(const std::string& options) : options(options) {}
  SolverOptions options;
  OwnedMat K;
  OwnedNullSpace near_null;
  OwnedKsp ksp;
  OwnedVec x, rhs, whole;
  OwnedScatter to_all;
  PetscInt n = 0, m = 0, r0 = 0;
  PetscReal rtol = 0, atol = 0, dtol = 0;  ///< after the options
  PetscInt max_it = 0;
  long nonzeros = 0;
  bool warned = false;
  std::string name;
};

PetscSolver::~PetscSolver() = default;

PetscSolver::PetscSolver(const Eigen::SparseMatrix<double>& A, const PetscSolveSetup& setup) {
  petsc::ensure_initialized();
  s_ = std::make_unique<State>(setup.options);
  State& s = *s_;
  const SolverOptions::Pushed pushed(s.options);
  const MPI_Comm comm = PETSC_COMM_WORLD;
  const PetscInt n = static_cast<PetscInt>(A.rows());
  const PetscInt bs = std::max(setup.components, 1);
  if (A.cols() != n || n % bs != 0)
    throw std::logic_error(fmt::format("PetscSolver: a {}×{} matrix and {} components per "
                                       "particle do not fit",
                                       A.rows(), A.cols(), bs));
  s.n = n;
  s.nonzeros = A.nonZeros();

  // Whole particles per rank: PETSc's split of the n / bs blocks, this rank's first row r0.
  PetscInt local_blocks = PETSC_DECIDE, blocks = n / bs;
  check(PetscSplitOwnership(comm, &local_blocks, &blocks), "PetscSplitOwnership");
  PetscInt last_block = 0;
  MPI_Scan(&local_blocks, &last_block, 1, MPIU_INT, MPI_SUM, comm);
  const PetscInt m = local_blocks * bs, r0 = (last_block - local_blocks) * bs;
  s.m = m;
  s.r0 = r0;

  // The owned rows in CSR, straight from the column-major matrix: columns come in increasing
  // order, so each row's column indices are sorted as PETSc wants them.
  {
    std::vector<PetscInt> ia(m + 1, 0);
    for (int col = 0; col < A.outerSize(); ++col)
      for (Eigen::SparseMatrix<double>::InnerIterator it(A, col); it; ++it)
        if (it.row() >= r0 && it.row() < r0 + m) ++ia[it.row() - r0 + 1];
    for (PetscInt i = 0; i < m; ++i) ia[i + 1] += ia[i];
    std::vector<PetscInt> ja(ia[m]), next(ia.begin(), ia.end() - 1);
    std::vector<PetscScalar> va(ia[m]);
    for (int col = 0; col < A.outerSize(); ++col)
      for (Eigen::SparseMatrix<double>::InnerIterator it(A, col); it; ++it)
        if (it.row() >= r0 && it.row() < r0 + m) {
          const PetscInt k = next[it.row() - r0]++;
          ja[k] = col;
          va[k] = it.value();
        }
    check(MatCreate(comm, &s.K.p), "MatCreate");
    check(MatSetSizes(s.K.p, m, m, n, n), "MatSetSizes");
    check(MatSetBlockSize(s.K.p, bs), "MatSetBlockSize");
    check(MatSetType(s.K.p, MATMPIAIJ), "MatSetType");
    // Exact preallocation (per row, the diagonal-block and off-diagonal-block counts) from
    // the rows themselves; inserts the values and assembles.
    check(MatMPIAIJSetPreallocationCSR(s.K.p, ia.data(), ja.data(), va.data()),
          "MatMPIAIJSetPreallocationCSR");
  }
  if (!setup.fixed.empty()) {
    // Elimination: each rank zeroes its own fixed rows and their columns everywhere.
    std::vector<PetscInt> rows;
    for (int row : setup.fixed)
      if (row >= r0 && row < r0 + m) rows.push_back(row);
    check(MatZeroRowsColumns(s.K.p, static_cast<PetscInt>(rows.size()), rows.data(),
                             setup.fixed_diagonal, nullptr, nullptr),
          "MatZeroRowsColumns");
  }
  if (setup.symmetric) check(MatSetOption(s.K.p, MAT_SPD, PETSC_TRUE), "MatSetOption(MAT_SPD)");
  check(MatCreateVecs(s.K.p, &s.x.p, &s.rhs.p), "MatCreateVecs");

  // The rigid-body modes (translations, rotations) as GAMG's near-null space. They are exact
  // null vectors of the unconstrained stiffness for the particle coefficients too, not only
  // for nodal values: a linearly complete approximation (MLS, RKPM, FEM, the corrected
  // kernels) reproduces u(x) = a + W x exactly when its coefficients are u_I = a + W x_I
  // (Σ N_I = 1, Σ N_I x_I = x), and a rigid motion stores no energy.
  const bool rigid = bs > 1 && setup.coordinates.rows() == bs &&
                     setup.coordinates.cols() == n / bs;
  if (rigid) {
    OwnedVec coords;
    check(VecCreate(comm, &coords.p), "VecCreate");
    check(VecSetSizes(coords.p, m, n), "VecSetSizes");
    check(VecSetBlockSize(coords.p, bs), "VecSetBlockSize");
    check(VecSetType(coords.p, VECMPI), "VecSetType");
    PetscScalar* c = nullptr;
    check(VecGetArray(coords.p, &c), "VecGetArray");
    for (PetscInt p = 0; p < local_blocks; ++p)
      for (PetscInt k = 0; k < bs; ++k) c[p * bs + k] = setup.coordinates(k, r0 / bs + p);
    check(VecRestoreArray(coords.p, &c), "VecRestoreArray");
    check(MatNullSpaceCreateRigidBody(coords.p, &s.near_null.p), "MatNullSpaceCreateRigidBody");
    check(MatSetNearNullSpace(s.K.p, s.near_null.p), "MatSetNearNullSpace");
  }

  check(KSPCreate(comm, &s.ksp.p), "KSPCreate");
  check(KSPSetOperators(s.ksp.p, s.K.p, s.K.p), "KSPSetOperators");
  check(KSPSetType(s.ksp.p, setup.symmetric ? KSPCG : KSPGMRES), "KSPSetType");
  // The stopping test on the true residual: CG measures the unpreconditioned norm, GMRES
  // preconditions from the right (its residual is then the true one).
  if (setup.symmetric)
    check(KSPSetNormType(s.ksp.p, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
  else
    check(KSPSetPCSide(s.ksp.p, PC_RIGHT), "KSPSetPCSide");
  check(KSPSetTolerances(s.ksp.p, setup.rtol, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT),
        "KSPSetTolerances");
  PC pc = nullptr;
  check(KSPGetPC(s.ksp.p, &pc), "KSPGetPC");
  check(PCSetType(pc, PCGAMG), "PCSetType");
  // KSPSetFromOptions only reads the options database: its failure is an option of the user's
  // that PETSc cannot take (a value of the wrong type or range, an unknown type name).
  if (const PetscErrorCode code = KSPSetFromOptions(s.ksp.p); code != 0) {
    const char* text = nullptr;
    PetscErrorMessage(code, &text, nullptr);
    throw InputError(fmt::format("PETSc could not apply the options '{}' (petsc_options, after "
                                 "PETSC_OPTIONS): {}; check each option's value (a number, a "
                                 "type name PETSc knows)",
                                 setup.options, text ? text : "unknown error"));
  }
  check(KSPGetTolerances(s.ksp.p, &s.rtol, &s.atol, &s.dtol, &s.max_it), "KSPGetTolerances");
  check(VecScatterCreateToAll(s.x.p, &s.to_all.p, &s.whole.p), "VecScatterCreateToAll");

  KSPType ksp_type = nullptr;
  PCType pc_type = nullptr;
  check(KSPGetType(s.ksp.p, &ksp_type), "KSPGetType");
  check(PCGetType(pc, &pc_type), "PCGetType");
  const std::string pc_name = upper(pc_type ? pc_type : "none");
  const int ranks = petsc::size();
  s.name = fmt::format("PETSc {} + {}{} on {} rank{}", upper(ksp_type ? ksp_type : "?"), pc_name,
                       rigid && pc_name == "GAMG" ? " (rigid-body near-null space)" : "", ranks,
                       ranks == 1 ? "" : "s");
}

Eigen::VectorXd PetscSolver::solve(const Eigen::VectorXd& b, SolveInfo& info,
                                   const Eigen::VectorXd& x0, double rtol_scale) {
  State& s = *s_;
  const SolverOptions::Pushed pushed(s.options);
  const PetscInt n = s.n, m = s.m, r0 = s.r0;
  if (b.size() != n || (x0.size() != 0 && x0.size() != n))
    throw std::logic_error("PetscSolver::solve: the right-hand side does not fit the matrix");
  info.unknowns = static_cast<int>(n);
  info.nonzeros = s.nonzeros;
  info.solver = s.name;
  {
    PetscScalar* v = nullptr;
    check(VecGetArray(s.rhs.p, &v), "VecGetArray");
    std::copy(b.data() + r0, b.data() + r0 + m, v);
    check(VecRestoreArray(s.rhs.p, &v), "VecRestoreArray");
    check(VecGetArray(s.x.p, &v), "VecGetArray");
    if (x0.size() == n)
      std::copy(x0.data() + r0, x0.data() + r0 + m, v);
    else
      std::fill(v, v + m, 0.0);
    check(VecRestoreArray(s.x.p, &v), "VecRestoreArray");
  }
  check(KSPSetTolerances(s.ksp.p, std::min(s.rtol * rtol_scale, 0.5), s.atol, s.dtol, s.max_it),
        "KSPSetTolerances");
  check(KSPSetInitialGuessNonzero(s.ksp.p, x0.size() == n ? PETSC_TRUE : PETSC_FALSE),
        "KSPSetInitialGuessNonzero");
  const PetscErrorCode solved = KSPSolve(s.ksp.p, s.rhs.p, s.x.p);
  if (solved != 0) {
    // A failed set-up (a zero pivot in a smoother, an indefinite matrix for CG) is a
    // property of the system, not a bug: the caller's SingularError.
    const char* text = nullptr;
    PetscErrorMessage(solved, &text, nullptr);
    throw SingularError(fmt::format(
        "{} could not solve the global system ({} unknowns): {}. Try another preconditioner "
        "(petsc_options '-pc_type hypre' or '-pc_type jacobi') or solver=direct",
        s.name, n, text ? text : "unknown error"));
  }
  KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
  PetscInt its = 0;
  PetscReal rtol = 0, atol = 0, dtol = 0;
  PetscInt max_it = 0;
  check(KSPGetConvergedReason(s.ksp.p, &reason), "KSPGetConvergedReason");
  check(KSPGetIterationNumber(s.ksp.p, &its), "KSPGetIterationNumber");
  check(KSPGetTolerances(s.ksp.p, &rtol, &atol, &dtol, &max_it), "KSPGetTolerances");
  info.iterations += static_cast<int>(its);
  info.converged = KSPConvergedReasons[reason];

  // The true residual of the solved system, whatever norm the Krylov method watched.
  {
    OwnedVec r;
    check(VecDuplicate(s.rhs.p, &r.p), "VecDuplicate");
    check(MatMult(s.K.p, s.x.p, r.p), "MatMult");
    check(VecAYPX(r.p, -1.0, s.rhs.p), "VecAYPX");
    PetscReal rn = 0, bn = 0;
    check(VecNorm(r.p, NORM_2, &rn), "VecNorm");
    check(VecNorm(s.rhs.p, NORM_2, &bn), "VecNorm");
    info.residual = rn / (bn > 0 ? bn : 1.0);
  }
  if (reason < 0)
    throw SingularError(fmt::format(
        "{} did not converge on the global system ({} unknowns): {} after {} iterations "
        "(true relative residual {:.2e}, ksp_rtol {:.1e}, at most {} iterations). Try more "
        "iterations (petsc_options '-ksp_max_it 100000'), a looser ksp_rtol, another "
        "preconditioner ('-pc_type hypre'), or solver=direct",
        s.name, n, info.converged, its, info.residual, rtol, max_it));

  if (!s.warned && petsc::rank() == 0)
    if (const auto left = s.options.unused(); !left.empty())
      std::cerr << fmt::format("warning: PETSc did not use the options {}: check their "
                               "spelling and the solver types they apply to\n",
                               fmt::join(left, " "));
  s.warned = true;

  // Every rank gets the whole solution (the errors are computed everywhere).
  check(VecScatterBegin(s.to_all.p, s.x.p, s.whole.p, INSERT_VALUES, SCATTER_FORWARD),
        "VecScatterBegin");
  check(VecScatterEnd(s.to_all.p, s.x.p, s.whole.p, INSERT_VALUES, SCATTER_FORWARD),
        "VecScatterEnd");
  Eigen::VectorXd out(n);
  const PetscScalar* w = nullptr;
  check(VecGetArrayRead(s.whole.p, &w), "VecGetArrayRead");
  std::copy(w, w + n, out.data());
  check(VecRestoreArrayRead(s.whole.p, &w), "VecRestoreArrayRead");
  if (!out.allFinite() || !std::isfinite(info.residual))
    throw SingularError(fmt::format(
        "{} returned a solution that is not finite on the global system ({} unknowns): the "
        "matrix is singular or the preconditioner broke down; try solver=direct",
        s.name, n));
  // A converged solve whose true residual is far above its tolerance watched another norm
  // (e.g. -ksp_norm_type preconditioned): its result is not what ksp_rtol promised.
  if (!(info.residual <= std::max(1e-6, 1e3 * rtol)))
    throw SingularError(fmt::format(
        "{} stopped ({}) with a true relative residual {:.2e}, far above ksp_rtol {:.1e}: the "
        "norm it watched is not the residual's (the system is badly conditioned); use the "
        "unpreconditioned norm, a tighter ksp_rtol or solver=direct",
        s.name, info.converged, info.residual, rtol));
  return out;
}

Eigen::VectorXd petsc_solve(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& b,
                            const PetscSolveSetup& setup, SolveInfo& info) {
  info.iterations = 0;
  return PetscSolver(A, setup).solve(b, info);
}

Eigen::VectorXd eliminated_rhs(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& b,
                               const std::vector<int>& fixed, const Eigen::VectorXd& values,
                               double diagonal) {
  Eigen::VectorXd x0 = Eigen::VectorXd::Zero(A.cols());
  for (std::size_t k = 0; k < fixed.size(); ++k) x0[fixed[k]] = values[static_cast<Eigen::Index>(k)];
  Eigen::VectorXd out = b - A * x0;
  for (std::size_t k = 0; k < fixed.size(); ++k)
    out[fixed[k]] = diagonal * values[static_cast<Eigen::Index>(k)];
  return out;
}

}  // namespace mfv
