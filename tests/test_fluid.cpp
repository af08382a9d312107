// The fluid pieces shared by the funnel, hydrostatic column and dam break (problems/fluid.hpp):
// the Tait material of 001 eq 77, the hydrostatic state, the penalty walls, and a column at
// rest that stays at rest.
#include <cmath>

#include <gtest/gtest.h>

#include "dynamics/explicit.hpp"
#include "problems/fluid.hpp"
#include "test_support.hpp"

namespace mfv {
namespace {

std::unique_ptr<Material> tait() { return test_catalogue().materials.create("tait", Params{}); }

TEST(Tait, KirchhoffStressIsMinusJPressureWithoutInvertingF) {
  const auto m = tait();
  const fluid::Water w;
  // A sheared and compressed F (column-major): τ = P Fᵀ must be −J p I whatever the shear.
  const double F[4] = {0.99, 0.0, 3.0, 0.995};
  double P[4], state[2] = {w.rho0, 0};
  m->first_piola(2, 1, F, P, state);
  const double J = F[0] * F[3] - F[1] * F[2];
  const double p = w.B * (std::pow(1 / J, w.gamma) - 1);
  EXPECT_NEAR(state[1], w.rho0 / J, 1e-9);
  const double t11 = P[0] * F[0] + P[2] * F[2], t12 = P[0] * F[1] + P[2] * F[3];
  const double t21 = P[1] * F[0] + P[3] * F[2], t22 = P[1] * F[1] + P[3] * F[3];
  EXPECT_NEAR(t11, -J * p, 1e-9 * std::abs(p));
  EXPECT_NEAR(t22, -J * p, 1e-9 * std::abs(p));
  EXPECT_NEAR(t12, 0, 1e-9 * std::abs(p));
  EXPECT_NEAR(t21, 0, 1e-9 * std::abs(p));
  EXPECT_NEAR(m->wave_speed(2, 1.0), 57.38, 0.01);  // √(7 · 0.4704 MPa / 1000 kg/m³)
}

TEST(Tait, AnInvertedPointHasNoDensity) {
  const auto m = tait();
  const double F[4] = {-1, 0, 0, 1};
  double P[4], state[2] = {1000, 0};
  m->first_piola(2, 1, F, P, state);
  EXPECT_FALSE(std::isfinite(P[0]));
}

TEST(Tait, RefusesBadParameters) {
  for (const char* bad : {"gamma=0", "gamma=-7", "gamma=nan", "gamma=100", "B=0", "rho0=-1"}) {
    const std::string s(bad);
    Params p;
    const auto eq = s.find('=');
    p.set(s.substr(0, eq), std::stod(s.substr(eq + 1)));
    EXPECT_THROW(test_catalogue().materials.create("tait", p), InputError) << bad;
  }
}

TEST(Water, HydrostaticDensityInvertsTheEquationOfState) {
  const fluid::Water w;
  for (double h : {0.0, 0.01, 0.25, 10.0})
    EXPECT_NEAR(w.pressure(w.hydrostatic_density(h)), w.rho0 * w.g * h, 1e-6 * (1 + h));
}

TEST(Walls, PushAlongTheNormalOnlyWithinReach) {
  const fluid::Walls walls({{Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0)}}, 0.1, 100.0);
  Eigen::MatrixXd x(2, 3);
  x << 0.5, 0.5, 2.0,  //
      0.04, 0.2, 0.05;  // inside reach; beyond reach; beyond the segment's end
  const Eigen::VectorXd m = Eigen::VectorXd::Constant(3, 2.0);
  Eigen::MatrixXd f = Eigen::MatrixXd::Zero(2, 3);
  walls.add_forces(x, m, f);
  EXPECT_NEAR(f(1, 0), 2.0 * 100 * 0.06, 1e-12);
  EXPECT_EQ(f(0, 0), 0);
  EXPECT_EQ(f.col(1).norm(), 0);
  EXPECT_EQ(f.col(2).norm(), 0);
  EXPECT_NEAR(walls.energy(x, m), 0.5 * 2.0 * 100 * 0.06 * 0.06, 1e-12);
  EXPECT_THROW(fluid::Walls({{Eigen::Vector2d(0, 0), Eigen::Vector2d(0, 0)}}, 0.1, 1.0),
               InputError);
  EXPECT_THROW(fluid::Walls({}, -0.1, 1.0), InputError);
  EXPECT_THROW(fluid::Walls({}, 0.1, std::nan("")), InputError);
}

/// A column of water at rest in a box, hydrostatic at t = 0: over a few sound crossings it
/// stays at rest (speeds far below √(2 g H)) and the bottom pressure stays ρ0 g H.
class ColumnAtRest : public ::testing::TestWithParam<std::string> {};

TEST_P(ColumnAtRest, StaysAtRest) {
  const double W = 0.05, H = 0.1, dx = 0.005;
  const Domain box = Domain::rectangle(0, 0, W, H);
  const ParticleSet p = rectangle_lattice(box, 10, 20, Placement::inset);
  auto m = test_catalogue().methods.create(GetParam());
  Discretization d = m->discretize(box, p, 1);
  fluid::Setup setup;
  setup.surface = H;
  setup.walls = {{{0, 0}, {W, 0}}, {{0, 0}, {0, 2 * H}}, {{W, 0}, {W, 2 * H}}};
  DynamicsOptions opt;
  opt.frame = KernelFrame::eulerian;
  opt.viscosity.alpha = 0.1;
  DynamicsModel model = fluid::water_model(d, test_catalogue().materials, setup);
  ExplicitDynamics sim(*m, std::move(d), model, opt);
  const double c0 = setup.water.sound_speed();
  const double dt = 0.2 * dx / c0;
  const int steps = static_cast<int>(4 * H / c0 / dt);  // four sound crossings
  for (int s = 0; s < steps; ++s) sim.step(dt);
  const double vmax = sim.particle_velocity().colwise().norm().maxCoeff();
  EXPECT_LT(vmax, 0.02 * std::sqrt(2 * setup.water.g * H)) << GetParam();
  // The bottom row's mean pressure, averaged over the last crossing (the settling leaves an
  // acoustic ripple that α = 0.1 damps slowly), against ρ0 g (H − y).
  double mean = 0, exact = 0;
  int samples = 0;
  const int last = static_cast<int>(H / c0 / dt);
  for (int s = 0; s < last; ++s) {
    sim.step(dt);
    const Eigen::MatrixXd sigma = sim.particle_cauchy_stress();
    for (int I = 0; I < p.size(); ++I) {
      if (p.x(1, I) > dx) continue;
      mean += -0.5 * (sigma(0, I) + sigma(3, I));
      exact += setup.water.rho0 * setup.water.g * (H - p.x(1, I));
      ++samples;
    }
  }
  // SPH's row holds it to 5 % over this crossing, kbm-ni's is about 12 % low: a one-crossing
  // window samples a slow oscillation of the bottom row's pressure at one phase. Averaged over
  // crossings 3–10 both rows are 13–14 % high, the same with the floor wall replaced by a
  // pinned row, and not converging with Δx: the boundary row's one-sided supports, not the
  // walls or the hydrostatic start (exact at t = 0); hydrostatic-column measures it per method.
  const double tolerance = GetParam() == "sph" ? 0.05 : 0.15;
  EXPECT_NEAR(mean / samples, exact / samples, tolerance * exact / samples) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(Methods, ColumnAtRest, ::testing::Values("sph", "kbm-ni"),
                         [](const auto& info) { return test_name(info.param); });

}  // namespace
}  // namespace mfv
