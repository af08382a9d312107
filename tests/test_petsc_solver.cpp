// solver=petsc (analyses/petsc_solver.hpp) against UMFPACK on the same cantilever systems: the
// solution, the reported iterations and residual, refused parameters and a forced failure.
#include <cmath>
#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

#include "analyses/solver.hpp"

#include "apps/catalogue.hpp"
#include "methods/core/errors.hpp"
#include "methods/core/petsc_session.hpp"
#include "verify/runner.hpp"

namespace mfv {
namespace {

const Catalogue& catalogue() {
  static const Catalogue c;
  return c;
}

CaseSpec cantilever(const std::string& method, const std::string& method_params,
                    const std::string& problem_params, int nodes = 9) {
  CaseSpec s;
  s.problem = "cantilever";
  s.method = method;
  s.method_params = Params::parse(method_params);
  s.problem_params = Params::parse(problem_params);
  s.nodes = nodes;
  return s;
}

const SolveInfo& solve_info(const CaseResult& r) { return r.data<StaticSolveData>().solve; }

double relative_difference(const CaseResult& a, const CaseResult& b) {
  const Eigen::VectorXd& ua = a.data<StaticSolveData>().fields.coefficient;
  const Eigen::VectorXd& ub = b.data<StaticSolveData>().fields.coefficient;
  EXPECT_EQ(ua.size(), ub.size());
  return (ua - ub).norm() / ub.norm();
}

struct Agreement {
  std::string method, method_params;  // method_params: e.g. bc=penalty
  std::string krylov;                 // "CG" or "GMRES"
  std::string conditions;             // what the solver line says of them
  double tolerance;                   // on the relative solution difference
};

class PetscAgrees : public ::testing::TestWithParam<Agreement> {};

// ksp_rtol = 1e-10 on the true residual. Multipliers (augmented Lagrangian) and elimination
// reach the multiplier system's solution: measured relative differences 7e-13 to 9e-12 at
// 9 × 33 particles, bound 1e-8 = 100 × ksp_rtol. bc=penalty solves the same
// K + 1e8 · kmax G Gᵀ as UMFPACK, whose condition (~1e12) turns the same residual into larger
// differences (measured 2.1e-6; the BiCGSTAB test of test_elasticity.cpp finds 2.6e-4 at
// residual 1e-12): bound 1e-4.
TEST_P(PetscAgrees, WithUmfpackOnTheSameSystem) {
  const Agreement& a = GetParam();
  const CaseResult direct =
      run_case(catalogue(), cantilever(a.method, a.method_params, "solver=direct"));
  const CaseResult petsc =
      run_case(catalogue(), cantilever(a.method, a.method_params, "solver=petsc"));
  const SolveInfo& s = solve_info(petsc);
  EXPECT_NE(s.solver.find("PETSc " + a.krylov + " + GAMG"), std::string::npos) << s.solver;
  EXPECT_NE(s.solver.find(a.conditions), std::string::npos) << s.solver;
  EXPECT_GT(s.iterations, 0);
  EXPECT_EQ(s.converged.rfind("CONVERGED", 0), 0u) << s.converged;
  EXPECT_LE(s.residual, 10 * 1e-10);
  EXPECT_LE(relative_difference(petsc, direct), a.tolerance) << s.solver;
  EXPECT_NEAR(petsc.errors.l2_rel, direct.errors.l2_rel, a.tolerance * direct.errors.l2_rel);
  EXPECT_NEAR(petsc.errors.energy_rel, direct.errors.energy_rel,
              a.tolerance * direct.errors.energy_rel);
}

INSTANTIATE_TEST_SUITE_P(
    Methods, PetscAgrees,
    ::testing::Values(Agreement{"fem", "", "CG", "augmented Lagrangian", 1e-8},
                      Agreement{"efg-ni", "", "CG", "augmented Lagrangian", 1e-8},
                      Agreement{"efg-ni", "bc=penalty", "CG", "penalty β = 1e+08", 1e-4},
                      Agreement{"kbm-si", "", "GMRES", "augmented Lagrangian", 1e-8},
                      Agreement{"sph", "", "GMRES", "elimination", 1e-8}),
    [](const auto& info) {
      std::string n = info.param.method + (info.param.method_params.empty() ? "" : "_penalty");
      for (char& c : n)
        if (c == '-') c = '_';
      return n;
    });

TEST(PetscSolver, MethodParamsReachTheAnalysis) {
  // -p solver=petsc: the method does not declare `solver`, the static-solve analysis does.
  const CaseResult r = run_case(catalogue(), cantilever("fem", "solver=petsc", ""));
  EXPECT_NE(solve_info(r).solver.find("PETSc"), std::string::npos);
  EXPECT_EQ(r.analysis_params.text("solver"), "petsc");
  EXPECT_FALSE(r.spec.method_params.has("solver"));
  // An unknown key names the method's and the analysis's parameters.
  try {
    run_case(catalogue(), cantilever("fem", "solvr=petsc", ""));
    ADD_FAILURE() << "an unknown key was accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("solvr"), std::string::npos) << m;
    EXPECT_NE(m.find("ksp_rtol"), std::string::npos) << m;
  }
  // The same analysis key with two values is refused.
  EXPECT_THROW(run_case(catalogue(), cantilever("fem", "solver=petsc", "solver=direct")),
               InputError);
}

void expect_refused(const std::string& problem_params, const std::string& names) {
  try {
    run_case(catalogue(), cantilever("fem", "", problem_params));
    ADD_FAILURE() << problem_params << " was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(names), std::string::npos) << e.what();
  }
}

TEST(PetscSolver, RefusesBadParameters) {
  for (const char* v : {"0", "-1", "2", "1"}) expect_refused(std::string("solver=petsc,ksp_rtol=") + v, "ksp_rtol");
  CaseSpec nan = cantilever("fem", "", "solver=petsc");
  nan.problem_params.set("ksp_rtol", std::nan(""));
  EXPECT_THROW(run_case(catalogue(), nan), InputError);
  expect_refused("solver=direct,petsc_options=-ksp_type gmres", "petsc_options");
  expect_refused("petsc_options=-ksp_type gmres", "petsc_options");
  expect_refused("solver=petsc,petsc_options=ksp_type gmres", "must start with an option name");
  expect_refused("solver=cholesky", "solver");
}

/// Issue 26: no PETSc option that reads or writes a file or starts a program passes, from a
/// manifest or the command line (the reproducer truncated any file with -ksp_monitor ascii:);
/// options that print to stdout do.
TEST(PetscSolver, RefusesOptionsThatTouchFiles) {
  for (const char* o : {"-ksp_monitor ascii:/tmp/mfv-victim", "-ksp_view ascii:out.txt",
                        "-options_file /etc/passwd", "-options_file_yaml x.yaml",
                        "-log_view", "-log_view ascii:log.txt", "-info /tmp/info",
                        "-mat_view binary", "-ksp_view_mat binary:A.dat", "-vec_view hdf5:x.h5",
                        "-ksp_monitor draw", "-start_in_debugger", "-on_error_attach_debugger",
                        "-history /tmp/h", "-sub_options_file x", "--options_file x",
                        "-ksp_type cg -ksp_monitor_true_residual ascii:r.txt"}) {
    EXPECT_NE(petsc_option_touching_files(o), "") << o;
    expect_refused(std::string("solver=petsc,petsc_options=") + o, "reads or writes a file");
  }
  // A value PETSc cannot take is bad input too (exit 2), not a failure of the run.
  expect_refused("solver=petsc,petsc_options=-ksp_rtol abc", "could not apply the options");
  expect_refused("solver=petsc,petsc_options=-ksp_type no-such-krylov", "could not apply");
  for (const char* o : {"-ksp_monitor", "-ksp_view ::ascii_info", "-ksp_type gmres -pc_type jacobi",
                        "-ksp_rtol 1e-12", "-ksp_monitor ascii", "-ksp_view ascii::ascii_info_detail",
                        "-pc_gamg_threshold -0.01", "-mg_levels_ksp_max_it 3"})
    EXPECT_EQ(petsc_option_touching_files(o), "") << o;
}

TEST(PetscSolver, FailedKrylovSolveIsSingularError) {
  try {
    run_case(catalogue(),
             cantilever("efg-ni", "", "solver=petsc,petsc_options=-ksp_max_it 1"));
    ADD_FAILURE() << "a Krylov solve stopped after one iteration gave a result";
  } catch (const SingularError& e) {
    EXPECT_NE(std::string(e.what()).find("DIVERGED_ITS"), std::string::npos) << e.what();
  }
  // The case's options do not leak into the next solve.
  EXPECT_NO_THROW(run_case(catalogue(), cantilever("efg-ni", "", "solver=petsc")));
}

TEST(PetscSolver, ReadsPetscOptionsFromTheEnvironment) {
  ASSERT_EQ(setenv("PETSC_OPTIONS", "-ksp_max_it 1", 1), 0);
  EXPECT_THROW(run_case(catalogue(), cantilever("fem", "", "solver=petsc")), SingularError);
  // The case's own options come after the variable's and win.
  EXPECT_NO_THROW(run_case(catalogue(),
                           cantilever("fem", "", "solver=petsc,petsc_options=-ksp_max_it 500")));
  unsetenv("PETSC_OPTIONS");
}

}  // namespace
}  // namespace mfv
