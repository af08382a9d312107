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

/// Points spread over the domain's box (a 1D line or a 2D grid), away from its edges.
Eigen::MatrixXd interior_points(const Domain& d) {
  const int n = d.dim == 1 ? 997 : 31;
  const int total = d.dim == 1 ? n : n * n;
  Eigen::MatrixXd x(d.dim, total);
  for (int k = 0; k < total; ++k)
    for (int c = 0; c < d.dim; ++c) {
      const int i = c == 0 ? k % n : k / n;
      x(c, k) = d.lower[c] + (d.upper[c] - d.lower[c]) * (i + 0.5) / n;
    }
  return x;
}

TEST_P(ExactSolutions, DerivativeMatchesFiniteDifferences) {
  const auto p = test_catalogue().problems.create(GetParam());
  if (p->transient()) GTEST_SKIP() << "transient problem: its exact solution is tested in test_dynamics";
  if (p->analysis()) GTEST_SKIP() << "analysis problem: no field to solve for";
  const Domain d = p->domain();
  const Eigen::MatrixXd x = interior_points(d);
  const double e = 1e-6 * (d.upper - d.lower).maxCoeff();
  Eigen::MatrixXd u, g, up, gp, um, gm;
  p->exact_field(x, u, g);
  const double scale = g.cwiseAbs().maxCoeff();
  for (int dir = 0; dir < d.dim; ++dir) {
    Eigen::MatrixXd xp = x, xm = x;
    xp.row(dir).array() += e;
    xm.row(dir).array() -= e;
    p->exact_field(xp, up, gp);
    p->exact_field(xm, um, gm);
    for (int c = 0; c < p->components(); ++c)
      for (Eigen::Index i = 0; i < x.cols(); ++i)
        EXPECT_NEAR(g(c * d.dim + dir, i), (up(c, i) - um(c, i)) / (2 * e),
                    1e-6 * (scale + std::abs(g(c * d.dim + dir, i))))
            << "component " << c << ", direction " << dir << ", point " << i;
  }
}

TEST_P(ExactSolutions, SatisfiesItsEssentialConditions) {
  const auto p = test_catalogue().problems.create(GetParam());
  if (p->transient()) GTEST_SKIP() << "transient problem: its exact solution is tested in test_dynamics";
  if (p->analysis()) GTEST_SKIP() << "analysis problem: no field to solve for";
  const auto m = test_catalogue().methods.create("fem");
  const Discretization d =
      m->discretize(p->domain(), p->particles(p->domain().dim == 1 ? 11 : 5, 0),
                    p->derivative_order());
  const AssembledSystem sys = p->assemble(d);
  ASSERT_GT(sys.constraint_values.size(), 0);
  Eigen::MatrixXd u, g;
  p->exact_field(sys.constraint_points, u, g);
  for (int b = 0; b < sys.constraint_values.size(); ++b) {
    const int c = sys.constraint_components.empty() ? 0 : sys.constraint_components[b];
    EXPECT_NEAR(u(c, b), sys.constraint_values[b], 1e-12 * (1 + u.cwiseAbs().maxCoeff()));
  }
}

TEST_P(ExactSolutions, FineFemSolvesTheStatedEquation) {
  // A consistent source and weak form make FEM converge to the exact solution; a wrong sign
  // or a garbled source (004 I eq 6.4) would leave an O(1) error.
  const auto p = test_catalogue().problems.create(GetParam());
  if (p->transient()) GTEST_SKIP() << "transient problem: its exact solution is tested in test_dynamics";
  if (p->analysis()) GTEST_SKIP() << "analysis problem: no field to solve for";
  const bool line = p->domain().dim == 1;
  CaseSpec spec{GetParam(), {}, "fem", {}, line ? 2401 : 33, 0};
  const CaseResult r = run_case(test_catalogue(), spec);
  // 1D: 2401 nodes resolve the peaks (width 0.05) by 20 elements: O(h^2) gives ~1e-4 in L2.
  // 2D: Q4 on 129 × 33 (cantilever) measures 4.5e-4 in L2 and 2e-2 in energy.
  EXPECT_LT(r.errors.l2_rel, line ? 5e-4 : 1e-3);
  EXPECT_LT(r.errors.h1_semi_rel, line ? 6e-2 : 5e-2);
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
