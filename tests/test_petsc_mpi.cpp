// solver=petsc on the ranks of mpirun (run by CTest under ${MPIEXEC_EXECUTABLE} -n 2): each
// rank solves the cantilever with PETSc across the ranks and compares its errors with the
// one-process UMFPACK solve of the same case on its own.
#include <string>
#include <tuple>

#include <gtest/gtest.h>

#include "apps/catalogue.hpp"
#include "methods/core/petsc_session.hpp"
#include "verify/runner.hpp"

namespace mfv {
namespace {

CaseResult run(const std::string& method, const std::string& solver) {
  static const Catalogue catalogue;
  CaseSpec s;
  s.problem = "cantilever";
  s.method = method;
  s.problem_params = Params::parse("solver=" + solver);
  s.nodes = 9;
  return run_case(catalogue, s);
}

class OnRanks : public ::testing::TestWithParam<std::string> {};

// ksp_rtol = 1e-10; the errors are norms of the solution, which agrees with UMFPACK's to
// 100 × ksp_rtol on one process (test_petsc_solver.cpp): bound 1e-8 relative.
TEST_P(OnRanks, SameErrorsAsOneProcess) {
  const CaseResult petsc = run(GetParam(), "petsc");
  const CaseResult direct = run(GetParam(), "direct");
  const SolveInfo& s = petsc.data<StaticSolveData>().solve;
  const int ranks = petsc::size();
  EXPECT_NE(s.solver.find(fmt::format("on {} rank", ranks)), std::string::npos) << s.solver;
  EXPECT_GT(s.iterations, 0);
  for (const auto& [name, p, d] :
       {std::tuple{"l2", petsc.errors.l2_rel, direct.errors.l2_rel},
        std::tuple{"h1", petsc.errors.h1_rel, direct.errors.h1_rel},
        std::tuple{"energy", petsc.errors.energy_rel, direct.errors.energy_rel}})
    EXPECT_NEAR(p, d, 1e-8 * d) << name << " on rank " << petsc::rank() << " of " << ranks;
}

INSTANTIATE_TEST_SUITE_P(Methods, OnRanks, ::testing::Values("fem", "efg-ni", "kbm-si", "sph"),
                         [](const auto& info) {
                           std::string n = info.param;
                           for (char& c : n)
                             if (c == '-') c = '_';
                           return n;
                         });

TEST(OnRanks, RunsOnTwo) { EXPECT_EQ(petsc::size(), 2) << "run under mpiexec -n 2"; }

}  // namespace
}  // namespace mfv

int main(int argc, char** argv) {
  mfv::petsc::ensure_initialized();
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
