// The rings of 000 §5.2–5.3 and 001 §9.5–9.6: the follower pressure of the explicit engine,
// and the rubber-ring and steel-ring problems run by name with every method that discretizes
// an annulus (the others refuse with an InputError that names the reason).
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "analyses/case.hpp"
#include "dynamics/explicit.hpp"
#include "dynamics/thick_cylinder.hpp"
#include "test_support.hpp"
#include "verify/runner.hpp"

namespace mfv {
namespace {

constexpr double kPi = std::numbers::pi;

/// The force of a follower pressure on a ring's inner surface read from the first step from
/// rest: u = ½ dt² a₀ with no internal force at u = 0, so f_ext = m a₀ = 2 m u / dt².
Eigen::MatrixXd follower_force(const std::string& method, double p, int nr, int nt) {
  AnnulusLattice spec{0.5, 1.0, nr, nt};
  ParticleSet ps = annulus_lattice(spec);
  const Domain box = Domain::rectangle(-1, -1, 1, 1);
  const auto m = test_catalogue().methods.create(method, Params{});
  Discretization d = m->discretize(box, ps, 1);
  DynamicsModel model;
  Params mp;
  mp.set("E", 1.0);
  mp.set("nu", 0.25);
  model.material = test_catalogue().materials.create("svk", mp);
  model.density = 1;
  model.mass = lumped_masses(d.particles, 1, MassLumping::volume);
  std::vector<int> loop(nt);
  for (int j = 0; j < nt; ++j) loop[j] = j;
  model.follower_pressures = {{loop, [p](double) { return p; }}};
  const Eigen::VectorXd mass = model.mass;
  ExplicitDynamics sim(*m, std::move(d), std::move(model), DynamicsOptions{});
  const double dt = 1e-6;
  sim.step(dt);
  Eigen::MatrixXd f(2, ps.size());
  for (int I = 0; I < ps.size(); ++I)
    f.col(I) = 2 * mass[I] * sim.displacement().segment<2>(2 * I) / (dt * dt);
  return f;
}

TEST(FollowerPressure, PushesTheInnerSurfaceOutwardWithPTimesItsShare) {
  const int nr = 3, nt = 24;
  const double p = 2.5, a = 0.5, dth = 2 * kPi / nt;
  const Eigen::MatrixXd f = follower_force("sph", p, nr, nt);
  // A regular polygon: f_I = p/2 · R₋₉₀(x_{I+1} − x_{I−1}) = p a sin Δθ radially outward.
  for (int j = 0; j < nt; ++j) {
    const Eigen::Vector2d e(std::cos(j * dth), std::sin(j * dth));
    EXPECT_NEAR(f.col(j).dot(e), p * a * std::sin(dth), 1e-6 * p * a);
    EXPECT_NEAR(f(0, j) * e.y() - f(1, j) * e.x(), 0.0, 1e-6 * p * a);
  }
  // Only the inner surface is loaded, and a closed surface's forces sum to zero.
  EXPECT_LT(f.rightCols(f.cols() - nt).norm(), 1e-6 * p * a);
  EXPECT_LT(f.rowwise().sum().norm(), 1e-9 * p * a * nt);
}

TEST(FollowerPressure, MethodsWithNodalParametersGetTheConsistentLoad) {
  // kbm-si's unknowns are MLS parameters: f_J = Σ_I N_J(X_I) f_I sums to zero (partition of
  // unity), and its work in a uniform expansion u = εX is the particles' own (linear
  // reproduction): Σ_J f_J·X_J = Σ_I f_I·X_I = p a² n_θ sin Δθ.
  const int nr = 4, nt = 32;
  const double p = 1.0, a = 0.5, dth = 2 * kPi / nt;
  AnnulusLattice spec{0.5, 1.0, nr, nt};
  const ParticleSet ps = annulus_lattice(spec);
  const Eigen::MatrixXd f = follower_force("kbm-si", p, nr, nt);
  EXPECT_LT(f.rowwise().sum().norm(), 1e-6);
  double work = 0;
  for (int J = 0; J < ps.size(); ++J) work += f.col(J).dot(ps.x.col(J));
  EXPECT_NEAR(work, p * a * a * nt * std::sin(dth), 1e-5);
}

TEST(FollowerPressure, RefusesOpenOrOutOfRangeLoops) {
  AnnulusLattice spec{0.5, 1.0, 3, 12};
  ParticleSet ps = annulus_lattice(spec);
  const auto m = test_catalogue().methods.create("sph", Params{});
  Discretization d = m->discretize(Domain::rectangle(-1, -1, 1, 1), ps, 1);
  Params mp;
  mp.set("E", 1.0);
  DynamicsModel model;
  model.material = test_catalogue().materials.create("svk", mp);
  model.mass = lumped_masses(d.particles, 1, MassLumping::volume);
  model.follower_pressures = {{{0, 1}, [](double) { return 1.0; }}};
  EXPECT_THROW(ExplicitDynamics(*m, d, model, DynamicsOptions{}), InputError);
  model.follower_pressures = {{{0, 1, 999}, [](double) { return 1.0; }}};
  EXPECT_THROW(ExplicitDynamics(*m, d, model, DynamicsOptions{}), InputError);
  model.follower_pressures = {{{0, 1, 2}, nullptr}};
  EXPECT_THROW(ExplicitDynamics(*m, d, model, DynamicsOptions{}), InputError);
}

/// Every registered method runs each ring by name for a few steps, or refuses the annulus.
class RingsByName : public ::testing::TestWithParam<std::string> {};

TEST_P(RingsByName, RunOrRefuseClearly) {
  for (const char* problem : {"rubber-ring", "steel-ring"})
    for (const char* frame : {"lagrangian", "eulerian"}) {
      CaseSpec s;
      s.problem = problem;
      s.method = GetParam();
      s.nodes = std::string(problem) == "rubber-ring" ? 120 : 150;  // small lattices: a smoke run
      s.problem_params = Params::parse(fmt::format(
          "frame={},frames=0,samples=5,end_time={},reference_elements=8", frame,
          std::string(problem) == "rubber-ring" ? 2e-6 : 2e-7));
      try {
        const CaseResult r = run_case(test_catalogue(), s);
        const TransientData& t = r.data<TransientData>();
        EXPECT_GT(t.steps, 0) << problem;
        EXPECT_FALSE(t.instability.has_value()) << problem << " " << frame << ": " << t.verdict();
        EXPECT_GE(r.headline.at("min neighbours"), 3) << problem;
        EXPECT_GT(r.headline.at("min det F"), 0.5) << problem;
      } catch (const InputError& e) {
        EXPECT_FALSE(std::string(e.what()).empty());
        GTEST_LOG_(INFO) << GetParam() << " refuses " << problem << ": " << e.what();
      }
    }
}

INSTANTIATE_TEST_SUITE_P(EveryMethod, RingsByName, ::testing::ValuesIn(registered_methods()),
                         [](const auto& info) { return test_name(info.param); });

TEST(Rings, BadParametersAreInputErrors) {
  for (const char* bad : {"radial=7", "jitter=0.7", "load=none", "pressure=-1", "end_time=nan",
                          "end_time=-1", "reference_elements=100000", "jitter=-0.1"}) {
    CaseSpec s;
    s.problem = "rubber-ring";
    s.method = "sph";
    s.nodes = 540;
    s.problem_params = Params::parse(std::string(bad) + ",frames=0");
    EXPECT_THROW(run_case(test_catalogue(), s), InputError) << bad;
  }
  CaseSpec s;
  s.problem = "steel-ring";
  s.method = "sph";
  s.nodes = 1051;  // prime: no polar lattice
  EXPECT_THROW(run_case(test_catalogue(), s), InputError);
  for (const char* bad : {"yield=-1", "imperfection=1", "hardening=-1e12", "hardening=nan"}) {
    s.nodes = 150;
    s.problem_params = Params::parse(std::string(bad) + ",frames=0");
    EXPECT_THROW(run_case(test_catalogue(), s), InputError) << bad;
  }
}

}  // namespace
}  // namespace mfv
