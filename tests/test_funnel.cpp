// The funnel of 001 §9.7: the free-streamline contraction coefficients against their closed
// forms, Torricelli's level law against the straight tank's closed form, the level recovered
// from the drained fraction, the lattice's wall clearance and volumes, the blow-up watch on a
// synthetic blow-up, the problem's refusal of bad parameters, a short run that drains water
// with finite fields, and the finding on synthetic studies.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "analyses/case.hpp"
#include "problems/fluid.hpp"
#include "problems/funnel_measures.hpp"
#include "test_support.hpp"
#include "verify/runner.hpp"

namespace mfv {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(ContractionCoefficient, FlatWallBordaAndFortyFiveDegrees) {
  // Closed forms: β = π/2 gives 1/(1 + 2/π) (the integral is ∫cos = 1), β = π gives 1/2.
  EXPECT_NEAR(funnel::contraction_coefficient(kPi / 2), 1 / (1 + 2 / kPi), 1e-10);
  EXPECT_NEAR(funnel::contraction_coefficient(kPi / 2), 0.611, 5e-4);
  EXPECT_NEAR(funnel::contraction_coefficient(kPi), 0.5, 1e-10);
  // 45° walls: the catalogue's "≈ 0.75"; it lies between the flat wall's and a parallel
  // channel's 1 and falls monotonically with β.
  const double c45 = funnel::contraction_coefficient(kPi / 4);
  EXPECT_NEAR(c45, 0.75, 0.01);
  EXPECT_GT(c45, funnel::contraction_coefficient(kPi / 2));
  EXPECT_GT(funnel::contraction_coefficient(0.1), c45);
  for (double bad : {0.0, -1.0, 4.0, std::nan("")})
    EXPECT_THROW(funnel::contraction_coefficient(bad), InputError) << bad;
}

TEST(FunnelGeometry, AreaAndItsInverse) {
  const funnel::Geometry g;
  EXPECT_NEAR(g.width(0), 0.04, 1e-15);
  EXPECT_NEAR(g.width(0.05), 0.14, 1e-15);
  EXPECT_NEAR(g.width(0.2), 0.24, 1e-15);
  // A(0.25) = ∫₀^0.1 (0.04 + 2y) dy + 0.24 × 0.15 = 0.014 + 0.036.
  EXPECT_NEAR(g.area(0.25), 0.05, 1e-15);
  for (double h : {0.0, 0.003, 0.05, 0.1, 0.17, 0.3})
    EXPECT_NEAR(g.level_of_area(g.area(h)), h, 1e-12) << h;
  // Half the water of 0.25 m: 0.014 + 0.24 (h − 0.1) = 0.025.
  EXPECT_NEAR(funnel::level_from_drained(g, 0.25, 0.5), 0.1 + 0.011 / 0.24, 1e-12);
  EXPECT_NEAR(funnel::level_from_drained(g, 0.25, 0.0), 0.25, 1e-12);
  EXPECT_EQ(funnel::level_from_drained(g, 0.25, 1.0), 0.0);
  EXPECT_NEAR(g.inertance(0.1), 0.5 * std::log(6.0), 1e-12);
}

TEST(Torricelli, StraightTankMatchesTheClosedForm) {
  // A straight tank (cone of zero height): w dh/dt = −C_c D √(2gh) gives
  // h(t) = (√h0 − C_c D √(2g) t / (2w))².
  funnel::Torricelli t;
  t.geometry.outlet = 0.04;
  t.geometry.cone = 0;
  const double w = 0.04, cc = 0.7, h0 = 0.25, g = 9.81;
  t.cc = cc;
  t.h0 = h0;
  t.g = g;
  const std::vector<double> times{0.0, 0.1, 0.2, 0.3};
  const std::vector<double> h = t.levels(times);
  for (std::size_t k = 0; k < times.size(); ++k) {
    const double exact = std::pow(std::sqrt(h0) - cc * 0.04 * std::sqrt(2 * g) * times[k] / (2 * w), 2);
    EXPECT_NEAR(h[k], exact, 1e-9 * h0) << times[k];
  }
  // It empties at t* = 2 w √h0 / (C_c D √(2g)) and stays empty.
  const double empty = 2 * w * std::sqrt(h0) / (cc * 0.04 * std::sqrt(2 * g));
  EXPECT_EQ(t.levels({0.0, 1.5 * empty}).back(), 0.0);
  // Drained half: √h = √(h0/2).
  const double half = 2 * w * (std::sqrt(h0) - std::sqrt(h0 / 2)) / (cc * 0.04 * std::sqrt(2 * g));
  EXPECT_NEAR(t.time_to_drain(0.5, 10.0), half, 1e-7);
  EXPECT_TRUE(std::isnan(t.time_to_drain(0.5, 0.5 * half)));
}

TEST(Torricelli, StartUpLagsTheQuasiSteadyLawThenFollowsIt) {
  funnel::Torricelli q;  // the funnel, C_c = 0.611
  funnel::Torricelli s = q;
  s.startup = true;
  const std::vector<double> times{0.01, 0.05, 0.3, 0.6};
  const auto fq = q.drained(times), fs = s.drained(times);
  for (std::size_t k = 0; k < times.size(); ++k) EXPECT_LT(fs[k], fq[k]) << times[k];
  // After the start-up it is the quasi-steady law a little later: with the level frozen,
  // C_c D I dv/dt = g h − v²/2 gives v = v∞ tanh(v∞ t / 2L), L = C_c D I(h0), which lags the
  // outflow by 2 L ln 2 / v∞ (0.023 s here); the half-drain times differ by about that.
  const double L = q.cc * q.geometry.outlet * q.geometry.inertance(q.h0);
  const double lag = 2 * L * std::log(2.0) / std::sqrt(2 * q.g * q.h0);
  EXPECT_NEAR(s.time_to_drain(0.5, 5.0) - q.time_to_drain(0.5, 5.0), lag, 0.2 * lag);
  EXPECT_THROW(q.levels({0.2, 0.1}), InputError);
  funnel::Torricelli bad;
  bad.cc = 0;
  EXPECT_THROW(bad.levels({0.1}), InputError);
}

TEST(FunnelMeasures, DrainedFractionAndFirstCrossing) {
  Eigen::MatrixXd x(2, 4);
  x << 0, 0, 0, 0,  //
      0.1, -0.01, 0.2, -2.0;
  const Eigen::VectorXd m = Eigen::Vector4d(1, 2, 3, 4);
  EXPECT_NEAR(funnel::drained_fraction(x, m), 0.6, 1e-15);
  EXPECT_NEAR(funnel::first_crossing({0, 1, 2}, {0, 0.4, 0.8}, 0.5), 1.25, 1e-12);
  EXPECT_TRUE(std::isnan(funnel::first_crossing({0, 1}, {0, 0.4}, 0.5)));
}

TEST(FunnelLattice, ClearOfTheWallsWithConsistentVolumes) {
  const funnel::Geometry g;
  const double dx = 0.005;
  const ParticleSet p = funnel::funnel_lattice(g, 0.25, dx);
  ASSERT_GT(p.size(), 1500);
  const auto walls = funnel::wall_segments(g);
  double nearest = INFINITY;
  for (int I = 0; I < p.size(); ++I)
    for (const auto& w : walls) {
      const Eigen::Vector2d s = w[1] - w[0];
      const double t = std::clamp((p.x.col(I) - w[0]).dot(s) / s.squaredNorm(), 0.0, 1.0);
      nearest = std::min(nearest, (p.x.col(I) - w[0] - t * s).norm());
    }
  EXPECT_GE(nearest, 0.5 * dx * (1 - 1e-9));
  EXPECT_LT(nearest, dx);
  // The bottom row spans the outlet: D/Δx particles.
  int bottom = 0;
  for (int I = 0; I < p.size(); ++I) bottom += p.x(1, I) < dx;
  EXPECT_EQ(bottom, 8);
  // The volumes cover about the funnel's area (the staircase at the cone loses a little).
  EXPECT_NEAR(p.volume.sum(), g.area(0.25), 0.05 * g.area(0.25));
  ASSERT_TRUE(p.stress_points);
  EXPECT_EQ(p.stress_points->x.cols(), static_cast<Eigen::Index>(p.quads.size()));
  EXPECT_NEAR(p.stress_points->particle_volume.sum() + p.stress_points->volume.sum(),
              p.volume.sum(), 1e-12);
  EXPECT_GT(p.stress_points->particle_volume.minCoeff(), 0.0);
  for (const auto& q : p.quads) {
    // Counter-clockwise unit squares.
    const Eigen::Vector2d a = p.x.col(q[0]), b = p.x.col(q[1]), c = p.x.col(q[2]);
    EXPECT_NEAR((b - a).norm(), dx, 1e-12);
    EXPECT_GT((b - a).x() * (c - b).y() - (b - a).y() * (c - b).x(), 0);
  }
  for (double bad : {0.0, -0.005, 0.03, std::nan(""), 1e-6})
    EXPECT_THROW(funnel::funnel_lattice(g, 0.25, bad), InputError) << bad;
}

TEST(FluidWatch, FlagsASyntheticBlowUp) {
  // A block of water at rest is sound; a particle whose speed grows as e^{1000 t} gives the
  // growth rate, and one set far beyond the speed bound is reported.
  const double dx = 0.01;
  const Domain box = Domain::rectangle(0, 0, 0.04, 0.04);
  const ParticleSet p = rectangle_lattice(box, 4, 4, Placement::inset);
  auto m = test_catalogue().methods.create("sph");
  Discretization d = m->discretize(box, p, 1);
  fluid::Setup setup;
  setup.surface = 0.04;
  DynamicsModel model = fluid::water_model(d, test_catalogue().materials, setup);
  const Eigen::VectorXd mass = model.mass;
  DynamicsOptions opt;
  opt.frame = KernelFrame::eulerian;
  ExplicitDynamics sim(*m, std::move(d), model, opt);
  fluid::Limits limits;
  limits.speed = 5 * std::sqrt(2 * 9.81 * 0.04);
  fluid::Watch watch(mass, 9.81, fluid::potential_energy(p.x, mass, 9.81), limits);
  EXPECT_EQ(watch.check(sim), "");
  // A speed growing as e^{1000 t}: the watch's samples fit the rate.
  const double dt = 0.1 * dx / setup.water.sound_speed();
  for (int k = 0; k < 30; ++k) {
    Eigen::MatrixXd v = Eigen::MatrixXd::Zero(2, p.size());
    v(0, 0) = std::exp(1000.0 * k * dt);  // far above the settling's mm/s
    sim.set_particle_velocity(v);
    sim.step(dt);
    watch.sample(sim);
  }
  EXPECT_NEAR(watch.speed_growth_rate(10), 1000.0, 100.0);
  Eigen::MatrixXd v = Eigen::MatrixXd::Zero(2, p.size());
  v(1, 3) = 100;
  sim.set_particle_velocity(v);
  EXPECT_NE(watch.check(sim).find("moves at"), std::string::npos);
}

CaseSpec funnel_case(const std::string& params, int nodes = 4, const std::string& method = "sph") {
  CaseSpec s;
  s.problem = "funnel";
  s.method = method;
  s.nodes = nodes;
  s.problem_params = Params::parse(params);
  return s;
}

TEST(FunnelProblem, BadParametersAreInputErrors) {
  for (const char* bad : {"end_time=0", "end_time=-1", "end_time=nan", "end_time=1e9",
                          "level=0", "level=-0.2", "level=nan", "level=1e6", "level=0.01"}) {
    EXPECT_THROW(run_case(test_catalogue(), funnel_case(std::string(bad) + ",frames=0")),
                 InputError)
        << bad;
  }
  EXPECT_THROW(run_case(test_catalogue(), funnel_case("frames=0", 2)), InputError);
  EXPECT_THROW(run_case(test_catalogue(), funnel_case("frames=0", 100000)), InputError);
}

TEST(FunnelProblem, ShortRunDrainsWaterWithFiniteFields) {
  // Δx = 10 mm (D/Δx = 4), SPH with the Eulerian kernel, 60 ms: water has left the outlet.
  const CaseResult r = run_case(
      test_catalogue(), funnel_case("frame=eulerian,end_time=0.06,frames=2,samples=20"));
  const TransientData& t = r.data<TransientData>();
  EXPECT_FALSE(t.instability.has_value()) << t.verdict();
  EXPECT_GT(t.steps, 200);
  EXPECT_GT(r.headline.at("drained fraction"), 0.005);
  EXPECT_LT(r.headline.at("drained fraction"), 0.2);
  EXPECT_GT(r.headline.at("density min / rho0"), 0.9);
  EXPECT_LT(r.headline.at("density max / rho0"), 1.1);
  EXPECT_LT(r.headline.at("energy error"), 0.1);
  EXPECT_LT(r.headline.at("max speed (m/s)"), r.headline.at("speed bound (m/s)"));
  for (const auto& f : t.frames)
    for (const auto& [name, field] : f.data) EXPECT_TRUE(field.allFinite()) << name;
  ASSERT_GE(t.profiles.size(), 2u);
}

/// A synthetic kbm-si study of the funnel with the headlines the finding reads.
StudySummary funnel_study(const std::string& frame, bool drains, double blow_up) {
  StudySummary s;
  s.method = "kbm-si";
  s.label = "kbm-si " + frame;
  s.finest_nodes = 8;
  s.problem_resolved.set("frame", frame.c_str());
  s.headlines.push_back({{"drains in band", drains ? 1.0 : 0.0},
                         {"unstable", std::isnan(blow_up) ? 0.0 : 1.0},
                         {"blow-up time (s)", blow_up},
                         {"half-drain time band low (s)", 0.43}});
  return s;
}

std::string funnel_verdict(const std::vector<StudySummary>& studies) {
  const auto p = create_problem(test_catalogue(), "funnel", Params{});
  for (const Finding& f : p->findings())
    if (f.id == "kbm-si-eulerian-drains-lagrangian-explodes") return f.check(studies).status;
  ADD_FAILURE() << "no finding kbm-si-eulerian-drains-lagrangian-explodes";
  return {};
}

TEST(FunnelFindings, EulerianDrainsAndLagrangianBlowsUpEarly) {
  EXPECT_EQ(funnel_verdict({funnel_study("lagrangian", false, 0.1),
                            funnel_study("eulerian", true, NAN)}),
            "reproduced");
  // A Lagrangian blow-up after the band's earliest half-drain time, or none, does not count.
  EXPECT_EQ(funnel_verdict({funnel_study("lagrangian", false, 0.5),
                            funnel_study("eulerian", true, NAN)}),
            "not reproduced");
  EXPECT_EQ(funnel_verdict({funnel_study("lagrangian", false, NAN),
                            funnel_study("eulerian", true, NAN)}),
            "not reproduced");
  EXPECT_EQ(funnel_verdict({funnel_study("lagrangian", false, 0.1),
                            funnel_study("eulerian", false, NAN)}),
            "not reproduced");
  EXPECT_EQ(funnel_verdict({funnel_study("lagrangian", false, 0.1)}), "not run");
}

}  // namespace
}  // namespace mfv
