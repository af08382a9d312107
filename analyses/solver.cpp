#include "analyses/solver.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <memory>

#include <Eigen/IterativeLinearSolvers>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <umfpack.h>

#include "methods/core/errors.hpp"

namespace mfv {

namespace {

/// Why a direct solve did not produce an answer, when it is worth trying the fallback.
struct DirectFailure {
  std::string reason;
};

/// UMFPACK's C interface (the Eigen wrapper hides the fill and condition statistics).
Eigen::VectorXd umfpack_solve(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& b,
                              SolveInfo& info, DirectFailure& failure) {
  const int n = static_cast<int>(A.rows());
  const int* Ap = A.outerIndexPtr();
  const int* Ai = A.innerIndexPtr();
  const double* Ax = A.valuePtr();
  double control[UMFPACK_CONTROL], stats[UMFPACK_INFO];
  umfpack_di_defaults(control);
  void* symbolic = nullptr;
  void* numeric = nullptr;
  int status = umfpack_di_symbolic(n, n, Ap, Ai, Ax, &symbolic, control, stats);
  if (status == UMFPACK_OK)
    status = umfpack_di_numeric(Ap, Ai, Ax, symbolic, &numeric, control, stats);
  if (symbolic) umfpack_di_free_symbolic(&symbolic);
  std::unique_ptr<void, void (*)(void*)> keep(numeric, [](void* p) {
    if (p) umfpack_di_free_numeric(&p);
  });
  if (status == UMFPACK_WARNING_singular_matrix)
    throw SingularError(fmt::format(
        "the global system ({} unknowns) is singular: UMFPACK found a zero pivot. Typical "
        "causes: a support too small for the particle spacing (raise dmax), spurious "
        "zero-energy modes of nodal integration, or boundary conditions that do not fix the "
        "solution",
        n));
  if (status != UMFPACK_OK) {
    failure.reason = status == UMFPACK_ERROR_out_of_memory
                         ? "UMFPACK ran out of memory"
                         : fmt::format("UMFPACK factorization failed (status {})", status);
    return {};
  }
  info.fill = static_cast<long>(stats[UMFPACK_LNZ] + stats[UMFPACK_UNZ]);
  info.rcond = stats[UMFPACK_RCOND];
  Eigen::VectorXd x(n);
  status = umfpack_di_solve(UMFPACK_A, Ap, Ai, Ax, x.data(), b.data(), numeric, control, stats);
  if (status != UMFPACK_OK && status != UMFPACK_WARNING_singular_matrix) {
    failure.reason = fmt::format("UMFPACK solve failed (status {})", status);
    return {};
  }
  info.solver = "UMFPACK LU";
  return x;
}

Eigen::VectorXd iterative_solve(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& b,
                                SolveInfo& info) {
  Eigen::BiCGSTAB<Eigen::SparseMatrix<double>, Eigen::IncompleteLUT<double>> it;
  it.preconditioner().setDroptol(1e-6);
  it.preconditioner().setFillfactor(20);
  it.setTolerance(1e-12);
  it.setMaxIterations(std::max<Eigen::Index>(1000, A.rows()));
  it.compute(A);
  if (it.info() != Eigen::Success)
    throw SingularError(fmt::format(
        "the global system ({} unknowns): the incomplete LU preconditioner failed (zero pivot); "
        "the matrix is singular or badly scaled: raise dmax or use --solver direct",
        A.rows()));
  Eigen::VectorXd x = it.solve(b);
  info.iterations = static_cast<int>(it.iterations());
  info.solver += "BiCGSTAB + ILUT";
  return x;
}

}  // namespace

void check_solver_choice(const SolverChoice& choice) {
  if (std::find(std::begin(kSolverChoices), std::end(kSolverChoices), choice.kind) ==
      std::end(kSolverChoices))
    throw InputError(fmt::format("unknown solver '{}'; valid: {}", choice.kind,
                                 fmt::join(kSolverChoices, ", ")));
  if (!(choice.ksp_rtol > 0 && choice.ksp_rtol < 1))
    throw InputError(fmt::format(
        "ksp_rtol = {} must lie in (0, 1): it is the Krylov solve's relative tolerance on "
        "‖b − A x‖/‖b‖; e.g. ksp_rtol=1e-10",
        choice.ksp_rtol));
  if (!choice.petsc_options.empty() && choice.kind != "petsc")
    throw InputError(fmt::format(
        "petsc_options '{}' is given with solver={}, which does not use PETSc: add "
        "solver=petsc or leave petsc_options out",
        choice.petsc_options, choice.kind));
  // PETSc's option parser skips a leading word that is not an option name without a word,
  // so a typo such as "ksp_type cg" would be ignored: the text must open with "-name".
  const auto first = choice.petsc_options.find_first_not_of(" \t");
  if (first != std::string::npos && choice.petsc_options[first] != '-')
    throw InputError(fmt::format(
        "petsc_options '{}' must start with an option name such as -ksp_type (PETSc's command "
        "line: '-ksp_type gmres -ksp_rtol 1e-10')",
        choice.petsc_options));
  if (const std::string why = petsc_option_touching_files(choice.petsc_options); !why.empty())
    throw InputError(fmt::format(
        "petsc_options '{}': {}; mfv passes no PETSc option that reads or writes a file or starts "
        "a program, from a manifest or the command line (a suite file must not touch yours): "
        "use the option without a file ('-ksp_monitor' prints to stdout), or set PETSC_OPTIONS "
        "in your own environment",
        choice.petsc_options, why));
}

std::string petsc_option_touching_files(const std::string& text) {
  // Options that read files, write logs or start programs whatever their value.
  static const char* const kNames[] = {
      "options_file", "options_file_yaml", "options_string_yaml", "log_trace", "log_view",
      "log_summary", "log_all", "log_mpe", "log_perfstubs", "info", "history", "malloc_dump",
      "malloc_view", "malloc_log", "objects_dump", "start_in_debugger", "on_error_attach_debugger",
      "stop_for_debugger", "debugger_ranks", "debugger_pause", "display", "on_error_emacs",
      "viewer_binary_filename", "viewer_binary_skip_info", "petscspace_view",
      "saws_port", "saws_root", "python"};
  std::vector<std::string> words;
  {
    std::string w;
    for (char ch : text) {
      if (ch == ' ' || ch == '\t' || ch == '\n') {
        if (!w.empty()) words.push_back(w), w.clear();
      } else {
        w += ch;
      }
    }
    if (!w.empty()) words.push_back(w);
  }
  for (std::size_t i = 0; i < words.size(); ++i) {
    const std::string& w = words[i];
    if (w.size() < 2 || w[0] != '-' || (w[1] >= '0' && w[1] <= '9') || w[1] == '.') continue;
    std::string name = w.substr(w[1] == '-' ? 2 : 1);
    // A prefixed option (-sub_ksp_view, -fieldsplit_0_pc_type) keeps its meaning: match ends.
    for (const char* n : kNames) {
      const std::string bad(n);
      if (name == bad || (name.size() > bad.size() &&
                          name.compare(name.size() - bad.size(), bad.size(), bad) == 0 &&
                          name[name.size() - bad.size() - 1] == '_'))
        return fmt::format("'-{}' reads or writes files or starts a program", name);
    }
    // A viewer value "type:file[:format[:mode]]" (-ksp_monitor ascii:out.txt, -mat_view
    // binary:A.dat) opens the file; "::ascii_info" and a bare type keep to stdout.
    if (i + 1 < words.size() && words[i + 1][0] != '-') {
      const std::string& v = words[i + 1];
      // Viewers that write a file (binary writes "binaryoutput" when none is named), open a
      // window or a socket, whatever follows.
      static const char* const kViewers[] = {"binary", "hdf5", "vtk", "socket", "draw",
                                             "matlab", "saws", "glvis", "adios", "mathematica"};
      const std::string type = v.substr(0, v.find(':'));
      for (const char* t : kViewers)
        if (type == t)
          return fmt::format("'-{} {}' opens a {} viewer (a file, window or socket)", name, v, t);
      const auto colon = v.find(':');
      if (colon != std::string::npos) {
        const auto next = v.find(':', colon + 1);
        const std::string file = v.substr(colon + 1, next == std::string::npos ? std::string::npos
                                                                               : next - colon - 1);
        if (!file.empty())
          return fmt::format("'-{} {}' opens the file '{}'", name, v, file);
      }
    }
  }
  return {};
}

Eigen::VectorXd solve_sparse(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& b,
                             const std::string& kind, SolveInfo& info) {
  if (kind != "auto" && kind != "direct" && kind != "iterative")
    throw InputError(fmt::format("unknown solver '{}'; valid: auto, direct, iterative", kind));
  Eigen::SparseMatrix<double> C = A;
  C.makeCompressed();
  info.unknowns = static_cast<int>(C.rows());
  info.nonzeros = C.nonZeros();
  info.solver.clear();
  Eigen::VectorXd x;
  if (kind != "iterative") {
    DirectFailure failure;
    x = umfpack_solve(C, b, info, failure);
    if (!failure.reason.empty()) {
      if (kind == "direct")
        throw SingularError(fmt::format("the global system ({} unknowns): {}; try --solver "
                                        "iterative",
                                        info.unknowns, failure.reason));
      info.solver = fmt::format("fallback after {}: ", failure.reason);
      x = iterative_solve(C, b, info);
    }
  } else {
    x = iterative_solve(C, b, info);
  }
  const double bn = b.norm();
  info.residual = x.size() == b.size() ? (C * x - b).norm() / (bn > 0 ? bn : 1.0) : NAN;
  if (!x.allFinite() || !(info.residual < 1e-6))
    throw SingularError(fmt::format(
        "the global system ({} unknowns) is numerically singular: relative residual {:.2e} "
        "after {} (reciprocal condition estimate {:.1e}). Raise the support (dmax) or use "
        "another boundary treatment",
        info.unknowns, info.residual, info.solver, info.rcond));
  return x;
}

}  // namespace mfv
