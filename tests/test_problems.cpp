/// Exact solutions against finite differences and against their boundary data; the source
/// terms checked by solving with a fine FEM mesh.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "test_support.hpp"
#include "verify/runner.hpp"

namespace mfv {
namespace {

class ExactSolutions : public ::testing::TestWithParam<std::string> {};

TEST_P(ExactSolutions, DerivativeMatchesFiniteDifferences) {
  const auto p = test_catalogue().problems.create(GetParam());
  const Domain d = p->domain();
  const int n = 997;
  const double e = 1e-6;
  Eigen::MatrixXd x(1, n), xp(1, n), xm(1, n);
  for (int i = 0; i < n; ++i) {
    x(0, i) = d.lower[0] + (d.upper[0] - d.lower[0]) * (i + 0.5) / n;
    xp(0, i) = x(0, i) + e;
    xm(0, i) = x(0, i) - e;
  }
  Eigen::VectorXd u, du, up, dup, um, dum;
  p->exact(x, u, du);
  p->exact(xp, up, dup);
  p->exact(xm, um, dum);
  for (int i = 0; i < n; ++i)
    EXPECT_NEAR(du[i], (up[i] - um[i]) / (2 * e), 1e-6 * (1 + std::abs(du[i]))) << "x = " << x(0, i);
}

TEST_P(ExactSolutions, SatisfiesItsEssentialConditions) {
  const auto p = test_catalogue().problems.create(GetParam());
  CaseSpec spec{GetParam(), {}, "fem", {}, 11, 0};
  const auto m = test_catalogue().methods.create("fem");
  const Discretization d =
      m->discretize(p->domain(), uniform_line(p->domain(), 11), p->derivative_order());
  const AssembledSystem sys = p->assemble(d);
  Eigen::VectorXd u, du;
  p->exact(sys.constraint_points, u, du);
  for (int b = 0; b < u.size(); ++b) EXPECT_NEAR(u[b], sys.constraint_values[b], 1e-12);
}

TEST_P(ExactSolutions, FineFemSolvesTheStatedEquation) {
  // A consistent source and weak form make FEM converge to the exact solution; a wrong sign
  // or a garbled source (004 I eq 6.4) would leave an O(1) error.
  CaseSpec spec{GetParam(), {}, "fem", {}, 2401, 0};
  const CaseResult r = run_case(test_catalogue(), spec);
  // 2401 nodes resolve the peaks (width 0.05) by 20 elements: O(h^2) gives ~1e-4 in L2.
  EXPECT_LT(r.errors.l2_rel, 5e-4);
  EXPECT_LT(r.errors.h1_semi_rel, 6e-2);
}

INSTANTIATE_TEST_SUITE_P(AllProblems, ExactSolutions,
                         ::testing::ValuesIn(test_catalogue().problems.keys()),
                         [](const auto& info) {
                           std::string n = info.param;
                           for (auto& c : n)
                             if (c == '-') c = '_';
                           return n;
                         });

TEST(Problems, AdvectionCaseIsStable) {
  // a = 1000 on 241 nodes: element Péclet number 12.5, boundary layer of width 1/a = 0.001
  // inside the last element. Plain Galerkin would oscillate node to node; the stabilized form
  // (004 I eq 6.3) must keep the nodal values free of wiggles and accurate away from the layer.
  Params pp;
  pp.set("a", 1000.0);
  CaseSpec spec{"advection-diffusion", pp, "fem", {}, 241, 0};
  const CaseResult r = run_case(test_catalogue(), spec);
  const Eigen::VectorXd err = r.fields.u_h - r.fields.u_exact;
  const Eigen::Index n = err.size();
  double away = 0;
  for (Eigen::Index i = 0; i + 2 < n; ++i) away = std::max(away, std::abs(err[i]));
  EXPECT_LT(away, 0.05 * r.fields.u_exact.cwiseAbs().maxCoeff()) << "nodal error off the layer";
  // No node-to-node oscillation: the error does not alternate in sign over the last nodes.
  int alternations = 0;
  for (Eigen::Index i = n - 12; i + 1 < n - 1; ++i)
    if (err[i] * err[i + 1] < 0 && std::abs(err[i]) > 1e-3) ++alternations;
  EXPECT_LE(alternations, 1);
}

}  // namespace
}  // namespace mfv
