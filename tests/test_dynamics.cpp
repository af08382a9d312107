/// Explicit dynamics: materials, the engine's time integrators, critical steps, energy
/// balance for every method of 001 Tables 1–2, kernel frames for every registered method, and
/// the rod-pulse problem's exact solution and Table 3 ranking.
#include <algorithm>
#include <cmath>
#include <map>

#include <gtest/gtest.h>
#include <fmt/format.h>

#include "dynamics/explicit.hpp"
#include "methods/core/errors.hpp"
#include "problems/transient_problem.hpp"
#include "test_support.hpp"
#include "verify/runner.hpp"

namespace mfv {
namespace {

std::shared_ptr<const Material> material(const std::string& name, const Params& p) {
  return test_catalogue().materials.create(name, p);
}

Params elastic(double E, double nu, const char* plane = "strain") {
  Params p;
  p.set("E", E);
  p.set("nu", nu);
  p.set("plane", plane);
  return p;
}

TEST(Materials, SvkIsHookeAtSmallStrainAndFrameInvariant) {
  const auto m = material("svk", elastic(200, 0.3));
  const double E = 200, nu = 0.3, lambda = E * nu / ((1 + nu) * (1 - 2 * nu)),
               mu = E / (2 * (1 + nu));
  Eigen::Matrix2d H;
  H << 1e-7, 3e-7, -2e-7, 4e-7;
  Eigen::Matrix2d F = Eigen::Matrix2d::Identity() + H, P;
  m->first_piola(2, 1, F.data(), P.data(), nullptr);
  const Eigen::Matrix2d eps = 0.5 * (H + H.transpose());
  const Eigen::Matrix2d hooke = lambda * eps.trace() * Eigen::Matrix2d::Identity() + 2 * mu * eps;
  EXPECT_LT((P - hooke).norm(), 1e-6 * hooke.norm());
  // P(RF) = R P(F) for a finite rotation: the stress does not see rigid rotations.
  Eigen::Matrix2d Fl;
  Fl << 1.1, 0.2, -0.05, 0.95;
  const double a = 0.7;
  Eigen::Matrix2d R;
  R << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
  Eigen::Matrix2d RF = R * Fl, P1, P2;
  m->first_piola(2, 1, Fl.data(), P1.data(), nullptr);
  m->first_piola(2, 1, RF.data(), P2.data(), nullptr);
  EXPECT_LT((P2 - R * P1).norm(), 1e-12 * P1.norm());
  // Plane stress is softer than plane strain in the lateral direction.
  EXPECT_NEAR(m->wave_speed(2, 1.0), std::sqrt(lambda + 2 * mu), 1e-12);
  EXPECT_NEAR(material("svk", elastic(200, 0.3, "stress"))->wave_speed(2, 1.0),
              std::sqrt(E / (1 - nu * nu)), 1e-9);
  EXPECT_THROW(material("svk", elastic(200, 0.5)), InputError);
}

TEST(Materials, Plastic1DYieldsAndHardensWithTheTangentModulus) {
  Params p;
  p.set("E", 100.0);
  p.set("sigma_y", 1.0);
  p.set("Ep", 25.0);
  const auto m = material("plastic-1d", p);
  std::vector<double> state(2, 0.0);
  double P = 0;
  for (double strain : {0.005, 0.01, 0.02, 0.03}) {
    const double F = 1 + strain;
    m->first_piola(1, 1, &F, &P, state.data());
  }
  // Loaded monotonically to ε = 0.03: σ = σ_y + E_p (ε − σ_y/E).
  EXPECT_NEAR(P, 1.0 + 25.0 * (0.03 - 0.01), 1e-12);
  // Unloading is elastic.
  const double F = 1.029;
  m->first_piola(1, 1, &F, &P, state.data());
  EXPECT_NEAR(P, 1.5 - 100 * 0.001, 1e-12);
  Params bad = p;
  bad.set("Ep", 150.0);
  EXPECT_THROW(material("plastic-1d", bad), InputError);
}

/// A 1D bar with a Gaussian initial velocity: (simulation, particles).
struct Bar {
  std::unique_ptr<Method> method;
  std::unique_ptr<ExplicitDynamics> sim;
  ParticleSet particles;
};

Bar make_bar(const std::string& name, int n, DynamicsOptions opt, Params mp = {}) {
  Bar b;
  b.method = test_catalogue().methods.create(name, mp);
  const Domain dom = Domain::interval(0, 60);
  b.particles = uniform_line(dom, n);
  Discretization d = b.method->discretize(dom, b.particles, 1);
  DynamicsModel model;
  model.material = material("svk", elastic(210, 0));
  model.density = 7.8e-6;
  model.mass = lumped_masses(d.particles, model.density, MassLumping::volume);
  b.sim = std::make_unique<ExplicitDynamics>(*b.method, std::move(d), std::move(model), opt);
  Eigen::MatrixXd v(1, n);
  for (int I = 0; I < n; ++I) v(0, I) = std::exp(-0.025 * std::pow(b.particles.x(0, I) - 30, 2));
  b.sim->set_particle_velocity(v);
  return b;
}

TEST(ExplicitDynamics, LumpedLinearElementsHaveTheCourantCriticalStep) {
  // Two-node elements with row-sum masses: ω_max = 2c/Δx, so Δt_crit = Δx/c exactly.
  Bar b = make_bar("fem", 61, {});
  const double c = std::sqrt(210 / 7.8e-6), dx = 1.0;
  EXPECT_NEAR(b.sim->critical_time_step() / (dx / c), 1.0, 0.01);
}

TEST(ExplicitDynamics, NewmarkWithHalfGammaIsCentralDifferences) {
  DynamicsOptions verlet, newmark;
  newmark.integrator = TimeIntegrator::newmark;
  Bar a = make_bar("efg-ni", 41, verlet), b = make_bar("efg-ni", 41, newmark);
  const double dt = 0.5 * a.sim->critical_time_step();
  for (int s = 0; s < 50; ++s) {
    a.sim->step(dt);
    b.sim->step(dt);
  }
  EXPECT_LT((a.sim->velocity() - b.sim->velocity()).norm(), 1e-12 * a.sim->velocity().norm());
  // γ > ½ is dissipative: the energy balance goes negative.
  DynamicsOptions damped = newmark;
  damped.newmark_gamma = 0.6;
  Bar c = make_bar("efg-ni", 41, damped);
  for (int s = 0; s < 200; ++s) c.sim->step(dt);
  EXPECT_LT(c.sim->energy().balance(), -1e-3 * c.sim->energy().initial);
}

TEST(ExplicitDynamics, ArtificialViscosityDissipates) {
  DynamicsOptions opt;
  opt.viscosity.alpha = 1.0;
  opt.viscosity.beta = 2.0;
  Bar plain = make_bar("sph", 61, {}), viscous = make_bar("sph", 61, opt);
  const double dt = 0.5 * plain.sim->critical_time_step();
  for (int s = 0; s < 200; ++s) {
    plain.sim->step(dt);
    viscous.sim->step(dt);
  }
  // The viscous forces are internal forces, so the balance still closes (their work is in
  // W_int); what they do is take kinetic energy out of the travelling pulse.
  EXPECT_LT(std::abs(plain.sim->energy().balance()), 1e-2 * plain.sim->energy().initial);
  EXPECT_LT(std::abs(viscous.sim->energy().balance()), 1e-2 * viscous.sim->energy().initial);
  const double peak_plain = plain.sim->velocity().cwiseAbs().maxCoeff();
  const double peak_viscous = viscous.sim->velocity().cwiseAbs().maxCoeff();
  EXPECT_LT(peak_viscous, 0.98 * peak_plain);
}

/// Every registered method on the 1D bar.
class KernelFrames : public ::testing::TestWithParam<std::string> {};

TEST_P(KernelFrames, EulerianAndLagrangianAgreeAtSmallStrain) {
  // v ≈ 1 m/s against c ≈ 5189 m/s: strains of 2e-4, so the kernels' configurations differ
  // by that much and the two frames must agree to about that relative level.
  const std::string& name = GetParam();
  const Domain dom = Domain::interval(0, 60);
  std::string refusal;
  if (!discretize_if_supported(name, {}, dom, uniform_line(dom, 61), refusal))
    GTEST_SKIP() << refusal;
  DynamicsOptions eul;
  eul.frame = KernelFrame::eulerian;
  eul.update_every = 5;
  Bar a = make_bar(name, 61, {}), b = make_bar(name, 61, eul);
  const double dt = 0.5 * a.sim->critical_time_step();
  for (int s = 0; s < 100; ++s) {
    a.sim->step(dt);
    b.sim->step(dt);
  }
  const double diff = (a.sim->particle_velocity() - b.sim->particle_velocity()).norm() /
                      a.sim->particle_velocity().norm();
  EXPECT_LT(diff, 2e-3) << name;
  EXPECT_GT(b.sim->counters().retabulations, 10) << name;
}

INSTANTIATE_TEST_SUITE_P(EveryMethod, KernelFrames, ::testing::ValuesIn(registered_methods()),
                         [](const auto& info) { return test_name(info.param); });

/// The Eulerian recomputation with neighbour lists (a skin) on 2 threads against the plain
/// one (skin 0: a fresh search every time) on 1 thread, on the 2D rod with a pulse fast enough
/// (100 mm/ms, 2 % strain) that the lists are searched again during the run: the histories
/// must be equal bit for bit, the searches fewer. The pre-change engine gave the same
/// histories bit for bit (checked once against main's build when this landed).
class EulerianLists : public ::testing::TestWithParam<std::string> {};

TEST_P(EulerianLists, GiveTheHistoryOfAFreshSearchBitForBit) {
  const std::string& name = GetParam();
  const Domain rod = Domain::rectangle(0, 0, 60, 5);
  // 241 × 21 (Δx = 0.25): 5,061 particles, more than kParallelMinimum, so on 2 threads every
  // table builder and the force tables run in parallel.
  const ParticleSet p = rectangle_lattice(rod, 241, 21, Placement::boundary);
  auto run = [&](double skin, int threads) {
    auto m = test_catalogue().methods.create(name);
    DynamicsOptions opt;
    opt.frame = KernelFrame::eulerian;
    opt.neighbour_skin = skin;
    opt.threads = threads;
    DynamicsModel model;
    model.material = material("svk", elastic(210, 0));
    model.density = 7.8e-6;
    model.mass = lumped_masses(p, model.density, MassLumping::volume);
    auto sim = std::make_unique<ExplicitDynamics>(*m, m->discretize(rod, p, 1), model, opt);
    Eigen::MatrixXd v = Eigen::MatrixXd::Zero(2, p.size());
    for (int I = 0; I < p.size(); ++I) v(0, I) = 100 * std::exp(-0.025 * std::pow(p.x(0, I) - 30, 2));
    sim->set_particle_velocity(v);
    const double dt = 0.3 * p.spacing / std::sqrt(210 / 7.8e-6);  // 0.3 Δx/c
    for (int s = 0; s < 12; ++s) sim->step(dt);
    return std::pair{std::move(m), std::move(sim)};
  };
  const auto [ma, plain] = run(0, 1);
  const auto [mb, lists] = run(0.03, 2);  // ~0.006 Δx per step: a search every few steps
  EXPECT_EQ(plain->displacement(), lists->displacement()) << name;
  EXPECT_EQ(plain->velocity(), lists->velocity()) << name;
  EXPECT_EQ(plain->discretization().trial_q.grad, lists->discretization().trial_q.grad) << name;
  EXPECT_EQ(plain->discretization().test_q.grad, lists->discretization().test_q.grad) << name;
  EXPECT_EQ(plain->counters().neighbour_rebuilds, plain->counters().retabulations) << name;
  EXPECT_GT(lists->counters().neighbour_rebuilds, 1) << name;
  EXPECT_LT(lists->counters().neighbour_rebuilds, plain->counters().retabulations / 2) << name;
}

INSTANTIATE_TEST_SUITE_P(ParticleMethods2D, EulerianLists,
                         ::testing::Values("sph", "rlm", "kbm-ni", "kbm-si", "efg-ni", "efg-ci"),
                         [](const auto& info) { return test_name(info.param); });

TEST(ExplicitDynamics, RefusesBadInput) {
  EXPECT_THROW(kernel_frame_from("lagrange"), InputError);
  EXPECT_THROW(time_integrator_from("rk4"), InputError);
  auto m = test_catalogue().methods.create("sph");
  const Domain dom = Domain::interval(0, 1);
  Discretization d = m->discretize(dom, uniform_line(dom, 11), 1);
  DynamicsModel model;
  model.material = material("svk", elastic(1, 0));
  model.mass = Eigen::VectorXd::Ones(5);  // wrong size
  EXPECT_THROW(ExplicitDynamics(*m, d, model, {}), InputError);
  model.mass = Eigen::VectorXd::Ones(11);
  DynamicsOptions opt;
  opt.newmark_gamma = 0.4;
  EXPECT_THROW(ExplicitDynamics(*m, d, model, opt), InputError);
  for (double skin : {-0.1, std::nan(""), 11.0, HUGE_VAL}) {
    DynamicsOptions bad;
    bad.neighbour_skin = skin;
    EXPECT_THROW(ExplicitDynamics(*m, d, model, bad), InputError) << skin;
  }
  ExplicitDynamics ok(*m, d, model, {});
  EXPECT_THROW(ok.step(-1.0), InputError);
  EXPECT_THROW(ok.set_particle_velocity(Eigen::MatrixXd::Zero(2, 11)), InputError);
}

/// Every method of 001 Tables 1–2 conserves energy on the 2D rod with a stable step.
class RodEnergy : public ::testing::TestWithParam<std::string> {};

TEST_P(RodEnergy, ConservesEnergyAndPropagatesThePulse) {
  CaseSpec s;
  s.problem = "rod-pulse";
  s.method = GetParam();
  s.nodes = 61;
  s.problem_params = Params::parse("frames=0,samples=20");
  const CaseResult r = run_case(test_catalogue(), s);
  EXPECT_GT(r.data<TransientData>().steps, 20);
  // Central differences at 0.8 of the critical step: the energy balance fluctuates by about
  // 1% on this coarse lattice (0.01% at 481 × 41) and must not drift beyond that.
  EXPECT_LT(r.headline.at("energy drift"), 2e-2) << r.data<TransientData>().dynamics;
  // The pulse comes back to its place: a bounded error (SPH's is large on 6 layers, 001).
  EXPECT_LT(r.headline.at("velocity error at L/c"), GetParam() == "sph" ? 0.9 : 0.1);
  EXPECT_GT(r.data<TransientData>().dt_critical, 0.9 * r.h / std::sqrt(210 / 7.8e-6));
}

INSTANTIATE_TEST_SUITE_P(Table1, RodEnergy,
                         ::testing::Values("sph", "rlm", "kbm-ni", "kbm-si", "efg-ni", "efg-ci",
                                           "fem"));

TEST(RodPulse, ExactSolutionReflectsAtFreeEnds) {
  // Through the runner's public face: the Gaussian comes back at L/c, so the exact velocity
  // error there is the method's alone; here we check the loading's consistency instead.
  CaseSpec s;
  s.problem = "rod-pulse";
  s.method = "efg-ni";
  s.nodes = 121;
  s.problem_params = Params::parse("frames=2,samples=50");
  const CaseResult g = run_case(test_catalogue(), s);
  // Mid-rod probe at t = 0 and t = L/c: the exact values are 1 (the pulse's centre).
  const auto& h = g.data<TransientData>().history;
  const auto& cols = g.data<TransientData>().history_columns;
  const int exact_mid = static_cast<int>(std::find(cols.begin(), cols.end(), "exact v middle") -
                                         cols.begin());
  ASSERT_LT(exact_mid, static_cast<int>(cols.size()));
  EXPECT_NEAR(h.front()[exact_mid], 1.0, 1e-12);
  EXPECT_LT(g.headline.at("velocity error at L/c"), 0.02);
  EXPECT_LT(g.headline.at("velocity error at 2L/c"), 0.05);
  // The impulse: the left end moves at 50 m/s while driven; the pulse is 30 mm long.
  s.problem_params = Params::parse("loading=impulse,frames=0,samples=50");
  const CaseResult im = run_case(test_catalogue(), s);
  const int v_left = static_cast<int>(std::find(cols.begin(), cols.end(), "exact v left end") -
                                      cols.begin());
  EXPECT_NEAR(im.data<TransientData>().history[1][v_left], 50.0, 1e-12);
  EXPECT_LT(im.headline.at("energy drift"), 2e-2);
  EXPECT_LT(im.headline.at("velocity error at L/c"), 0.5);
  // Uniform masses put too much inertia on the free edges: reflections get worse.
  s.problem_params = Params::parse("mass=uniform,frames=0,samples=20");
  const CaseResult uni = run_case(test_catalogue(), s);
  EXPECT_GT(uni.headline.at("velocity error at 2L/c"), g.headline.at("velocity error at 2L/c"));
  s.problem_params = Params::parse("loading=step");
  EXPECT_THROW(run_case(test_catalogue(), s), InputError);
  s.problem_params = {};
  s.nodes = 100;
  EXPECT_THROW(run_case(test_catalogue(), s), InputError);
}

TEST(RodPulse, SphIsWorstAndEfgCellIntegrationBetterAsInTable3) {
  // 121 × 11 particles; the full ranking at 481 × 41 is in the nightly suite's findings.
  std::map<std::string, double> e;
  for (const std::string m : {"sph", "efg-ni", "efg-ci"}) {
    CaseSpec s;
    s.problem = "rod-pulse";
    s.method = m;
    s.nodes = 121;
    s.problem_params = Params::parse("frames=0,samples=10,transits=1");
    e[m] = run_case(test_catalogue(), s).headline.at("velocity error at L/c");
  }
  EXPECT_GT(e["sph"], 10 * e["efg-ni"]);
  EXPECT_LT(e["efg-ci"], e["efg-ni"]);
}

// Issue 12: efg-ci at 1.5 times its critical step used to reach a kinetic energy of 7.8e197
// and then inf with its errors left at 0. Now the run stops at the blow-up bound, says where,
// and its errors and rates are "not reached" (NaN), never a number.
TEST(RodPulse, BlownUpRunStopsAsUnstableWithNoErrors) {
  CaseSpec s;
  s.problem = "rod-pulse";
  s.method = "efg-ci";
  s.problem_params = Params::parse("safety=1.5,frames=0,samples=20,threads=1");
  const StudyResult st = run_study(test_catalogue(), s, {61, 121});
  for (const CaseResult& r : st.cases) {
    const TransientData& t = r.data<TransientData>();
    ASSERT_TRUE(t.instability.has_value()) << r.spec.nodes;
    EXPECT_TRUE(t.stopped_early);
    EXPECT_EQ(t.instability->step, t.steps);
    EXPECT_GT(t.instability->step, 0);
    EXPECT_NEAR(t.instability->time, t.steps * t.dt, 1e-12 * t.end_time);
    EXPECT_LT(t.instability->time, t.end_time / 2);  // before the first checkpoint L/c
    EXPECT_EQ(t.verdict().rfind(fmt::format("unstable at step {}, t = ", t.steps), 0), 0u)
        << t.verdict();
    EXPECT_TRUE(std::isnan(r.errors.l2));
    EXPECT_TRUE(std::isnan(r.errors.l2_rel));
    EXPECT_TRUE(std::isnan(r.headline.at("velocity error at L/c")));
    EXPECT_TRUE(std::isnan(r.headline.at("velocity error at 2L/c")));
    // Every history row that was recorded is finite: the stop came before the overflow.
    for (const auto& row : t.history)
      for (double v : row) EXPECT_TRUE(std::isfinite(v));
  }
  EXPECT_TRUE(std::isnan(st.rates.rate("L2")));
  EXPECT_TRUE(std::isnan(st.rates.rate("H1-semi")));
  for (double p : st.rates.pairwise_of("L2")) EXPECT_TRUE(std::isnan(p));
}

// A stable run measures the velocity error only: no H1 error is shown as 0.
TEST(RodPulse, StableRunHasNoInstabilityAndNoH1Error) {
  CaseSpec s;
  s.problem = "rod-pulse";
  s.method = "efg-ni";
  s.nodes = 61;
  s.problem_params = Params::parse("frames=0,samples=20,transits=1");
  const CaseResult r = run_case(test_catalogue(), s);
  EXPECT_FALSE(r.data<TransientData>().instability.has_value());
  EXPECT_FALSE(r.data<TransientData>().stopped_early);
  EXPECT_EQ(r.data<TransientData>().verdict(), "");
  EXPECT_TRUE(std::isfinite(r.errors.l2_rel));
  EXPECT_EQ(r.errors.l2_rel, r.headline.at("velocity error at L/c"));
  EXPECT_TRUE(std::isnan(r.errors.h1_semi_rel));
  EXPECT_TRUE(std::isnan(r.errors.energy_rel));
  EXPECT_NE(r.data<TransientData>().main_error.find("velocity"), std::string::npos);
  EXPECT_GT(r.data<TransientData>().max_displacement, 0.0);
}


// Issue 25, item 5: Table 3 states its particle counts per method; each is compared at its
// own (the lattice nodes × ((nodes − 1)/12 + 1)), and its 2004 CPU minutes are no longer
// compared as absolute values.
TEST(RodPulse, Table3IsComparedAtItsOwnParticleCounts) {
  const auto p = test_catalogue().problems.create_as<TransientProblem>("rod-pulse");
  std::map<std::string, int> nodes;
  for (const PublishedValue& v : p->published()) {
    EXPECT_NE(v.quantity, "CPU minutes");
    nodes[v.method] = v.nodes;
  }
  EXPECT_EQ(nodes["sph"], 481);
  EXPECT_EQ(nodes["rlm"], 481);
  EXPECT_EQ(nodes["efg-ni"], 481);
  EXPECT_EQ(nodes["kbm-si"], 349);
  EXPECT_EQ(nodes["efg-ci"], 217);
  // 481 × 41 = 19,721 (001 §9.2); KBM si 10,470 particles and 348 × 29 stress points
  // (Table 3: 10,500 and 10,200); EFG ci 4,123 particles (4,100) on 216 × 18 cells.
  auto rule = [&](const std::string& method, const std::string& params, int n) {
    const auto m = test_catalogue().methods.create(method, Params::parse(params));
    return m->discretize(p->domain(), p->particles(n, 0), 1);
  };
  EXPECT_EQ(p->particles(481, 0).size(), 19721);
  const Discretization kbm = rule("kbm-si", "", 349);
  EXPECT_EQ(kbm.particles.size(), 10470);
  EXPECT_EQ(kbm.quadrature.size() - kbm.quadrature.nodal_points, 348 * 29);
  const Discretization ci = rule("efg-ci", "", 217);
  EXPECT_EQ(ci.particles.size(), 4123);
  EXPECT_EQ(ci.quadrature.cells, 216 * 18);
  // Table 3's 15,700 "cells": 15,552 as 2 × 2 Gauss points on each lattice cell, or as a
  // background grid of 432 × 36 cells.
  EXPECT_EQ(rule("efg-ci", "quad=2", 217).quadrature.size(), 15552);
  EXPECT_EQ(rule("efg-ci", "cells=432", 217).quadrature.cells, 15552);
}

/// A Gaussian study of `method` with `key` = `value` at the lattice of `nodes` (and 121).
StudySummary rod_study(const std::string& method, int nodes, const std::string& key,
                       double value) {
  StudySummary s;
  s.method = method;
  s.label = "rod-pulse/" + method;
  s.problem_resolved = Params::parse("loading=gaussian,mass=volume,frame=lagrangian");
  s.h = {60.0 / 120, 60.0 / (nodes - 1)};
  s.headlines = {{{key, 99.0}}, {{key, value}}};
  s.resolutions = 2;
  return s;
}

// Issue 25, item 6: the CPU minutes compare as ratios to SPH's, each method at its Table 3
// count, within a factor 1.5 of 001's (RLM 1.26, KBM si 1.35, EFG ni 1.23, EFG ci 3.24).
TEST(RodPulse, CpuMinutesCompareAsRatiosToSph) {
  const auto p = test_catalogue().problems.create("rod-pulse");
  const auto all = p->findings();
  const auto f = std::find_if(all.begin(), all.end(),
                              [](const Finding& x) { return x.id == "cpu-ratios"; });
  ASSERT_NE(f, all.end());
  auto studies = [](double efg_ci) {
    return std::vector<StudySummary>{
        rod_study("sph", 481, "CPU minutes", 1.0), rod_study("rlm", 481, "CPU minutes", 1.3),
        rod_study("kbm-si", 349, "CPU minutes", 1.3), rod_study("efg-ni", 481, "CPU minutes", 1.2),
        rod_study("efg-ci", 217, "CPU minutes", efg_ci)};
  };
  EXPECT_EQ(f->check(studies(3.0)).status, "reproduced");
  EXPECT_EQ(f->check(studies(1.2)).status, "partly");  // 1.2 against 3.24: beyond 1.5×
  // Read at 481 for EFG ci the ratio is not Table 3's: no study at 217, so it is left out.
  auto at481 = studies(3.0);
  at481[4] = rod_study("efg-ci", 481, "CPU minutes", 1.2);
  EXPECT_EQ(f->check(at481).status, "reproduced");
  EXPECT_EQ(f->check(at481).ours.find("efg-ci"), std::string::npos);
  EXPECT_EQ(f->check({rod_study("rlm", 481, "CPU minutes", 1.3)}).status, "not run");
}

// Issue 25, item 5: the ranking reads each method at its Table 3 count.
TEST(RodPulse, RankingReadsEachMethodAtItsTable3Count) {
  const auto p = test_catalogue().problems.create("rod-pulse");
  const auto all = p->findings();
  const auto f = std::find_if(all.begin(), all.end(),
                              [](const Finding& x) { return x.id == "ranking"; });
  ASSERT_NE(f, all.end());
  const std::string e = "velocity error at L/c";
  std::vector<StudySummary> s = {rod_study("sph", 481, e, 0.05), rod_study("rlm", 481, e, 0.013),
                                 rod_study("kbm-si", 349, e, 0.008),
                                 rod_study("efg-ni", 481, e, 0.0083),
                                 rod_study("efg-ci", 217, e, 0.0068)};
  EXPECT_EQ(f->check(s).status, "reproduced");
  // The same five with KBM si read at 481 (not Table 3's count): not run.
  s[2] = rod_study("kbm-si", 481, e, 0.008);
  EXPECT_EQ(f->check(s).status, "not run");
}

// Issue 25, item 5: eq 75 names no norm; the readings it allows come from the same run.
TEST(RodPulse, VelocityErrorInEachNormOfEq75) {
  CaseSpec s;
  s.problem = "rod-pulse";
  s.method = "efg-ni";
  s.nodes = 61;
  s.problem_params = Params::parse("frames=0,samples=10,transits=1");
  const CaseResult r = run_case(test_catalogue(), s);
  const double volume = r.headline.at("velocity error at L/c");
  const double axial = r.headline.at("velocity error at L/c (axial)");
  const double sum = r.headline.at("velocity error at L/c (particle sum)");
  const double line = r.headline.at("velocity error at L/c (centre line)");
  EXPECT_LE(axial, volume);  // the lateral velocity left out
  for (double v : {axial, sum, line}) {
    EXPECT_GT(v, 0.3 * volume);
    EXPECT_LT(v, 3 * volume);
  }
}

}  // namespace
}  // namespace mfv
