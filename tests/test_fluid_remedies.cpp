// The fluid remedies of issue 43 (dynamics/fluid_remedies.hpp): each operator does what its
// formula says on a small cloud (the kernel's normalization and derivative; the density filters
// keep what their order reproduces and damp a checkerboard; the density diffusion moves density
// without creating any, damps a checkerboard, and in Antuono's form leaves a linear density
// alone; shifting leaves a uniform lattice in place and moves a displaced particle back), the
// engine's options are off by default and refused where they cannot act, and the funnel's wall
// particles (walls=particles) sit outside its walls.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "analyses/case.hpp"
#include "dynamics/explicit.hpp"
#include "dynamics/fluid_remedies.hpp"
#include "problems/funnel_measures.hpp"
#include "test_support.hpp"
#include "verify/runner.hpp"

namespace mfv {
namespace {

/// A square lattice of n × n points of spacing dx (x fastest), volumes dx².
Eigen::MatrixXd square(int n, double dx) {
  Eigen::MatrixXd x(2, n * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) x.col(i + n * j) = Eigen::Vector2d(i * dx, j * dx);
  return x;
}

/// The points at least `margin` from the lattice's edges (full supports).
std::vector<int> interior(int n, int margin) {
  std::vector<int> out;
  for (int j = margin; j < n - margin; ++j)
    for (int i = margin; i < n - margin; ++i) out.push_back(i + n * j);
  return out;
}

TEST(FluidRemedies, WendlandKernelIsNormalizedAndItsDerivativeIsRight) {
  // ∫ W = 1 in 2D (a fine lattice sum), W = 0 from 2h, dW/dr against central differences.
  const double h = 1.0, dx = 0.02;
  double sum = 0;
  for (int i = -120; i <= 120; ++i)
    for (int j = -120; j <= 120; ++j) sum += remedies::kernel(std::hypot(i * dx, j * dx), h);
  EXPECT_NEAR(sum * dx * dx, 1.0, 1e-6);
  EXPECT_EQ(remedies::kernel(2.0, h), 0.0);
  EXPECT_EQ(remedies::kernel(2.5, h), 0.0);
  for (double r : {0.1, 0.7, 1.3, 1.9}) {
    double dw = 0;
    remedies::kernel(r, h, &dw);
    const double e = 1e-6;
    EXPECT_NEAR(dw, (remedies::kernel(r + e, h) - remedies::kernel(r - e, h)) / (2 * e), 1e-7)
        << r;
  }
}

TEST(FluidRemedies, DensityDiffusionMovesDensityAndCreatesNone) {
  // An irregular cloud with random densities: Σ_i V_i D_i = 0 to round-off, in both forms (ψ_ij
  // is symmetric, ∇_i W_ij antisymmetric).
  const int n = 14;
  const double dx = 0.01, h = kRemedySmoothing * dx, c0 = 50, rho0 = 1000;
  Eigen::MatrixXd x = square(n, dx);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  for (Eigen::Index k = 0; k < x.size(); ++k) x.data()[k] += u(rng) * dx;
  Eigen::VectorXd V(n * n), rho(n * n);
  for (int k = 0; k < n * n; ++k) {
    V[k] = dx * dx * (1 + u(rng));
    rho[k] = rho0 * (1 + 0.01 * u(rng));
  }
  for (DiffusionForm form : {DiffusionForm::molteni, DiffusionForm::antuono}) {
    const Eigen::VectorXd D = remedies::density_diffusion(x, V, rho, h, c0, 0.1, form);
    const double scale = V.cwiseProduct(D.cwiseAbs()).sum();
    ASSERT_GT(scale, 0);
    EXPECT_LT(std::abs(V.dot(D)), 1e-12 * scale);
  }
}

TEST(FluidRemedies, DensityDiffusionDampsACheckerboardAndSparesALinearDensity) {
  const int n = 16;
  const double dx = 0.01, h = kRemedySmoothing * dx, c0 = 50, rho0 = 1000, eps = 1e-3;
  const Eigen::MatrixXd x = square(n, dx);
  const Eigen::VectorXd V = Eigen::VectorXd::Constant(n * n, dx * dx);
  Eigen::VectorXd board(n * n), linear(n * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      board[i + n * j] = rho0 * (1 + eps * ((i + j) % 2 ? -1 : 1));
      linear[i + n * j] = rho0 * (1 + 0.01 * (0.3 * i - 0.7 * j));
    }
  // A checkerboard: D opposes the perturbation at every interior point, and one explicit step
  // at the fluid problems' size of step (0.8 Δx/c0) shrinks it without overshooting.
  const double dt = 0.8 * dx / c0;
  for (DiffusionForm form : {DiffusionForm::molteni, DiffusionForm::antuono}) {
    const Eigen::VectorXd D = remedies::density_diffusion(x, V, board, h, c0, 0.1, form);
    for (int k : interior(n, 3)) {
      const double pert = board[k] - rho0;
      EXPECT_LT(D[k] * pert, 0) << k;
      const double after = board[k] + dt * D[k] - rho0;
      EXPECT_LT(std::abs(after), std::abs(pert)) << k;
      EXPECT_GT(after * pert, 0) << k;
    }
  }
  // A linear density: Antuono's term vanishes everywhere, edges included (the renormalized
  // gradient is exact there); Molteni's does not at the edges, where the support is one-sided.
  const Eigen::VectorXd Da =
      remedies::density_diffusion(x, V, linear, h, c0, 0.1, DiffusionForm::antuono);
  const Eigen::VectorXd Dm =
      remedies::density_diffusion(x, V, linear, h, c0, 0.1, DiffusionForm::molteni);
  EXPECT_LT(Da.cwiseAbs().maxCoeff(), 1e-9 * Dm.cwiseAbs().maxCoeff());
  EXPECT_GT(Dm.cwiseAbs().maxCoeff(), 0.0);
  for (int k : interior(n, 3)) EXPECT_LT(std::abs(Dm[k]), 1e-9 * Dm.cwiseAbs().maxCoeff()) << k;
}

TEST(FluidRemedies, DensityFiltersKeepWhatTheyReproduceAndDampACheckerboard) {
  const int n = 12;
  const double dx = 0.01, h = kRemedySmoothing * dx, rho0 = 1000;
  Eigen::MatrixXd x = square(n, dx);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  for (Eigen::Index k = 0; k < x.size(); ++k) x.data()[k] += u(rng) * dx;
  const Eigen::VectorXd V = Eigen::VectorXd::Constant(n * n, dx * dx);
  Eigen::VectorXd constant = Eigen::VectorXd::Constant(n * n, rho0), linear(n * n), board(n * n);
  for (int k = 0; k < n * n; ++k) {
    linear[k] = rho0 * (1 + 2 * x(0, k) - 3 * x(1, k));
    const int i = k % n, j = k / n;
    board[k] = rho0 * (1 + 1e-3 * ((i + j) % 2 ? -1 : 1));
  }
  // Shepard keeps a constant; MLS a linear density, at every point (edges included).
  const Eigen::VectorXd s = remedies::filtered_density(x, V, constant, h, DensityFilter::shepard);
  EXPECT_LT((s - constant).cwiseAbs().maxCoeff(), 1e-10 * rho0);
  const Eigen::VectorXd m = remedies::filtered_density(x, V, linear, h, DensityFilter::mls);
  EXPECT_LT((m - linear).cwiseAbs().maxCoeff(), 1e-9 * rho0);
  const Eigen::VectorXd sl = remedies::filtered_density(x, V, linear, h, DensityFilter::shepard);
  EXPECT_GT((sl - linear).cwiseAbs().maxCoeff(), 1e-4 * rho0);  // zeroth order: edges move
  // Both take most of a checkerboard out at the interior points.
  for (DensityFilter f : {DensityFilter::shepard, DensityFilter::mls}) {
    const Eigen::VectorXd b = remedies::filtered_density(x, V, board, h, f);
    for (int k : interior(n, 3))
      EXPECT_LT(std::abs(b[k] - rho0), 0.5 * std::abs(board[k] - rho0)) << k;
  }
  // off is the identity.
  EXPECT_EQ(remedies::filtered_density(x, V, board, h, DensityFilter::off), board);
}

TEST(FluidRemedies, ShiftingLeavesAUniformLatticeInPlaceAndMovesADisplacedParticleBack) {
  const int n = 12;
  const double dx = 0.01, h = kRemedySmoothing * dx;
  Eigen::MatrixXd x = square(n, dx);
  const std::vector<char> none;
  // The uniform lattice: interior particles feel no gradient, the edges' and corners' is
  // normal to them and is removed (C < 0.95 there): nothing moves.
  const Eigen::VectorXd C = remedies::concentration(x, h, dx);
  EXPECT_NEAR(C[5 + n * 5], 1.018, 2e-3);
  EXPECT_NEAR(C[5], 0.823, 2e-3);  // an edge
  const Eigen::MatrixXd still = remedies::shifts(x, h, dx, 0.5, 0.95, none);
  EXPECT_LT(still.cwiseAbs().maxCoeff(), 1e-12 * dx);
  // An interior particle displaced by 0.1 Δx moves back towards its site, by about 0.9 D of
  // its offset (0.88 D for a small offset: Wendland, h = 1.2 Δx), without overshooting.
  const int k = 6 + n * 6;
  const Eigen::Vector2d off(0.06 * dx, -0.08 * dx);
  x.col(k) += off;
  const Eigen::MatrixXd back = remedies::shifts(x, h, dx, 0.1, 0.95, none);
  EXPECT_LT(back.col(k).dot(off), 0);
  EXPECT_GT(back.col(k).norm(), 0.07 * off.norm());
  EXPECT_LT(back.col(k).norm(), 0.12 * off.norm());
  // Held particles do not move; the cap holds at a large D; a wall's normal component goes.
  std::vector<char> held(n * n, 0);
  held[k] = 1;
  EXPECT_TRUE(remedies::shifts(x, h, dx, 0.1, 0.95, held).col(k).isZero());
  x.col(k) += Eigen::Vector2d(0.3 * dx, 0);
  const Eigen::MatrixXd big = remedies::shifts(x, h, dx, 1.0, 0.95, none);
  EXPECT_LE(big.colwise().norm().maxCoeff(), kMaxShift * dx * (1 + 1e-12));
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(2, n * n);
  normal(0, k) = 1;
  const Eigen::MatrixXd walled = remedies::shifts(x, h, dx, 0.1, 0.95, none, normal);
  EXPECT_NEAR(walled(0, k), 0.0, 1e-15);
}

TEST(FluidRemedies, XuShiftingPartsAClosePairAndLeavesALatticeInPlace) {
  // Xu et al.'s repulsion: the uniform lattice's interior does not move (symmetric
  // neighbours), its edges shift only tangentially, which leaves a residual below 0.005 Δx
  // next to the corners (there ∇C, whose component goes, and the repulsion point differently);
  // a particle added 0.01 Δx from another parts them along their line (the Fickian shift's
  // ∇C vanishes there, W′(0) = 0), capped at 0.1 Δx.
  const int n = 12;
  const double dx = 0.01, h = kRemedySmoothing * dx, alpha = 0.05 * dx;
  Eigen::MatrixXd x = square(n, dx);
  const std::vector<char> none;
  const Eigen::MatrixXd still =
      remedies::shifts(x, h, dx, 0.05, 0.95, none, {}, ShiftingForm::xu, alpha);
  for (int k : interior(n, 3)) EXPECT_LT(still.col(k).norm(), 1e-12 * dx) << k;
  EXPECT_LT(still.colwise().norm().maxCoeff(), 0.005 * dx);
  const int a = 5 + n * 5;
  Eigen::MatrixXd y(2, n * n + 1);
  y << x, x.col(a) + Eigen::Vector2d(0.01 * dx, 0);
  const int b = n * n;
  const Eigen::MatrixXd xu =
      remedies::shifts(y, h, dx, 0.05, 0.95, none, {}, ShiftingForm::xu, alpha);
  EXPECT_LT(xu(0, a), -0.05 * dx);
  EXPECT_GT(xu(0, b), 0.05 * dx);
  EXPECT_LE(xu.colwise().norm().maxCoeff(), kMaxShift * dx * (1 + 1e-12));
  const Eigen::MatrixXd fick = remedies::shifts(y, h, dx, 0.05, 0.95, none);
  EXPECT_LT(std::abs(fick(0, b) - fick(0, a)), 0.01 * std::abs(xu(0, b) - xu(0, a)));
  EXPECT_EQ(shifting_form_from("xu"), ShiftingForm::xu);
  EXPECT_THROW(shifting_form_from("ficks"), InputError);
}

TEST(FluidRemedies, OptionsAreOffByDefaultAndBadOnesAreInputErrors) {
  const FluidRemedies off;
  EXPECT_FALSE(off.any());
  EXPECT_EQ(off.description(), "");
  EXPECT_THROW(density_filter_from("gauss"), InputError);
  EXPECT_THROW(diffusion_form_from("fick"), InputError);
  auto message = [](const std::string& params) {
    CaseSpec s;
    s.problem = "hydrostatic-column";
    s.method = "sph";
    s.nodes = 4;
    s.problem_params = Params::parse("walls=plain,crossings=0.2,average_crossings=0.1,frames=0," + params);
    try {
      run_case(test_catalogue(), s);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no InputError");
  };
  // Each message names the parameter.
  EXPECT_NE(message("frame=eulerian,density_diffusion=2").find("density_diffusion"),
            std::string::npos);
  EXPECT_NE(message("frame=eulerian,density_diffusion=-0.1").find("density_diffusion"),
            std::string::npos);
  EXPECT_NE(message("frame=eulerian,shifting=3").find("shifting"), std::string::npos);
  EXPECT_NE(message("frame=eulerian,shifting=0.1,shifting_surface=5").find("shifting_surface"),
            std::string::npos);
  EXPECT_NE(message("frame=eulerian,density_filter=box").find("density_filter"),
            std::string::npos);
  // The Lagrangian kernel recomputes F from u: the remedies are refused there.
  EXPECT_NE(message("frame=lagrangian,density_filter=shepard").find("frame=eulerian"),
            std::string::npos);
}

TEST(FluidRemedies, AColumnRunsWithEveryRemedyAndStaysNearRest) {
  // kbm-si, 4 × 8 particles, Eulerian, a few sound crossings with each remedy: finite, and
  // the water stays near rest (the remedies move density, not the column).
  for (const char* remedy : {"density_filter=shepard,density_filter_every=5",
                             "density_filter=mls,density_filter_every=5", "density_diffusion=0.1",
                             "shifting=0.1"}) {
    CaseSpec s;
    s.problem = "hydrostatic-column";
    s.method = "kbm-si";
    s.nodes = 4;
    s.problem_params =
        Params::parse(
        std::string("frame=eulerian,crossings=3,average_crossings=1,frames=0,samples=10,") +
        remedy);
    const CaseResult r = run_case(test_catalogue(), s);
    const TransientData& t = r.data<TransientData>();
    EXPECT_FALSE(t.instability.has_value()) << remedy << ": " << t.verdict();
    EXPECT_LT(r.headline.at("max density deviation"), 0.01) << remedy;
    EXPECT_LT(r.headline.at("peak kinetic energy / MgH"), 1e-3) << remedy;
    EXPECT_TRUE(t.dynamics.find("density") != std::string::npos ||
                t.dynamics.find("shifting") != std::string::npos)
        << remedy << ": the description names the remedy (" << t.dynamics << ")";
  }
}

TEST(FunnelWallParticles, OutsideTheWallsInWholeCells) {
  const funnel::Geometry g;
  const double dx = 0.005;
  const ParticleSet water = funnel::funnel_lattice(g, 0.25, dx);
  const ParticleSet walled = funnel::funnel_lattice(g, 0.25, dx, 2000000, 3);
  const int nw = water.size();
  ASSERT_GT(walled.size(), nw + 300);
  // The water comes first, unchanged.
  EXPECT_TRUE(walled.x.leftCols(nw) == water.x);
  const auto walls = funnel::wall_segments(g);
  for (int I = nw; I < walled.size(); ++I) {
    const Eigen::Vector2d p = walled.x.col(I);
    EXPECT_FALSE(funnel::inside(g, p)) << I;
    double d = INFINITY;
    for (const auto& w : walls) d = std::min(d, (p - RigidWall{w[0], w[1]}.nearest(p)).norm());
    EXPECT_GE(d, 0.5 * dx * (1 - 1e-9)) << I;
    EXPECT_LT(d, 3 * dx) << I;
  }
  for (int I = 0; I < nw; ++I) EXPECT_TRUE(funnel::inside(g, walled.x.col(I))) << I;
  // No cell joins water and wall particles across a 45° wall; the volumes still add up.
  for (const auto& q : walled.quads) {
    int in = 0;
    for (int J : q) in += J < nw;
    if (in != 0 && in != 4) {
      // Only at the vertical walls, where the stress point sits on the wall line.
      const Eigen::Vector2d c = 0.25 * (walled.x.col(q[0]) + walled.x.col(q[1]) +
                                        walled.x.col(q[2]) + walled.x.col(q[3]));
      EXPECT_NEAR(std::abs(c.x()), 0.5 * g.width(g.cone), 1e-12) << c.transpose();
    }
  }
  EXPECT_NEAR(walled.stress_points->particle_volume.sum() + walled.stress_points->volume.sum(),
              walled.volume.sum(), 1e-12);
  EXPECT_THROW(funnel::funnel_lattice(g, 0.25, dx, 2000000, 11), InputError);
}

TEST(FunnelWallParticles, ShortRunDrainsWaterWithFiniteFields) {
  // As FunnelProblem.ShortRunDrainsWaterWithFiniteFields, over wall particles.
  CaseSpec s;
  s.problem = "funnel";
  s.method = "sph";
  s.nodes = 4;
  s.problem_params =
      Params::parse("frame=eulerian,end_time=0.06,frames=0,samples=20,walls=particles");
  const CaseResult r = run_case(test_catalogue(), s);
  const TransientData& t = r.data<TransientData>();
  EXPECT_FALSE(t.instability.has_value()) << t.verdict();
  EXPECT_GT(r.headline.at("drained fraction"), 0.005);
  EXPECT_LT(r.headline.at("drained fraction"), 0.2);
  EXPECT_EQ(r.headline.at("drained fraction"), r.headline.at("drained fraction at time reached"));
  EXPECT_GT(r.headline.at("density min / rho0"), 0.9);
  EXPECT_LT(r.headline.at("density max / rho0"), 1.1);
}

}  // namespace
}  // namespace mfv
