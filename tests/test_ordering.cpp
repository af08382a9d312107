// Hilbert-curve renumbering (methods/ordering.hpp) and the explicit engine's uses of it and of
// its other scale changes (dynamics/explicit.hpp): ParticleOrder::hilbert gives the fields of
// the given order to round-off, in the engine and through the transient analysis; the forces
// do not depend on the thread count, bit for bit; the Jacobi-preconditioned velocity fit
// gives the incomplete-LU fit's nodal values.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>
#include <gtest/gtest.h>

#include "dynamics/explicit.hpp"
#include "methods/ordering.hpp"
#include "test_support.hpp"
#include "verify/runner.hpp"

namespace mfv {
namespace {

bool is_permutation_of_iota(std::vector<int> p) {
  std::sort(p.begin(), p.end());
  for (int k = 0; k < static_cast<int>(p.size()); ++k)
    if (p[k] != k) return false;
  return true;
}

TEST(Hilbert, ConsecutivePointsOfALatticeAreNeighbours) {
  // On a 2^k × 2^k lattice the curve visits every point once, each step to a side neighbour.
  const int m = 16;
  Eigen::MatrixXd x(2, m * m);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) x.col(i + m * j) << i, j;
  // Shuffled first, so that the input order cannot help.
  std::vector<int> shuffle(m * m);
  std::iota(shuffle.begin(), shuffle.end(), 0);
  std::shuffle(shuffle.begin(), shuffle.end(), std::mt19937_64(3));
  Eigen::MatrixXd y(2, m * m);
  for (int k = 0; k < m * m; ++k) y.col(k) = x.col(shuffle[k]);
  const std::vector<int> order = hilbert_order(y);
  ASSERT_EQ(static_cast<int>(order.size()), m * m);
  EXPECT_TRUE(is_permutation_of_iota(order));
  for (int k = 1; k < m * m; ++k)
    EXPECT_DOUBLE_EQ((y.col(order[k]) - y.col(order[k - 1])).norm(), 1.0) << "step " << k;
}

TEST(Hilbert, OneDimensionIsTheOrderAlongX) {
  const Eigen::MatrixXd x = (Eigen::MatrixXd(1, 5) << 0.3, -1, 2, 0.1, 0.2).finished();
  EXPECT_EQ(hilbert_order(x), (std::vector<int>{1, 3, 4, 0, 2}));
  EXPECT_TRUE(hilbert_order(Eigen::MatrixXd(2, 0)).empty());
}

TEST(Hilbert, RefusesBadPoints) {
  EXPECT_THROW(hilbert_order(Eigen::MatrixXd::Zero(3, 4)), InputError);
  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(2, 3);
  x(1, 2) = NAN;
  EXPECT_THROW(hilbert_order(x), InputError);
  Renumbering bad{{0, 0, 1}, {0, 1, 2}};
  EXPECT_THROW(bad.particle_new(), InputError);
}

Domain rod() { return Domain::rectangle(0, 0, 60, 5); }

TEST(Renumber, TablesFollowTheParticlesAndPoints) {
  // kbm-si: stress points after the particles, test table different from the trial one.
  const auto method = test_catalogue().methods.create("kbm-si");
  const ParticleSet p = rectangle_lattice(rod(), 25, 3, Placement::boundary);
  const Discretization d = method->discretize(rod(), p, 1);
  Discretization r = d;
  const Renumbering ren = hilbert_renumbering(d);
  ASSERT_EQ(ren.point_old.size(), static_cast<std::size_t>(d.quadrature.size()));
  for (int q = 0; q < d.quadrature.nodal_points; ++q) EXPECT_EQ(ren.point_old[q], ren.particle_old[q]);
  renumber(r, ren);
  EXPECT_EQ(r.particles.lattice, Eigen::Vector2i::Zero());
  // A field given in the old numbering, moved to the new: gradients at the points agree
  // exactly (the same entries in the same order), point by point.
  const int n = p.size();
  Eigen::VectorXd u(n), u_new(n);
  for (int I = 0; I < n; ++I) u[I] = std::sin(p.x(0, I)) + p.x(1, I) * p.x(1, I);
  for (int k = 0; k < n; ++k) u_new[k] = u[ren.particle_old[k]];
  const Eigen::MatrixXd g = d.gradient(u), g_new = r.gradient(u_new);
  const Eigen::VectorXd f = d.internal_force(g), f_new = r.internal_force(g_new);
  for (int q = 0; q < d.quadrature.size(); ++q) {
    EXPECT_EQ(g_new.col(q), g.col(ren.point_old[q])) << q;
    EXPECT_EQ(r.quadrature.points.col(q), d.quadrature.points.col(ren.point_old[q]));
  }
  // The force sums in another order: equal to round-off.
  for (int k = 0; k < n; ++k)
    EXPECT_NEAR(f_new[k], f[ren.particle_old[k]], 1e-12 * f.cwiseAbs().maxCoeff());
  EXPECT_EQ(ren.particles_to_old(r.particles.x), d.particles.x);
  // A renumbering that does not fit is refused.
  Renumbering wrong = ren;
  std::swap(wrong.point_old[0], wrong.point_old.back());
  Discretization r2 = d;
  EXPECT_THROW(renumber(r2, wrong), InputError);
}

/// The 2D rod of bench_dynamics (60 × 5 mm steel, the Gaussian pulse), nx × ny particles.
struct Rod {
  std::unique_ptr<Method> method;
  ParticleSet particles;
  std::unique_ptr<ExplicitDynamics> sim;

  Rod(const std::string& name, int nx, int ny, DynamicsOptions opt, bool driven = true) {
    method = test_catalogue().methods.create(name);
    particles = rectangle_lattice(rod(), nx, ny, Placement::boundary);
    DynamicsModel model;
    Params mp;
    mp.set("E", 210.0);
    mp.set("nu", 0.0);
    model.material = test_catalogue().materials.create("svk", mp);
    model.density = 7.8e-6;
    model.mass = lumped_masses(particles, model.density, MassLumping::volume);
    // The left end driven for a while: prescribed particles are named by index.
    for (int I = 0; I < particles.size() && driven; ++I)
      if (particles.sides[I] & Side::left) model.prescribed.push_back({I, 0, 0.5, 2e-4});
    sim = std::make_unique<ExplicitDynamics>(*method, method->discretize(rod(), particles, 1),
                                             model, opt);
    Eigen::MatrixXd v = Eigen::MatrixXd::Zero(2, particles.size());
    for (int I = 0; I < particles.size(); ++I)
      v(0, I) = std::exp(-0.025 * std::pow(particles.x(0, I) - 30, 2));
    sim->set_particle_velocity(v);
  }
  void run(int steps) {
    const double dt = 0.5 * particles.spacing / std::sqrt(210 / 7.8e-6);
    for (int s = 0; s < steps; ++s) sim->step(dt);
  }
};

double relative_gap(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(a.cwiseAbs().maxCoeff(), 1e-300);
}

class HilbertEngine : public ::testing::TestWithParam<std::string> {};

TEST_P(HilbertEngine, GivesTheFieldsOfTheGivenOrderToRoundOff) {
  DynamicsOptions given, hilbert;
  hilbert.order = ParticleOrder::hilbert;
  Rod a(GetParam(), 61, 6, given), b(GetParam(), 61, 6, hilbert);
  a.run(60);
  b.run(60);
  EXPECT_NE(b.sim->description().find("Hilbert"), std::string::npos);
  // 60 steps of sums in another order: differences of a few hundred ulps at most.
  constexpr double kRoundOff = 1e-11;
  EXPECT_LT(relative_gap(a.sim->particle_velocity(), b.sim->particle_velocity()), kRoundOff);
  EXPECT_LT(relative_gap(a.sim->particle_displacement(), b.sim->particle_displacement()),
            kRoundOff);
  EXPECT_LT(relative_gap(a.sim->point_cauchy_stress(), b.sim->point_cauchy_stress()), kRoundOff);
  EXPECT_LT(relative_gap(a.sim->velocity(), b.sim->velocity()), kRoundOff);
  EXPECT_NEAR(a.sim->energy().balance(), b.sim->energy().balance(),
              kRoundOff * a.sim->energy().initial);
  // The driven end moved with its prescribed velocity in both.
  EXPECT_GT(a.sim->particle_displacement().row(0).maxCoeff(), 0);
  // And the engine really moved something: the run is not trivially equal.
  EXPECT_GT(relative_gap(a.sim->particle_velocity(), Eigen::MatrixXd::Zero(2, a.particles.size())),
            0.5);
}

INSTANTIATE_TEST_SUITE_P(Rod, HilbertEngine, ::testing::Values("sph", "kbm-si", "efg-ni"));

TEST(HilbertEngine, RefusesTheEulerianFrameAndUnknownNames) {
  DynamicsOptions opt;
  opt.order = ParticleOrder::hilbert;
  opt.frame = KernelFrame::eulerian;
  EXPECT_THROW(Rod("sph", 25, 3, opt), InputError);
  EXPECT_THROW(particle_order_from("morton"), InputError);
  EXPECT_EQ(particle_order_from("none"), ParticleOrder::as_given);
}

TEST(ExplicitForces, DoNotDependOnTheThreadCount) {
  // 241 × 21 = 5,061 points: above the parallel threshold, so two threads split the points
  // and the terms of the particles on their boundary are deferred. In the Eulerian frame one
  // thread scatters the forces from the point table (no transposed copy per recomputation)
  // and two gather them from the copy: the same sums in the same order, bit for bit.
  for (const KernelFrame frame : {KernelFrame::lagrangian, KernelFrame::eulerian})
    for (const char* name : {"sph", "kbm-si"}) {
      DynamicsOptions one, two;
      one.threads = 1;
      two.threads = 2;
      one.frame = two.frame = frame;
      Rod a(name, 241, 21, one), b(name, 241, 21, two);
      a.run(20);
      b.run(20);
      const bool eulerian = frame == KernelFrame::eulerian;
      EXPECT_EQ(a.sim->velocity(), b.sim->velocity()) << name << (eulerian ? " eulerian" : "");
      EXPECT_EQ(a.sim->displacement(), b.sim->displacement()) << name;
      EXPECT_EQ(a.sim->energy().internal_work, b.sim->energy().internal_work) << name;
    }
}

TEST(VelocityFit, GivesTheIncompleteLuNodalValues) {
  // The fit before issue 17: BiCGSTAB with IncompleteLUT on N_J(X_I), tolerance 1e-12.
  for (const char* name : {"kbm-si", "efg-ni"}) {
    Rod r(name, 61, 6, DynamicsOptions{}, false);
    const ShapeTable t = r.sim->discretization().trial_at(r.particles.x, 0);
    const int n = r.particles.size();
    std::vector<Eigen::Triplet<double>> trip;
    for (int I = 0; I < n; ++I)
      for (int e = t.offsets[I]; e < t.offsets[I + 1]; ++e) trip.emplace_back(I, t.index[e], t.value[e]);
    Eigen::SparseMatrix<double> A(n, n);
    A.setFromTriplets(trip.begin(), trip.end());
    Eigen::BiCGSTAB<Eigen::SparseMatrix<double>, Eigen::IncompleteLUT<double>> ilut;
    ilut.setTolerance(1e-12);
    ilut.compute(A);
    Eigen::VectorXd v(n);
    for (int I = 0; I < n; ++I) v[I] = std::exp(-0.025 * std::pow(r.particles.x(0, I) - 30, 2));
    const Eigen::VectorXd c = ilut.solve(v);
    ASSERT_EQ(ilut.info(), Eigen::Success);
    Eigen::VectorXd fitted(n);
    for (int I = 0; I < n; ++I) fitted[I] = r.sim->velocity()[2 * I];
    EXPECT_LT((fitted - c).cwiseAbs().maxCoeff(), 1e-10 * c.cwiseAbs().maxCoeff()) << name;
    // And the field at the particles is the given one.
    EXPECT_LT((r.sim->particle_velocity().row(0).transpose() - v).cwiseAbs().maxCoeff(), 1e-10);
    // Not trivially: the nodal values differ from the particle values.
    EXPECT_GT((c - v).cwiseAbs().maxCoeff(), 1e-4) << name;
  }
}

TEST(HilbertAnalysis, ErrorsAreThoseOfTheGivenOrder) {
  // Through the transient analysis (reorder=hilbert): the rod names its driven particles by
  // index, the rubber ring its loaded inner surface as particles 0 … n_θ − 1 (a follower
  // pressure); the measures agree to round-off.
  struct Row {
    const char* problem;
    const char* method;
    int nodes;
    const char* params;
  };
  for (const Row& row : {Row{"rod-pulse", "sph", 61, "frames=0,samples=20"},
                         Row{"rod-pulse", "kbm-si", 61, "frames=0,samples=20"},
                         Row{"rubber-ring", "kbm-si", 540, "frame=lagrangian,frames=0"}}) {
    const char* method = row.method;
    CaseSpec s;
    s.problem = row.problem;
    s.method = method;
    s.nodes = row.nodes;
    s.problem_params = Params::parse(row.params);
    const CaseResult a = run_case(test_catalogue(), s);
    s.problem_params = Params::parse(std::string(row.params) + ",reorder=hilbert");
    const CaseResult b = run_case(test_catalogue(), s);
    ASSERT_FALSE(a.headline.empty());
    for (const auto& [k, v] : a.headline) {
      if (k.find("CPU") != std::string::npos || k.find("cpu") != std::string::npos) continue;
      ASSERT_TRUE(b.headline.count(k)) << k;
      if (std::isnan(v)) {  // not measured (a detector that did not fire) in both
        EXPECT_TRUE(std::isnan(b.headline.at(k))) << method << " " << k;
        continue;
      }
      EXPECT_NEAR(b.headline.at(k), v, 1e-9 * std::max(1.0, std::abs(v))) << method << " " << k;
    }
    if (std::isnan(a.errors.l2_rel))
      EXPECT_TRUE(std::isnan(b.errors.l2_rel)) << method;
    else
      EXPECT_NEAR(b.errors.l2_rel, a.errors.l2_rel, 1e-9) << method;
    EXPECT_NE(b.data<TransientData>().dynamics.find("Hilbert"), std::string::npos);
  }
}

}  // namespace
}  // namespace mfv
