#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <gtest/gtest.h>

#include "dynamics/explicit.hpp"
#include "problems/fluid.hpp"
#include "problems/fluid_measures.hpp"
#include "test_support.hpp"

namespace mfv {
namespace {

TEST(FluidDiag, DISABLED_Column) {
  const char* me = std::getenv("DIAG_METHOD");
  const std::string method = me ? me : "sph";
  const int nx = std::getenv("DIAG_NX") ? std::atoi(std::getenv("DIAG_NX")) : 20;
  const double kscale = std::getenv("DIAG_K") ? std::atof(std::getenv("DIAG_K")) : 1.0;
  const bool lag = std::getenv("DIAG_LAG") != nullptr;
  const double W = 0.1, H = 0.2, dx = W / nx;
  const int ny = static_cast<int>(std::lround(H / dx));
  const Domain box = Domain::rectangle(0, 0, W, H);
  const ParticleSet p = rectangle_lattice(box, nx, ny, Placement::inset);
  auto m = test_catalogue().methods.create(method);
  Discretization d = m->discretize(box, p, 1);
  fluid::Setup setup;
  setup.surface = H;
  setup.walls = {{{0, 0}, {W, 0}}, {{0, 0}, {0, 2 * H}}, {{W, 0}, {W, 2 * H}}};
  DynamicsOptions opt;
  opt.frame = lag ? KernelFrame::lagrangian : KernelFrame::eulerian;
  opt.viscosity.alpha = 0.1;
  opt.threads = 1;
  DynamicsModel model = fluid::water_model(d, test_catalogue().materials, setup);
  if (kscale != 1.0) {
    auto walls = std::make_shared<const fluid::Walls>(setup.walls, 0.5 * dx,
        kscale * std::pow(setup.water.sound_speed() / dx, 2));
    const Eigen::VectorXd mass = model.mass;
    const double g = setup.water.g;
    model.particle_forces = [walls, mass, g](double, const Eigen::MatrixXd& x, Eigen::MatrixXd& f) {
      f.row(1).array() -= g * mass.transpose().array();
      walls->add_forces(x, mass, f);
    };
  }
  if (std::getenv("DIAG_PIN")) {
    for (int I = 0; I < p.size(); ++I)
      if (p.x(1, I) < dx) model.prescribed.push_back({I, 1, 0.0});
  }
  const double MgH = model.mass.sum() * 9.81 * H;
  ExplicitDynamics sim(*m, std::move(d), model, opt);
  const double c0 = setup.water.sound_speed();
  const double dt = 0.5 * sim.critical_time_step();
  const int per = static_cast<int>(H / c0 / dt);
  const int crossings = std::getenv("DIAG_C") ? std::atoi(std::getenv("DIAG_C")) : 20;
  double avg_b = 0, avg_e = 0; int na = 0;
  Eigen::VectorXd prow = Eigen::VectorXd::Zero(ny);
  for (int c = 0; c <= crossings; ++c) {
    const Eigen::MatrixXd x = sim.particle_positions();
    const Eigen::MatrixXd v = sim.particle_velocity();
    const Eigen::VectorXd pr = fluid::pressure_of(sim.particle_cauchy_stress());
    Eigen::Index fast = 0;
    const double vmax = v.colwise().norm().maxCoeff(&fast);
    double bot = 0, bex = 0, top = 0, side = 0, sex = 0;
    for (int I = 0; I < p.size(); ++I) {
      const double ex = 1000 * 9.81 * (H - x(1, I));
      if (p.x(1, I) < dx) { bot += pr[I]; bex += ex; }
      if (p.x(1, I) > H - dx) top += pr[I] / nx;
      if (p.x(0, I) < dx && p.x(1,I) > dx) { side += pr[I]; sex += ex; }
    }
    std::printf("c=%2d K/MgH=%.3e vmax=%.3e at (%.4f,%.4f) bottom=%.4f side=%.4f top=%.1f Pa eP=%.4f dy_bot=%.3e dx_left=%.3e\n", c,
                sim.kinetic_energy() / MgH, vmax, p.x(0, fast), p.x(1, fast), bot / bex, side/sex, top,
                fluid::hydrostatic_pressure_error(x, pr, 1000, 9.81, H), x(1,0)-p.x(1,0), x(0,0)-p.x(0,0));
    for (int s = 0; s < per; ++s) {
      sim.step(dt);
      if (c >= crossings / 2 && s % 4 == 0) {
        const Eigen::VectorXd q = fluid::pressure_of(sim.particle_cauchy_stress());
        for (int I = 0; I < p.size(); ++I) {
          const int r = static_cast<int>(p.x(1, I) / dx);
          prow[r] += q[I] / nx;
          if (r == 0) { avg_b += q[I]; avg_e += 1000 * 9.81 * (H - p.x(1, I)); }
        }
        ++na;
      }
    }
  }
  std::printf("time-averaged bottom ratio %.4f\n", avg_b / avg_e);
  for (int r = 0; r < ny; r += std::max(1, ny / 10))
    std::printf("row %d y=%.4f p/exact=%.4f\n", r, (r + 0.5) * dx, prow[r] / na / (1000 * 9.81 * (H - (r + 0.5) * dx)));
  std::printf("row %d p/exact=%.4f\n", ny - 1, prow[ny - 1] / na / (1000 * 9.81 * (H - (ny - 0.5) * dx)));
}

}  // namespace
}  // namespace mfv
