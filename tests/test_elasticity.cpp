/// 2D elasticity: the cantilever's exact solution, the gradient tables of every registered
/// method that runs in 2D (001 Table 1), the displacement patch test with the outcome each
/// method's consistency and quadrature predict, the sparse solver's failure modes, and the
/// findings' verdicts.
#include <cmath>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <tuple>

#include <gtest/gtest.h>

#include "methods/core/errors.hpp"
#include "analyses/report_section.hpp"
#include "test_support.hpp"
#include "analyses/norms.hpp"
#include "reports/convergence.hpp"
#include "verify/runner.hpp"
#include "analyses/solver.hpp"

namespace mfv {
namespace {

TEST(Cantilever, ExactStressIsInEquilibriumAndCarriesTheLoad) {
  const auto p = test_catalogue().problems.create_as<BoundaryValueProblem>("cantilever");
  // Stresses from the exact displacement gradient: σ_yy = 0, σ_xy parabolic (Timoshenko).
  Eigen::MatrixXd x(2, 3), u, g;
  x << 0.0, 24.0, 48.0, -6.0, 1.5, 3.0;
  p->exact_field(x, u, g);
  const Eigen::MatrixXd s = p->flux(g);
  const double I = 12.0 * 12 * 12 / 12, P = 1000;
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(s(0, i), -P * (48 - x(0, i)) * x(1, i) / I, 1e-9 * P);
    EXPECT_NEAR(s(1, i), 0.0, 1e-9 * P);
    EXPECT_NEAR(s(2, i), P / (2 * I) * (36 - x(1, i) * x(1, i)), 1e-9 * P);
  }
  // div σ = 0 by central differences of the stress from exact gradients.
  const double e = 1e-4;
  Eigen::MatrixXd c(2, 1), ug;
  c << 17.0, 2.5;
  auto stress_at = [&](double dx, double dy) {
    Eigen::MatrixXd y = c;
    y(0, 0) += dx;
    y(1, 0) += dy;
    Eigen::MatrixXd uu, gg;
    p->exact_field(y, uu, gg);
    return Eigen::Vector3d(p->flux(gg).col(0));
  };
  const Eigen::Vector3d dsx = (stress_at(e, 0) - stress_at(-e, 0)) / (2 * e);
  const Eigen::Vector3d dsy = (stress_at(0, e) - stress_at(0, -e)) / (2 * e);
  EXPECT_NEAR(dsx[0] + dsy[2], 0.0, 1e-5);
  EXPECT_NEAR(dsx[2] + dsy[1], 0.0, 1e-5);
  // The end traction integrates to P: the assembled load of a fine FEM discretization.
  const auto m = test_catalogue().methods.create("fem");
  const Discretization d = m->discretize(p->domain(), p->particles(9, 0), 1);
  const AssembledSystem sys = p->assemble(d);
  double fy = 0, fx = 0;
  for (int J = 0; J < d.particles.size(); ++J) {
    fx += sys.f[2 * J];
    fy += sys.f[2 * J + 1];
  }
  EXPECT_NEAR(fy, P, 1e-9 * P);
  EXPECT_NEAR(fx, 0.0, 1e-9 * P);
}

/// Every registered method on the elastic patch: `n`×`n` particles perturbed by `perturbation`
/// of the spacing, or nothing (and `refusal` says why) when the method does not run in 2D.
std::optional<Discretization> on_the_patch(const std::string& method, int n, double perturbation,
                                           std::string& refusal) {
  const auto p = test_catalogue().problems.create_as<BoundaryValueProblem>("elastic-patch");
  return discretize_if_supported(method, {}, p->domain(), p->particles(n, perturbation), refusal);
}

class Methods2D : public ::testing::TestWithParam<std::string> {};

TEST_P(Methods2D, GradientTableReproducesLinearFields) {
  // 001 eqs 29, 33-34: the corrected gradients (RLM, KBM) and MLS/Q4 gradients are exact for
  // linear fields on a perturbed lattice; symmetrized SPH (eq 25) and uncorrected kernel sums
  // are not: the method's declared consistency says which.
  std::string refusal;
  const auto d = on_the_patch(GetParam(), 7, 0.3, refusal);
  if (!d) GTEST_SKIP() << refusal;
  const auto p = test_catalogue().problems.create_as<BoundaryValueProblem>("elastic-patch");
  Eigen::MatrixXd ue, ge;
  p->exact_field(d->particles.x, ue, ge);
  Eigen::VectorXd u(2 * d->particles.size());
  for (int J = 0; J < d->particles.size(); ++J) u.segment<2>(2 * J) = ue.col(J);
  Eigen::MatrixXd v, g;
  d->trial_q.field(u, 2, v, g);
  p->exact_field(d->quadrature.points, ue, ge);
  const double err = (g - ge).cwiseAbs().maxCoeff();
  if (d->consistency() < 1)
    EXPECT_GT(err, 1e-2) << GetParam() << " declares no linear consistency but reproduces "
                         << "linear fields now?";
  else
    EXPECT_LT(err, 1e-10) << GetParam();
}

TEST_P(Methods2D, SymmetricExactlyWhenTheTestTableIsTheTrialTable) {
  // K = Σ_q w_q B_testᵀ D B_trial is symmetric when the force is the transpose of the gradient:
  // Bubnov–Galerkin forms (EFG, FEM) and symmetrized SPH collocation; the Petrov–Galerkin KBM
  // (Shepard tests) and RLM (corrected force sums) are not.
  std::string refusal;
  const auto d = on_the_patch(GetParam(), 6, 0.2, refusal);
  if (!d) GTEST_SKIP() << refusal;
  const auto p = test_catalogue().problems.create_as<BoundaryValueProblem>("elastic-patch");
  const Eigen::MatrixXd K(p->assemble(*d).K);
  const double asym = (K - K.transpose()).norm() / K.norm();
  const bool same_tables = d->test_q.index == d->trial_q.index && d->test_q.grad == d->trial_q.grad;
  if (same_tables)
    EXPECT_LT(asym, 1e-13) << GetParam();
  else
    EXPECT_GT(asym, 1e-6) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(All, Methods2D, ::testing::ValuesIn(registered_methods()),
                         [](const auto& info) { return test_name(info.param); });

/// What the displacement patch test shows for a discretization, from what the method is.
enum class Patch {
  exact,       ///< passes to round-off
  quadrature,  ///< linearly consistent, misses by the error of its quadrature
  fails        ///< no linear consistency
};

Patch expected_patch(const Discretization& d) {
  if (d.consistency() < 1) return Patch::fails;
  // Element shape functions (the interpolating approximations) are polynomial on Gauss cells
  // that are their own elements, so the weak form is integrated exactly.
  if (d.trial->interpolating() && d.quadrature.kind == "gauss-cells") return Patch::exact;
  return Patch::quadrature;
}

/// Relative L2 error bands measured on 7×7 particles for the methods 001 studies, checked on
/// top of the expectation every method gets from what it is.
struct MeasuredBand {
  const char* method;
  double perturbation;
  double low, high;
};
const MeasuredBand kMeasured[] = {
    {"efg-ci", 0.0, 1e-5, 2e-3}, {"efg-ci", 0.3, 1e-5, 5e-3}, {"kbm-si", 0.0, 1e-5, 5e-3},
    {"kbm-si", 0.3, 1e-4, 5e-2}, {"kbm-ni", 0.0, 1e-4, 1e-2}, {"efg-ni", 0.0, 1e-4, 1e-2},
    {"efg-ni", 0.3, 1e-3, 5e-2}, {"rlm", 0.0, 1e-2, 0.3},     {"rlm", 0.3, 1e-2, 0.3},
    {"sph", 0.0, 3e-2, 0.5},     {"sph", 0.3, 3e-2, 0.5}};

class ElasticPatch : public ::testing::TestWithParam<std::tuple<std::string, double>> {};

// Measured on 7×7 particles (uniform, and perturbed by 0.3 of the spacing). Only Q4 passes to
// round-off. The meshfree methods miss by the error of their quadrature: nodal and
// stress-point sums, and Gauss cells that do not follow the supports, do not integrate the
// test-function gradients exactly where the supports are cut by the boundary (see the
// cantilever report). SPH fails because it has no linear consistency.
TEST_P(ElasticPatch, ExpectedOutcome) {
  const auto& [method, perturbation] = GetParam();
  std::string refusal;
  const auto d = on_the_patch(method, 7, perturbation, refusal);
  if (!d) GTEST_SKIP() << refusal;
  CaseSpec spec{"elastic-patch", {}, method, {}, 7, perturbation};
  const CaseResult r = run_case(test_catalogue(), spec);
  switch (expected_patch(*d)) {
    case Patch::exact:
      EXPECT_LT(r.errors.l2_rel, 1e-12) << method;
      EXPECT_LT(r.errors.energy_rel, 1e-11) << method;
      break;
    case Patch::quadrature:
      EXPECT_GT(r.errors.l2_rel, 1e-5) << method << ": passes the patch test now?";
      EXPECT_LT(r.errors.l2_rel, 0.3) << method;
      break;
    case Patch::fails:
      EXPECT_GT(r.errors.l2_rel, 3e-2) << method << ": passes the patch test now?";
      EXPECT_LT(r.errors.l2_rel, 0.5) << method;
      break;
  }
  for (const MeasuredBand& b : kMeasured)
    if (method == b.method && perturbation == b.perturbation) {
      EXPECT_GT(r.errors.l2_rel, b.low) << method << ": passes the patch test now?";
      EXPECT_LT(r.errors.l2_rel, b.high) << method;
    }
}

INSTANTIATE_TEST_SUITE_P(
    Methods, ElasticPatch,
    ::testing::Combine(::testing::ValuesIn(registered_methods()), ::testing::Values(0.0, 0.3)),
    [](const auto& info) {
      return test_name(std::get<0>(info.param)) +
             (std::get<1>(info.param) > 0 ? "_perturbed" : "_uniform");
    });

TEST(SparseSolver, IterativeAgreesWithDirect) {
  CaseSpec spec{"cantilever", {}, "efg-ci", Params::parse("bc=penalty"), 5, 0};
  const CaseResult direct = run_case(test_catalogue(), spec);
  spec.problem_params.set("solver", "iterative");
  const CaseResult it = run_case(test_catalogue(), spec);
  EXPECT_NE(it.data<StaticSolveData>().solve.solver.find("BiCGSTAB"), std::string::npos) << it.data<StaticSolveData>().solve.solver;
  EXPECT_GT(direct.data<StaticSolveData>().solve.fill, direct.data<StaticSolveData>().solve.nonzeros / 2);
  EXPECT_GT(direct.data<StaticSolveData>().solve.rcond, 0);
  // The penalty (1e8 × the stiffness diagonal) makes the system ill-conditioned, so a residual
  // of 1e-12 leaves ~1e-4 relative differences in the solution (measured 2.6e-4).
  EXPECT_NEAR(it.errors.l2_rel, direct.errors.l2_rel, 2e-3 * direct.errors.l2_rel);
}

TEST(SparseSolver, SingularSystemsGetAClearMessage) {
  Eigen::SparseMatrix<double> A(3, 3);
  A.insert(0, 0) = 1;
  A.insert(1, 1) = 1;  // row and column 2 empty: singular
  Eigen::VectorXd b = Eigen::VectorXd::Ones(3);
  SolveInfo info;
  try {
    solve_sparse(A, b, "direct", info);
    FAIL() << "a singular matrix was solved";
  } catch (const SingularError& e) {
    EXPECT_NE(std::string(e.what()).find("singular"), std::string::npos) << e.what();
  }
  EXPECT_THROW(solve_sparse(A, b, "cholesky", info), InputError);
}

TEST(Findings, VerdictsFollowTheMeasuredRates) {
  const auto p = test_catalogue().problems.create_as<BoundaryValueProblem>("cantilever");
  auto verdict_of = [&](const std::vector<StudySummary>& s, const std::string& claim_start) {
    for (const auto& f : p->findings())
      if (f.claim.rfind(claim_start, 0) == 0) return f.check(s).status;
    return std::string("no such finding");
  };
  StudySummary kbm;
  kbm.method = "kbm-si";
  kbm.label = "kbm-si";
  kbm.resolutions = 4;
  kbm.l2_rate = 1.95;
  EXPECT_EQ(verdict_of({kbm}, "KBM with stress points"), "reproduced");
  kbm.l2_rate = 0.3;
  EXPECT_EQ(verdict_of({kbm}, "KBM with stress points"), "not reproduced");
  EXPECT_EQ(verdict_of({}, "KBM with stress points"), "not run");
}


/// The summary of a study with L2 errors `e` at spacings `h` (coarsest first), as the runner
/// makes it.
StudySummary summary(const std::string& method, const std::vector<double>& h,
                     const std::vector<double>& e, int finest_nodes = 33) {
  StudySummary s;
  s.method = method;
  s.label = "cantilever/" + method;
  s.resolutions = static_cast<int>(h.size());
  s.h = h;
  s.l2_rel = e;
  s.l2_rate = fitted_rate(h, e);
  s.l2_rel_finest = e.back();
  s.l2_trend = judge_convergence(e, h);
  s.finest_nodes = finest_nodes;
  return s;
}

const Finding& cantilever_finding(const std::vector<Finding>& all, const std::string& id) {
  for (const auto& f : all)
    if (f.id == id) return f;
  throw std::logic_error("no cantilever finding " + id);
}

// Issue 25, item 8: "SPH does not converge at all" (001 §9.1) must not pass on an SPH whose
// L2 errors converge at rate 0.9 only because they are still above 5 % (the old clause).
TEST(Findings, SphThatConvergesSlowlyDoesNotReproduceNoConvergence) {
  const auto p = test_catalogue().problems.create_as<BoundaryValueProblem>("cantilever");
  const auto all = p->findings();
  const Finding& f = cantilever_finding(all, "sph-no-convergence");
  const std::vector<double> h = {3, 1.5, 0.75, 0.375};
  // cantilever/sph as measured: 0.40, 0.38 … 0.26 would be the shape; a steady rate 0.9 at
  // errors above 5 % converges.
  EXPECT_EQ(f.check({summary("sph", h, {1.2, 0.65, 0.35, 0.19})}).status, "not reproduced");
  EXPECT_EQ(f.check({summary("sph", h, {0.5, 0.6, 0.55, 0.7})}).status, "reproduced");
}

// Issue 25, item 8: RLM and KBM ni are "poor" (001 §9.1) only beside the methods 001 calls
// good (EFG ci, EFG ni, KBM si); a KBM ni as accurate as KBM si is not poor.
TEST(Findings, PoorMeansPoorerThanEveryMethod001CallsGood) {
  const auto p = test_catalogue().problems.create_as<BoundaryValueProblem>("cantilever");
  const auto all = p->findings();
  const Finding& f = cantilever_finding(all, "rlm-kbm-ni-poor");
  const std::vector<double> h = {3, 1.5, 0.75, 0.375};
  const StudySummary ci = summary("efg-ci", h, {1.4e-3, 2.9e-4, 7.5e-5, 2.1e-5});
  const StudySummary ni = summary("efg-ni", h, {4e-2, 1.2e-2, 3.3e-3, 2.8e-3});
  const StudySummary si = summary("kbm-si", h, {2.5e-2, 3.5e-3, 8.5e-3, 9.5e-3});
  const StudySummary rlm = summary("rlm", h, {0.2, 0.3, 0.35, 0.43});
  // KBM ni as measured: 9.1e-3 at 129 × 33, below KBM si's 9.5e-3 (and a rate 0.99 < 1,
  // which the old criterion took for "poor").
  const StudySummary kbm_ni = summary("kbm-ni", h, {5e-2, 1.1e-2, 6e-3, 9.1e-3});
  EXPECT_EQ(f.check({ci, ni, si, rlm, kbm_ni}).status, "partly");
  const StudySummary kbm_ni_poor = summary("kbm-ni", h, {5e-2, 3e-2, 2e-2, 1.5e-2});
  EXPECT_EQ(f.check({ci, ni, si, rlm, kbm_ni_poor}).status, "reproduced");
  // Without a good method at the same finest resolution nothing is poorer than it.
  EXPECT_EQ(f.check({ci, ni, si, summary("rlm", h, {0.2, 0.3, 0.35, 0.43}, 17)}).status,
            "not reproduced");
  EXPECT_EQ(f.check({rlm, kbm_ni}).status, "not run");
}

/// The particles held on x = 0 for a cantilever clamp (001 §9.1 does not say how).
std::set<int> held_particles(const std::string& method, const std::string& problem_params,
                             int nodes, ParticleSet* particles = nullptr) {
  const auto p = test_catalogue().problems.create_as<BoundaryValueProblem>(
      "cantilever", Params::parse(problem_params));
  const auto m = test_catalogue().methods.create(method, Params::parse("radius=4.5"));
  const Discretization d = m->discretize(p->domain(), p->particles(nodes, 0), 1);
  const AssembledSystem a = p->assemble(d);
  if (particles) *particles = d.particles;
  return {a.constraint_particles.begin(), a.constraint_particles.end()};
}

// Issue 25, item 7: a constant support of 4.5 over a clamp of the particles on x = 0 leaves
// the particles within the support of x = 0 free; clamp=supports holds every one of them,
// clamp=timoshenko holds three components only (the rigid motion) and loads x = 0 instead.
TEST(Cantilever, ClampCoversTheSupportsOrOnlyTheRigidMotion) {
  ParticleSet X;
  // 33 × 9 particles, spacing 1.5: columns x = 0, 1.5, 3 lie within 4.5 of x = 0.
  const std::set<int> side = held_particles("sph", "", 9, &X);
  for (int I : side) EXPECT_EQ(X.x(0, I), 0.0);
  EXPECT_EQ(side.size(), 9u);
  const std::set<int> supports = held_particles("sph", "clamp=supports", 9);
  std::set<int> within;
  for (int I = 0; I < X.size(); ++I)
    if (X.x(0, I) < 4.5 - 1e-9) within.insert(I);
  EXPECT_EQ(supports, within);
  EXPECT_EQ(held_particles("efg-ci", "clamp=supports", 9), within);
  const auto p = test_catalogue().problems.create_as<BoundaryValueProblem>(
      "cantilever", Params::parse("clamp=timoshenko"));
  const auto m = test_catalogue().methods.create("efg-ci", Params::parse("radius=4.5"));
  const Discretization d = m->discretize(p->domain(), p->particles(9, 0), 1);
  const AssembledSystem a = p->assemble(d);
  EXPECT_EQ(a.constraint_values.size(), 3);
  // The end x = 0 carries the exact traction: Σ f_y over the particles balances the end load
  // P = 1000 at x = L (the shear resultant of the parabolic traction is −P on x = 0).
  double fy = 0;
  for (int I = 0; I < d.particles.size(); ++I) fy += a.f[2 * I + 1];
  EXPECT_NEAR(fy, 0.0, 1e-9 * 1000);
}

// Issue 25, item 7: with the support held at 4.5 (001 Fig. 7) EFG ci converges under
// Timoshenko's support, while the clamp of the particles on x = 0 (one multiplier per
// boundary particle under a wide support) made its error rise from h = 1.5 to h = 1.
TEST(Cantilever, EfgCiWithAConstantSupportConvergesUnderTimoshenkosSupport) {
  auto errors = [](const std::string& clamp) {
    CaseSpec s{"cantilever", Params::parse("clamp=" + clamp), "efg-ci",
               Params::parse("radius=4.5"), 5, 0};
    const StudyResult st = run_study(test_catalogue(), s, {5, 7, 9, 13});
    std::vector<double> e;
    for (const auto& r : st.cases) e.push_back(r.errors.l2_rel);
    return e;
  };
  const std::vector<double> tim = errors("timoshenko");
  for (std::size_t i = 1; i < tim.size(); ++i) EXPECT_LT(tim[i], 0.5 * tim[i - 1]) << i;
  EXPECT_LT(tim.back(), 1e-4);
  const std::vector<double> side = errors("side");
  EXPECT_GT(side[3], 10 * side[2]);  // 2.1e-3 after 4.8e-5: the set-up, not the method
}

}  // namespace
}  // namespace mfv
