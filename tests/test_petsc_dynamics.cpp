// The total-Lagrangian engine on PETSc (dynamics/petsc_dynamics.hpp) against the native one
// on a small plane-strain rod (rod-pulse's 60 × 5 mm steel bar): after 100 steps the gathered
// displacements and velocities and the energy balance agree.
//
// Run as a unit test on one process, and by ctest under `mpiexec -n 2` (label mpi): every rank
// builds the native engine too and compares the gathered PETSc fields with it. Tolerances,
// relative to the largest native value of the field (energies: to the initial kinetic energy):
//   one rank 1e-12: the same arithmetic, except that MatMult sums a row in PETSc's column
//     order (the tables' order here) and the work sums are plain loops, not Eigen's dot;
//   two ranks 1e-10: a row's sum also splits into the diagonal and off-diagonal blocks, and
//     the transpose adds the other rank's contributions, and the energy sums per rank.
// Measured after 100 steps (sph, kbm-si, efg-ni): one rank u and v bit for bit, energy
// ≤ 3e-16; two ranks u ≤ 3.4e-14, v ≤ 5.8e-13, energy ≤ 5.2e-15.
#include <cmath>
#include <memory>

#include <gtest/gtest.h>

#include "dynamics/petsc_dynamics.hpp"
#include "methods/core/errors.hpp"
#include "methods/core/petsc_session.hpp"
#include "test_support.hpp"
#include "analyses/transient.hpp"
#include "verify/runner.hpp"

namespace mfv {
namespace {

constexpr double kLength = 60, kHeight = 5, kE = 210, kDensity = 7.8e-6;

double tolerance() { return petsc::size() > 1 ? 1e-10 : 1e-12; }

/// max |a − b| / max |b|.
double relative_difference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  const double scale = b.cwiseAbs().maxCoeff();
  return scale > 0 ? (a - b).cwiseAbs().maxCoeff() / scale : (a - b).cwiseAbs().maxCoeff();
}

/// The rod at 37 × 4 particles (Δx = 5/3 mm) with the options of one comparison.
struct Rod {
  Domain box = Domain::rectangle(0, 0, kLength, kHeight);
  ParticleSet particles = rectangle_lattice(box, 37, 4, Placement::boundary);
  std::unique_ptr<Method> method;
  Discretization d;
  DynamicsModel model;
  Eigen::MatrixXd v0;

  explicit Rod(const std::string& name, bool impulse = false) {
    method = test_catalogue().methods.create(name);
    d = method->discretize(box, particles, 1);
    Params mp;
    mp.set("E", kE);
    mp.set("nu", 0.3);
    mp.set("plane", "strain");
    model.material = test_catalogue().materials.create("svk", mp);
    model.density = kDensity;
    model.mass = lumped_masses(particles, kDensity, MassLumping::volume);
    const int n = particles.size();
    v0 = Eigen::MatrixXd::Zero(2, n);
    if (impulse) {  // the left end driven at 5 m/s for a while, and a pull on the right end
      for (int I = 0; I < n; ++I)
        if (particles.sides[I] & Side::left) model.prescribed.push_back({I, 0, 5.0, 5e-4});
      model.external_force = [this](double t, Eigen::VectorXd& f) {
        for (int I = 0; I < particles.size(); ++I)
          if (particles.sides[I] & Side::right) f[2 * I] = 1e-3 * std::sin(2000 * t);
      };
    } else {  // a Gaussian velocity pulse with some lateral motion
      for (int I = 0; I < n; ++I) {
        const double x = particles.x(0, I), y = particles.x(1, I);
        v0(0, I) = 10 * std::exp(-0.02 * (x - 20) * (x - 20));
        v0(1, I) = 2 * std::exp(-0.02 * (x - 30) * (x - 30)) * (y - 2.5) / 2.5;
      }
    }
  }
};

struct Comparison {
  double u = 0, v = 0, energy = 0;
};

Comparison compare(const std::string& name, const DynamicsOptions& opt, bool impulse,
                   int steps = 100) {
  Rod rod(name, impulse);
  ExplicitDynamics native(*rod.method, rod.d, rod.model, opt);
  PetscDynamics petsc(*rod.method, rod.d, rod.model, opt);
  if (!impulse) {
    native.set_particle_velocity(rod.v0);
    petsc.set_particle_velocity(rod.v0);
  }
  const double dt = 0.5 * native.critical_time_step();
  for (int s = 0; s < steps; ++s) {
    native.step(dt);
    petsc.step(dt);
  }
  EXPECT_TRUE(petsc.fields_finite());
  EXPECT_EQ(petsc.counters().steps, steps);
  EXPECT_DOUBLE_EQ(petsc.time(), native.time());
  Comparison c;
  c.u = relative_difference(petsc.displacement(), native.displacement());
  c.v = relative_difference(petsc.velocity(), native.velocity());
  const EnergyBalance& a = petsc.energy();
  const EnergyBalance& b = native.energy();
  const double scale = std::max({std::abs(b.initial), b.kinetic, std::abs(b.external_work)});
  c.energy = std::max({std::abs(a.kinetic - b.kinetic), std::abs(a.internal_work - b.internal_work),
                       std::abs(a.external_work - b.external_work),
                       std::abs(a.initial - b.initial)}) /
             scale;
  // The gathered engine the problems' callbacks read holds the same state.
  const ExplicitDynamics& view = petsc.state();
  const double tol = opt.viscosity.enabled() ? 1e-10 : tolerance();
  EXPECT_LE(relative_difference(view.velocity(), native.velocity()), tol) << name;
  EXPECT_LE(relative_difference(view.point_cauchy_stress(), native.point_cauchy_stress()), tol)
      << name;
  EXPECT_EQ(view.time(), petsc.time());
  return c;
}

class PetscDynamicsMatches : public ::testing::TestWithParam<std::string> {};

TEST_P(PetscDynamicsMatches, TheNativeEngineOnAGaussianPulse) {
  const Comparison c = compare(GetParam(), {}, false);
  EXPECT_LE(c.u, tolerance()) << GetParam();
  EXPECT_LE(c.v, tolerance()) << GetParam();
  EXPECT_LE(c.energy, tolerance()) << GetParam();
  if (petsc::rank() == 0)
    std::printf("%s on %d rank(s): relative differences u %.2e, v %.2e, energy %.2e\n",
                GetParam().c_str(), petsc::size(), c.u, c.v, c.energy);
}

TEST_P(PetscDynamicsMatches, TheNativeEngineWithSupportsLoadsAndNewmark) {
  // Prescribed velocities (released mid-run), an external force, the variational force and
  // the Newmark corrector (the prestress and a material history are in the test below).
  DynamicsOptions opt;
  opt.integrator = TimeIntegrator::newmark;
  opt.newmark_gamma = 0.6;
  opt.force = ForceForm::variational;
  const Comparison c = compare(GetParam(), opt, true);
  EXPECT_LE(c.u, tolerance()) << GetParam();
  EXPECT_LE(c.v, tolerance()) << GetParam();
  EXPECT_LE(c.energy, tolerance()) << GetParam();
}

TEST_P(PetscDynamicsMatches, TheNativeEngineWithArtificialViscosity) {
  // Ḟ = G du / dt is one more MatMult, which divides the row's sum by dt where the native
  // loop divides every term: round-off apart, amplified by the compression switch of the
  // viscous pressure. Tolerance 1e-10 on one and two ranks; measured on one rank after 100
  // steps: u ≤ 5e-14, v ≤ 1.0e-12 (efg-ni), energy ≤ 1e-14.
  DynamicsOptions opt;
  opt.viscosity.alpha = 1;
  opt.viscosity.beta = 2;
  const Comparison c = compare(GetParam(), opt, false);
  EXPECT_LE(c.u, 1e-10) << GetParam();
  EXPECT_LE(c.v, 1e-10) << GetParam();
  EXPECT_LE(c.energy, 1e-10) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(Methods, PetscDynamicsMatches,
                         ::testing::Values("sph", "kbm-si", "efg-ni"),
                         [](const auto& info) { return test_name(info.param); });

TEST(PetscDynamics, PrestressAndMaterialHistoryStayWithTheirPoints) {
  // J2 plasticity (a history per point, updated on the rank that owns the point) under a
  // prestress: the gathered history is the native engine's.
  Rod rod("sph");
  Params mp;
  mp.set("E", kE);
  mp.set("nu", 0.3);
  mp.set("yield", 0.05);
  mp.set("hardening", 2.0);
  rod.model.material = test_catalogue().materials.create("j2-jaumann", mp);
  rod.model.initial_stress = Eigen::Matrix2d{{1e-3, 0}, {0, 0}};
  ExplicitDynamics native(*rod.method, rod.d, rod.model, {});
  PetscDynamics petsc(*rod.method, rod.d, rod.model, {});
  native.set_particle_velocity(rod.v0);
  petsc.set_particle_velocity(rod.v0);
  const double dt = 0.5 * native.critical_time_step();
  for (int s = 0; s < 100; ++s) {
    native.step(dt);
    petsc.step(dt);
  }
  const ExplicitDynamics& view = petsc.state();
  const std::vector<std::string> names = native.material().state_names(2);
  ASSERT_FALSE(names.empty());
  bool yielded = false;
  for (const std::string& s : names) {
    const Eigen::VectorXd a = view.point_state(s), b = native.point_state(s);
    EXPECT_LE(relative_difference(a, b), tolerance()) << s;
    yielded |= b.cwiseAbs().maxCoeff() > 0;
  }
  EXPECT_TRUE(yielded) << "the pulse should yield some points";
  EXPECT_LE(relative_difference(view.velocity(), native.velocity()), tolerance());
}

TEST(PetscDynamics, HaloIsTheOffRankSupport) {
  // The rod stood on end (5 × 60 mm, 4 × 37 particles numbered x fastest), so that the ranks'
  // contiguous ranges of particles are bands of its length and the cut crosses it. kbm-si
  // adds stress points after the particles: they go with the particles of their supports,
  // so a rank's ghosts are the few rows beside the cut, not the other rank's every particle.
  const Domain box = Domain::rectangle(0, 0, kHeight, kLength);
  const ParticleSet particles = rectangle_lattice(box, 4, 37, Placement::boundary);
  for (const char* name : {"sph", "kbm-si"}) {
    const auto method = test_catalogue().methods.create(name);
    Params mp;
    mp.set("E", kE);
    mp.set("nu", 0.3);
    DynamicsModel model;
    model.material = test_catalogue().materials.create("svk", mp);
    model.density = kDensity;
    model.mass = lumped_masses(particles, kDensity, MassLumping::volume);
    PetscDynamics petsc(*method, method->discretize(box, particles, 1), model, {});
    const PetscHalo h = petsc.halo();
    EXPECT_EQ(h.ranks, petsc::size());
    long owned[2] = {h.owned_unknowns, h.owned_points}, total[2] = {0, 0};
    MPI_Allreduce(owned, total, 2, MPI_LONG, MPI_SUM, PETSC_COMM_WORLD);
    EXPECT_EQ(total[0], 2L * particles.size()) << name;
    EXPECT_GE(total[1], particles.size()) << name;
    EXPECT_GT(h.matrix_bytes, 0);
    if (h.ranks == 1) {
      EXPECT_EQ(h.ghost_trial, 0);
      EXPECT_EQ(h.ghost_test, 0);
      continue;
    }
    // Supports of about two spacings: a few rows of 4 particles beside the cut (measured:
    // 18 ghost unknowns for both methods, both products), against 148 unknowns on the other
    // rank.
    const long others = 2L * particles.size() - h.owned_unknowns;
    EXPECT_GT(h.ghost_trial, 0) << name;
    EXPECT_LE(h.ghost_trial, others / 3) << name;
    EXPECT_GT(h.ghost_test, 0) << name;
    EXPECT_LE(h.ghost_test, others / 3) << name;
    EXPECT_EQ(h.halo_bytes, 8 * (h.ghost_trial + h.ghost_test + 5)) << name;
    std::printf("%s rank %d: %ld points, ghosts %ld (F) %ld (f)\n", name, h.rank,
                h.owned_points, h.ghost_trial, h.ghost_test);
  }
}

TEST(PetscDynamics, RefusesWhatItDoesNotSupport) {
  Rod rod("sph");
  DynamicsOptions eulerian;
  eulerian.frame = KernelFrame::eulerian;
  auto refused = [&](const DynamicsModel& m, const DynamicsOptions& o, const char* what) {
    try {
      PetscDynamics p(*rod.method, rod.d, m, o);
      ADD_FAILURE() << what << " accepted";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(what), std::string::npos) << msg;
      EXPECT_NE(msg.find("engine=native"), std::string::npos) << msg;
    }
  };
  refused(rod.model, eulerian, "frame=eulerian");
  DynamicsModel follower = rod.model;
  follower.follower_pressures.push_back({{0, 1, 2}, [](double) { return 1.0; }});
  refused(follower, {}, "follower pressures");
  DynamicsModel walls = rod.model;
  walls.particle_forces = [](double, const Eigen::MatrixXd&, Eigen::MatrixXd&) {};
  refused(walls, {}, "particle forces");
  EXPECT_THROW(make_dynamics_engine("gpu", *rod.method, rod.d, rod.model, {}), InputError);
  PetscDynamics ok(*rod.method, rod.d, rod.model, {});
  EXPECT_THROW(ok.step(0), InputError);
  EXPECT_THROW(ok.step(-1), InputError);
  EXPECT_THROW(ok.step(NAN), InputError);
}

TEST(PetscDynamics, TransientAnalysisGivesTheNativeErrors) {
  // rod-pulse through the transient analysis (checkpoints, probes, frames read the gathered
  // state): the velocity errors and the energy drift of engine=petsc are the native ones.
  CaseSpec spec;
  spec.problem = "rod-pulse";
  spec.method = "kbm-si";
  spec.nodes = 61;
  spec.problem_params = Params::parse("loading=gaussian,frames=2");
  const CaseResult native = run_case(test_catalogue(), spec);
  spec.problem_params = Params::parse("loading=gaussian,frames=2,engine=petsc");
  const CaseResult petsc = run_case(test_catalogue(), spec);
  ASSERT_TRUE(std::isfinite(native.errors.l2_rel));
  EXPECT_NEAR(petsc.errors.l2_rel, native.errors.l2_rel, tolerance() * native.errors.l2_rel);
  for (const auto& [k, v] : native.headline)
    if (k != "CPU minutes")
      EXPECT_NEAR(petsc.headline.at(k), v, 1e-8 * std::abs(v) + 1e-14) << k;
  const auto& a = petsc.data<TransientData>();
  const auto& b = native.data<TransientData>();
  EXPECT_EQ(a.steps, b.steps);
  ASSERT_EQ(a.history.size(), b.history.size());
  EXPECT_NE(a.dynamics.find("PETSc"), std::string::npos);
  ASSERT_EQ(a.frames.size(), b.frames.size());
  const auto& fa = a.frames.back().data.front().second;
  const auto& fb = b.frames.back().data.front().second;
  EXPECT_LE((fa - fb).cwiseAbs().maxCoeff(), tolerance() * fb.cwiseAbs().maxCoeff());
  spec.problem_params = Params::parse("loading=gaussian,engine=petsc,frame=eulerian");
  EXPECT_THROW(run_case(test_catalogue(), spec), InputError);
}

}  // namespace
}  // namespace mfv
