/// The 1D transient problems: the prestressed rod's stability verdicts (000 §5.1) and the
/// Gaussian reproducing kernel bar (004 III §6). Each verdict is asserted as we measure it;
/// where that differs from the paper the comment says so (the findings say "not reproduced").
#include <gtest/gtest.h>

#include <cmath>

#include <fmt/format.h>

#include "methods/core/errors.hpp"
#include "problems/problem.hpp"
#include "test_support.hpp"
#include "verify/runner.hpp"

namespace mfv {
namespace {

CaseResult rod(const std::string& method, double dmax, const std::string& frame, double sigma,
               int nodes = 41) {
  CaseSpec c;
  c.problem = "prestressed-rod";
  c.method = method;
  c.method_params = Params::parse(fmt::format("kernel=quartic-spline,dmax={}", dmax));
  c.problem_params =
      Params::parse(fmt::format("frame={},sigma={},frames=0,threads=1", frame, sigma));
  c.nodes = nodes;
  return run_case(test_catalogue(), c);
}

double peak(const CaseResult& r) { return r.headline.at("peak velocity / v0"); }
bool unstable(const CaseResult& r) { return r.headline.at("unstable") > 0.5; }

// 000 §5.1, Fig. 13: Eulerian kernel, nodal integration, D_mx = 1.5, σ̄ = 0.1 is unstable
// ("velocity ten times larger"); ours grows past 100 v0 within a transit.
TEST(PrestressedRod, EulerianNodalUnstableAtDmx15) {
  const CaseResult r = rod("kbm-ni", 1.5, "eulerian", 0.1);
  EXPECT_TRUE(unstable(r));
  EXPECT_GT(peak(r), 10.0);
  EXPECT_LT(r.headline.at("onset (transits l/c)"), 1.0);
}

// The Lagrangian kernel with the same integration is stable: the peak nodal velocity stays
// below v0 (the energy bound) over five transits.
TEST(PrestressedRod, LagrangianNodalStableAtDmx15) {
  const CaseResult r = rod("kbm-ni", 1.5, "lagrangian", 0.1);
  EXPECT_FALSE(unstable(r));
  EXPECT_LT(peak(r), 1.0);
  EXPECT_NEAR(r.headline.at("stopped at t"), 5 * 0.04 / std::sqrt(10e9 / 2450), 1e-9);
}

// 000 says D_mx = 2.5 (Eulerian, nodal) is stable at σ̄ = 0.1 and unstable at σ̄ = 0.16.
// NOT REPRODUCED at σ̄ = 0.1: we measure the instability at both stresses, with onsets of about
// half a transit (0.49 and 0.38 l/c), so σ̄ = 0.16 is merely faster. The von Neumann relation
// (000 eq 3.18) agrees with us: at κ = π/Δx the first term vanishes and ω² = −(σ/ρ) Σ_j
// w''(jΔx)(1 − cos jπ) < 0 for any tension, because w''(Δx) > 0 for both supports.
TEST(PrestressedRod, EulerianNodalDmx25UnstableAtBothStresses) {
  const CaseResult a = rod("kbm-ni", 2.5, "eulerian", 0.1);
  const CaseResult b = rod("kbm-ni", 2.5, "eulerian", 0.16);
  EXPECT_TRUE(unstable(a));  // the paper: stable
  EXPECT_TRUE(unstable(b));  // the paper: unstable
  EXPECT_LT(b.headline.at("onset (transits l/c)"), a.headline.at("onset (transits l/c)"));
}

// Stress points with the Lagrangian kernel: stable over σ̄ ∈ [0, 1] (as 000 says).
TEST(PrestressedRod, LagrangianStressPointsStableOverSigma) {
  for (double s : {0.0, 0.1, 0.5, 1.0}) {
    const CaseResult r = rod("kbm-si", 1.5, "lagrangian", s);
    EXPECT_FALSE(unstable(r)) << "sigma " << s;
    EXPECT_LT(peak(r), 1.0) << "sigma " << s;
  }
}

// Stress points with the Eulerian kernel, D_mx = 1.5: 000 says stable for σ̄ ∈ [0, 1], and
// with the particles and the midpoints both integrated (000 eq 3.19) they are. With D_mx = 2.5
// the stress-point term vanishes near the cut-off and the tension wins (the dispersion
// analysis puts the onset at 0.91π/Δx for σ̄ = 0.1).
TEST(PrestressedRod, EulerianStressPoints) {
  for (double s : {0.0, 0.1, 0.5, 1.0})
    EXPECT_FALSE(unstable(rod("kbm-si", 1.5, "eulerian", s))) << "sigma " << s;
  for (double s : {0.1, 1.0})
    EXPECT_TRUE(unstable(rod("kbm-si", 2.5, "eulerian", s))) << "sigma " << s;
}

// σ̄ sweep, nodal integration, D_mx = 1.5: the Lagrangian kernel is stable at every tension
// (000 §3.1.1: only C̄ <= 0 is unstable); the Eulerian one is stable without prestress and
// unstable from σ̄ = 0.05 on, the onset coming earlier as the tension grows.
TEST(PrestressedRod, SigmaSweep) {
  double last_onset = 1e9;
  for (double s : {0.0, 0.05, 0.1, 0.3, 1.0}) {
    const CaseResult lag = rod("kbm-ni", 1.5, "lagrangian", s);
    EXPECT_FALSE(unstable(lag)) << "sigma " << s;
    const CaseResult eul = rod("kbm-ni", 1.5, "eulerian", s);
    if (s == 0) {
      EXPECT_FALSE(unstable(eul));
      continue;
    }
    EXPECT_TRUE(unstable(eul)) << "sigma " << s;
    const double onset = eul.headline.at("onset (transits l/c)");
    EXPECT_LT(onset, last_onset) << "sigma " << s;
    last_onset = onset;
  }
}

// The findings read the verdicts from the studies' headlines.
TEST(PrestressedRod, FindingsReadTheVerdicts) {
  const auto problem = test_catalogue().problems.create("prestressed-rod", {});
  auto summary = [](const std::string& method, double dmax, const std::string& frame,
                    double sigma) {
    StudySummary s;
    s.method = method;
    s.label = method;
    s.params = Params::parse(fmt::format("kernel=quartic-spline,dmax={}", dmax));
    s.problem_params = Params::parse(fmt::format("frame={},sigma={}", frame, sigma));
    s.resolved = test_catalogue().methods.resolve(method, s.params);
    s.problem_resolved = resolved_case_params(test_catalogue(), "prestressed-rod", s.problem_params);
    s.headlines.push_back(rod(method, dmax, frame, sigma).headline);
    s.resolutions = 1;
    return s;
  };
  const std::vector<StudySummary> all{
      summary("kbm-ni", 1.5, "eulerian", 0.1), summary("kbm-ni", 1.5, "lagrangian", 0.1),
      summary("kbm-ni", 2.5, "eulerian", 0.1), summary("kbm-ni", 2.5, "eulerian", 0.16),
      summary("kbm-si", 1.5, "lagrangian", 0.5)};
  const auto findings = problem->findings();
  ASSERT_EQ(findings.size(), 5u);
  EXPECT_EQ(findings[0].check(all).status, "reproduced");
  EXPECT_EQ(findings[1].check(all).status, "reproduced");
  EXPECT_EQ(findings[2].check(all).status, "not reproduced");
  EXPECT_EQ(findings[3].check(all).status, "reproduced");
  EXPECT_EQ(findings[4].check(all).status, "reproduced");  // only the Lagrangian si study given
  EXPECT_EQ(findings[4].check({}).status, "not run");
}

CaseResult bar(const std::string& method, const std::string& mparams, const std::string& pparams) {
  CaseSpec c;
  c.problem = "grk-bar";
  c.method = method;
  c.method_params = Params::parse(mparams);
  c.problem_params = Params::parse(pparams + (pparams.empty() ? "" : ",") + "frames=0,threads=1");
  c.nodes = 21;
  return run_case(test_catalogue(), c);
}

std::string grk(int j) { return fmt::format("kernel=gaussian,rule=eq6.10,j={}", j); }

// The exact solution: the FEM with lumped mass at its critical step l/c is exact for a step
// load at the nodes (the displacement error is round-off-small; v and σ carry the fronts).
TEST(GrkBar, FemAtItsCriticalStepMatchesTheExactSolution) {
  const CaseResult r = bar("fem", "", "");
  EXPECT_LT(r.headline.at("error u at 1.5 L/c"), 1e-3);
  EXPECT_LT(r.headline.at("error u at 2.5 L/c"), 2e-3);
  EXPECT_LT(r.headline.at("error stress at 2.5 L/c"), 0.03);
  EXPECT_NEAR(r.headline.at("critical dt / FEM dt"), 1.0, 0.01);
}

// GRK j = 0 at the FEM step: small displacement error (004: "coincided accurately").
TEST(GrkBar, ElasticGrkAtFemStep) {
  const CaseResult r = bar("rkpm", grk(0), "courant=1");
  EXPECT_EQ(r.headline.at("unstable"), 0.0);
  EXPECT_LT(r.headline.at("error u at 1.5 L/c"), 0.02);
  EXPECT_LT(r.headline.at("error u at 2.5 L/c"), 0.02);
  EXPECT_LT(r.headline.at("error stress at 2.5 L/c"), 0.2);
  EXPECT_LT(r.headline.at("energy drift"), 0.02);
}

// Critical steps (power iteration) beside 004's 'numeric' column: j = −1: 2.432e-5,
// j = 0: 3.223e-5, j = 1: 5.651e-5. Ours: 2.44e-5, 3.15e-5, 5.26e-5 (within 1%, 2%, 7%).
TEST(GrkBar, CriticalStepsNearThePaper) {
  const double paper[] = {2.432e-5, 3.223e-5, 5.651e-5};
  const double tolerance[] = {0.02, 0.04, 0.1};
  for (int j = -1; j <= 1; ++j) {
    const CaseResult r = bar("rkpm", grk(j), "courant=0.9");
    EXPECT_NEAR(r.headline.at("critical dt") / paper[j + 1], 1.0, tolerance[j + 1]) << "j " << j;
  }
}

// 1.35 × the FEM step: 004 ran j = 0 there (Fig. 14). NOT REPRODUCED for j = 0: our critical
// step is 1.28 × FEM (the paper's own 'numeric' value, 3.223e-5 s, is 1.31 × FEM, also below
// 1.35), and the run blows up within a few dozen steps. j = 1 (critical 2.1 × FEM) is stable
// there; j = −1 is unstable even at the FEM step (critical 0.99 × FEM, as the paper's table).
TEST(GrkBar, StabilityAboveTheFemStep) {
  EXPECT_EQ(bar("rkpm", grk(0), "courant=1.35").headline.at("unstable"), 1.0);  // paper: ran
  EXPECT_EQ(bar("rkpm", grk(1), "courant=1.35").headline.at("unstable"), 0.0);
  EXPECT_EQ(bar("rkpm", grk(-1), "courant=1").headline.at("unstable"), 1.0);
  EXPECT_EQ(bar("rkpm", grk(-1), "courant=0.9").headline.at("unstable"), 0.0);
}

// Elastic–plastic: with F0 = 5000 lb the bar never yields (2F0/A = σ_y/3); with F0 = 20,000 lb
// it does, and the stress never leaves the hardening curve σ_y + H α.
TEST(GrkBar, PlasticStressStaysOnTheHardeningCurve) {
  const CaseResult low = bar("rkpm", grk(0), "material=plastic");
  EXPECT_LT(low.headline.at("max stress / flow stress"), 0.5);
  const CaseResult high = bar("rkpm", grk(0), "material=plastic,F0=20000");
  EXPECT_LE(high.headline.at("max stress / flow stress"), 1.0 + 1e-9);
  EXPECT_GT(high.headline.at("max stress / flow stress"), 0.999);  // it did yield
  EXPECT_EQ(high.headline.at("unstable"), 0.0);
}

// Issue 12: the unstable rod is marked where the peak first passed 2 v0, stops early, and its
// peak is then a lower bound; the stable one runs to the end. Neither measures an error.
TEST(PrestressedRod, InstabilityIsRecordedWithItsStepAndTheRunStopsEarly) {
  const CaseResult eul = rod("kbm-ni", 1.5, "eulerian", 0.1);
  ASSERT_TRUE(eul.data<TransientData>().instability.has_value());
  EXPECT_NE(eul.data<TransientData>().instability->reason.find("above 2 v0"), std::string::npos);
  EXPECT_GT(eul.data<TransientData>().instability->step, 0);
  EXPECT_LE(eul.data<TransientData>().instability->step, eul.data<TransientData>().steps);
  EXPECT_TRUE(eul.data<TransientData>().stopped_early);
  EXPECT_EQ(eul.headline.at("run stopped early"), 1.0);
  EXPECT_NEAR(eul.headline.at("onset (transits l/c)") * 0.04 / std::sqrt(1e10 / 2450),
              eul.data<TransientData>().instability->time, 1e-15);
  EXPECT_TRUE(std::isnan(eul.errors.l2));

  const CaseResult lag = rod("kbm-ni", 1.5, "lagrangian", 0.1);
  EXPECT_FALSE(lag.data<TransientData>().instability.has_value());
  EXPECT_FALSE(lag.data<TransientData>().stopped_early);
  EXPECT_EQ(lag.headline.at("run stopped early"), 0.0);
  EXPECT_TRUE(std::isnan(lag.errors.l2));
  EXPECT_TRUE(lag.data<TransientData>().main_error.empty());
}

// The verdicts compare velocities with v0 and v*: a zero or negative kick or load would make
// every step "unstable", so they are refused.
TEST(TransientVerdicts, RefuseAReferenceVelocityThatIsNotPositive) {
  CaseSpec c;
  c.problem = "prestressed-rod";
  c.method = "kbm-ni";
  c.nodes = 41;
  for (const char* v0 : {"v0=0", "v0=-40"}) {
    c.problem_params = Params::parse(v0);
    EXPECT_THROW(run_case(test_catalogue(), c), InputError) << v0;
  }
  c.problem = "grk-bar";
  c.method = "fem";
  c.nodes = 21;
  for (const char* f0 : {"F0=0", "F0=-5000"}) {
    c.problem_params = Params::parse(f0);
    EXPECT_THROW(run_case(test_catalogue(), c), InputError) << f0;
  }
}

// The GRK bar above its critical step blows up before its checkpoints: their errors are
// "not reached", not 0.
TEST(GrkBar, UnstableRunLeavesItsCheckpointsNotReached) {
  const CaseResult r = bar("rkpm", grk(0), "courant=1.35");
  ASSERT_TRUE(r.data<TransientData>().instability.has_value());
  EXPECT_NE(r.data<TransientData>().instability->reason.find("v*"), std::string::npos);
  EXPECT_TRUE(r.data<TransientData>().stopped_early);
  for (const char* k : {"error u at 1.5 L/c", "error u at 2.5 L/c", "error stress at 2.5 L/c",
                        "error v at 2.5 L/c"})
    EXPECT_TRUE(std::isnan(r.headline.at(k))) << k;
  EXPECT_TRUE(std::isnan(r.errors.l2_rel));
  EXPECT_TRUE(std::isfinite(r.headline.at("peak velocity / v*")));
  const CaseResult ok = bar("rkpm", grk(0), "courant=1");
  EXPECT_FALSE(ok.data<TransientData>().instability.has_value());
  EXPECT_TRUE(std::isfinite(ok.errors.l2_rel));
}

}  // namespace
}  // namespace mfv
