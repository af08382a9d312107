/// Ring particle sets (annulus_lattice): exact polar volumes, stress points, the quads' Gauss
/// cells, jitter, and every registered method discretizing the annulus or refusing it.
#include <cmath>
#include <iostream>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "methods/core/errors.hpp"
#include "test_support.hpp"

namespace mfv {
namespace {

constexpr double kPi = std::numbers::pi;

AnnulusLattice ring(double a, double b, int nr, int nt, double jitter = 0, std::uint64_t seed = 1) {
  AnnulusLattice g;
  g.inner = a;
  g.outer = b;
  g.radial = nr;
  g.circumferential = nt;
  g.jitter = jitter;
  g.seed = seed;
  return g;
}

Domain box_of(const AnnulusLattice& g) {
  return Domain::rectangle(-g.outer, -g.outer, g.outer, g.outer);
}

/// Shoelace area of a quadrilateral given by particle indices.
double shoelace(const ParticleSet& p, const std::array<int, 4>& q) {
  double s = 0;
  for (int k = 0; k < 4; ++k) {
    const auto a = p.x.col(q[k]), b = p.x.col(q[(k + 1) % 4]);
    s += a[0] * b[1] - a[1] * b[0];
  }
  return 0.5 * s;
}

TEST(RingParticles, CountsAndVolumesSumToTheAnnulus) {
  struct Case {
    double a, b;
    int nr, nt, particles, stress_points;
  };
  for (const Case c : {Case{1, 2, 9, 60, 540, 480}, Case{0.5, 3, 13, 80, 1040, 960},
                       Case{2, 2.5, 7, 150, 1050, 900}}) {
    const ParticleSet p = annulus_lattice(ring(c.a, c.b, c.nr, c.nt));
    const double area = kPi * (c.b * c.b - c.a * c.a);
    EXPECT_EQ(p.size(), c.particles);
    EXPECT_EQ(p.dim, 2);
    EXPECT_EQ(p.lattice, Eigen::Vector2i::Zero());
    ASSERT_TRUE(p.stress_points);
    EXPECT_EQ(p.stress_points->x.cols(), c.stress_points);
    EXPECT_EQ(static_cast<int>(p.quads.size()), c.stress_points);
    EXPECT_NEAR(p.volume.sum(), area, 1e-12 * area);
    EXPECT_NEAR(p.stress_points->volume.sum() + p.stress_points->particle_volume.sum(), area,
                1e-12 * area);
    EXPECT_GT(p.volume.minCoeff(), 0);
    EXPECT_GT(p.stress_points->particle_volume.minCoeff(), 0);
  }
}

TEST(RingParticles, SurfaceParticlesCarryHalfCells) {
  const double a = 1, b = 2;
  const int nr = 9, nt = 60;
  const ParticleSet p = annulus_lattice(ring(a, b, nr, nt));
  const double dr = (b - a) / (nr - 1), dt = 2 * kPi / nt;
  for (int j = 0; j < nt; ++j) {
    // Inner surface: r from a to a + Δr/2; outer: b - Δr/2 to b (half the interior cell).
    EXPECT_NEAR(p.volume[j], 0.5 * dt * (std::pow(a + 0.5 * dr, 2) - a * a), 1e-14);
    EXPECT_NEAR(p.volume[j + nt * (nr - 1)], 0.5 * dt * (b * b - std::pow(b - 0.5 * dr, 2)),
                1e-14);
    // An interior ring i: the full cell r_i ± Δr/2, so 2 r_i Δr Δθ / 2 = r_i Δr Δθ.
    for (int i = 1; i + 1 < nr; ++i)
      EXPECT_NEAR(p.volume[j + nt * i], (a + i * dr) * dr * dt, 1e-14);
  }
  // Half a full cell: a surface particle carries Δr/2 of radius, so its volume is half that of
  // a Δr-wide cell at the half cell's mean radius a + Δr/4.
  EXPECT_NEAR(p.volume[0] / ((a + 0.25 * dr) * dr * dt), 0.5, 1e-12);
}

TEST(RingParticles, StressPointsAtPolarCellCentres) {
  const double a = 1, b = 2;
  const int nr = 7, nt = 150;
  const ParticleSet p = annulus_lattice(ring(a, b, nr, nt));
  const double dr = (b - a) / (nr - 1), dt = 2 * kPi / nt;
  const StressPoints& s = *p.stress_points;
  for (int i = 0; i + 1 < nr; ++i)
    for (int j = 0; j < nt; ++j) {
      const int k = j + nt * i;
      const double r = a + (i + 0.5) * dr, t = (j + 0.5) * dt;
      EXPECT_NEAR(s.x(0, k), r * std::cos(t), 1e-14);
      EXPECT_NEAR(s.x(1, k), r * std::sin(t), 1e-14);
      const double cell = 0.5 * dt * (std::pow(a + (i + 1) * dr, 2) - std::pow(a + i * dr, 2));
      EXPECT_NEAR(s.volume[k], 0.5 * cell, 1e-15);
    }
  // An interior particle: A/8 from each of its 4 cells.
  const int J = 5 + nt * 3;
  const auto cell = [&](int i) {
    return 0.5 * dt * (std::pow(a + (i + 1) * dr, 2) - std::pow(a + i * dr, 2));
  };
  EXPECT_NEAR(s.particle_volume[J], 0.25 * (cell(2) + cell(3)), 1e-15);
  // Quads are counter-clockwise (positive shoelace area).
  for (const auto& q : p.quads) EXPECT_GT(shoelace(p, q), 0);
}

TEST(RingParticles, SquareLatticeSplitIsHalfAndEighths) {
  // The split annulus_lattice copies: make_stress_points on a square lattice with quad-centre
  // stress points gives A/2 to each stress point and A/8 per cell to each corner particle.
  const Domain d = Domain::rectangle(0, 0, 1, 1);
  const ParticleSet p = rectangle_lattice(d, 5, 5, Placement::boundary);
  const StressPoints s = make_stress_points(p, d);
  const double A = 0.25 * 0.25;
  for (int k = 0; k < s.volume.size(); ++k) EXPECT_NEAR(s.volume[k], A / 2, 1e-12);
  EXPECT_NEAR(s.particle_volume[0], A / 8, 1e-12);       // corner: one cell
  EXPECT_NEAR(s.particle_volume[1], 2 * A / 8, 1e-12);   // side: two cells
  EXPECT_NEAR(s.particle_volume[6], 4 * A / 8, 1e-12);   // interior: four cells
}

TEST(RingParticles, LocalSpacingAndDilations) {
  const double a = 1, b = 2;
  const int nr = 5, nt = 24;
  const ParticleSet p = annulus_lattice(ring(a, b, nr, nt));
  const double dr = 0.25, dt = 2 * kPi / nt;
  ASSERT_EQ(p.local_spacing.size(), p.size());
  for (int i = 0; i < nr; ++i)
    EXPECT_DOUBLE_EQ(p.local_spacing[nt * i], std::max(dr, (a + i * dr) * dt));
  EXPECT_DOUBLE_EQ(p.spacing, std::max(dr, 1.5 * dt));
  // A method's dilations follow the local spacing: a_J / local_spacing_J is one constant.
  const Discretization d =
      test_catalogue().methods.create("efg")->discretize(box_of(ring(a, b, nr, nt)), p, 1);
  const Eigen::ArrayXd ratio = d.particles.dilation.array() / p.local_spacing.array();
  EXPECT_NEAR(ratio.maxCoeff(), ratio.minCoeff(), 1e-14 * ratio.maxCoeff());
  EXPECT_GT(ratio.minCoeff(), 0);
}

TEST(RingParticles, GaussCellsOnTheQuads) {
  for (const auto& g : {ring(1, 2, 9, 60), ring(1, 2, 5, 24), ring(0.2, 1, 6, 12)}) {
    const ParticleSet p = annulus_lattice(g);
    const IntegrationRule r =
        test_catalogue().integrations.create("gauss-cells")->rule(box_of(g), p);
    const int cells = static_cast<int>(p.quads.size());
    EXPECT_EQ(r.cells, cells);
    EXPECT_EQ(r.size(), 9 * cells);  // eq 66 with m = 1: 3 × 3 per cell
    double polygon = 0;
    for (const auto& q : p.quads) polygon += shoelace(p, q);
    EXPECT_NEAR(r.weights.sum(), polygon, 1e-12 * polygon);
    // The chords cut the circles: O(Δθ²) below the annulus.
    const double area = kPi * (g.outer * g.outer - g.inner * g.inner);
    const double dt = 2 * kPi / g.circumferential;
    const double chord = std::abs(r.weights.sum() - area) / area;
    std::cout << "[ring] " << g.radial << " x " << g.circumferential << ": quads' area "
              << polygon << ", chord error " << chord << " (bound dtheta^2/6 = " << dt * dt / 6
              << ")\n";
    EXPECT_LT(chord, dt * dt / 6);
    // Every Gauss point lies in the annulus.
    const Eigen::ArrayXd radius = r.points.colwise().norm().transpose().array();
    EXPECT_GE(radius.minCoeff(), g.inner * (1 - 1e-12));
    EXPECT_LE(radius.maxCoeff(), g.outer * (1 + 1e-12));
    // nq overrides the point count.
    const IntegrationRule r2 = test_catalogue()
                                   .integrations.create("gauss-cells", Params::parse("nq=2"))
                                   ->rule(box_of(g), p);
    EXPECT_EQ(r2.size(), 4 * cells);
    EXPECT_NEAR(r2.weights.sum(), polygon, 1e-12 * polygon);
  }
}

TEST(RingParticles, StressPointRuleUsesTheSuppliedPoints) {
  const auto g = ring(1, 2, 5, 24);
  const ParticleSet p = annulus_lattice(g);
  const IntegrationRule r =
      test_catalogue().integrations.create("stress-points")->rule(box_of(g), p);
  EXPECT_EQ(r.nodal_points, p.size());
  EXPECT_EQ(r.size(), p.size() + 4 * 24);
  const double area = kPi * 3;
  EXPECT_NEAR(r.weights.sum(), area, 1e-12 * area);
  EXPECT_EQ(r.points.rightCols(4 * 24), p.stress_points->x);
  try {
    test_catalogue()
        .integrations.create("stress-points", Params::parse("layout=triangle-centres"))
        ->rule(box_of(g), p);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("quad-centre stress points"), std::string::npos)
        << e.what();
  }
}

TEST(RingParticles, BoundaryRulesAreRefused) {
  const auto g = ring(1, 2, 5, 24);
  const ParticleSet p = annulus_lattice(g);
  for (const char* scheme : {"nodal", "gauss-cells", "stress-points"}) try {
      test_catalogue().integrations.create(scheme)->boundary_rule(box_of(g), p, 0);
      FAIL() << scheme;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("no box sides"), std::string::npos) << e.what();
    }
  EXPECT_THROW(test_catalogue()
                   .integrations.create("gauss-cells", Params::parse("cells=10"))
                   ->rule(box_of(g), p),
               InputError);
}

TEST(RingParticles, InvertedQuadsAndMismatchedSpacingsAreRefused) {
  const auto g = ring(1, 2, 5, 24);
  ParticleSet p = annulus_lattice(g);
  std::swap(p.quads[3][1], p.quads[3][3]);  // clockwise
  try {
    test_catalogue().integrations.create("gauss-cells")->rule(box_of(g), p);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("quadrilateral cell 3"), std::string::npos) << e.what();
  }
  ParticleSet q = annulus_lattice(g);
  q.local_spacing.conservativeResize(q.size() - 1);
  EXPECT_THROW(test_catalogue().methods.create("efg")->discretize(box_of(g), q, 1), InputError);
}

TEST(RingParticles, JitterIsSeededBoundedAndKeepsSurfaces) {
  const double a = 1, b = 2, jitter = 0.3;
  const int nr = 6, nt = 40;
  const ParticleSet p = annulus_lattice(ring(a, b, nr, nt, jitter, 7));
  const ParticleSet same = annulus_lattice(ring(a, b, nr, nt, jitter, 7));
  const ParticleSet other = annulus_lattice(ring(a, b, nr, nt, jitter, 8));
  const ParticleSet plain = annulus_lattice(ring(a, b, nr, nt));
  EXPECT_EQ(p.x, same.x);
  EXPECT_GT((p.x - other.x).norm(), 1e-3);
  EXPECT_EQ(p.volume, plain.volume);  // volumes of the unjittered lattice
  const double dr = (b - a) / (nr - 1), dt = 2 * kPi / nt;
  double moved = 0;
  for (int i = 0; i < nr; ++i)
    for (int j = 0; j < nt; ++j) {
      const int J = j + nt * i;
      const double r = p.x.col(J).norm(), r0 = a + i * dr;
      double t = std::atan2(p.x(1, J), p.x(0, J)) - j * dt;
      t = std::remainder(t, 2 * kPi);
      if (i == 0 || i == nr - 1) EXPECT_NEAR(r, r0, 1e-14 * r0) << J;
      else EXPECT_LE(std::abs(r - r0), jitter * dr * (1 + 1e-12)) << J;
      EXPECT_LE(std::abs(t), jitter * dt * (1 + 1e-12)) << J;
      moved = std::max(moved, std::abs(t) / dt);
    }
  EXPECT_GT(moved, 0.5 * jitter);  // it did move
  // Cells stay convex enough for the bilinear map.
  const IntegrationRule rule =
      test_catalogue().integrations.create("gauss-cells")->rule(box_of(ring(a, b, nr, nt)), p);
  EXPECT_GT(rule.weights.minCoeff(), 0);
}

TEST(RingParticles, BadInputNamesTheField) {
  const auto expect_refused = [](const AnnulusLattice& g, const std::string& field) {
    try {
      annulus_lattice(g);
      FAIL() << field;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  const double nan = std::nan("");
  expect_refused(ring(0, 2, 5, 24), "inner");
  expect_refused(ring(-1, 2, 5, 24), "inner");
  expect_refused(ring(nan, 2, 5, 24), "inner");
  expect_refused(ring(1, 1, 5, 24), "outer");
  expect_refused(ring(1, nan, 5, 24), "outer");
  expect_refused(ring(1, INFINITY, 5, 24), "outer");
  expect_refused(ring(1, 1e200, 5, 24), "outer");
  expect_refused(ring(1e-200, 2e-200, 5, 24), "outer");
  expect_refused(ring(1, 2, 1, 24), "radial");
  expect_refused(ring(1, 2, 5, 2), "circumferential");
  expect_refused(ring(1, 2, 5, 24, -0.1), "jitter");
  expect_refused(ring(1, 2, 5, 24, 0.5), "jitter");
  expect_refused(ring(1, 2, 5, 24, nan), "jitter");
  expect_refused(ring(1, 2, 100000, 100000), "annulus lattice");
}

/// Every registered method on a 5 × 24 ring: it runs and its gradient table is as consistent
/// as it says, or it refuses the ring with InputError.
class RingConformance : public ::testing::TestWithParam<std::string> {};

TEST_P(RingConformance, RunsConsistentlyOrRefuses) {
  const std::string method = GetParam();
  const auto g = ring(1, 2, 5, 24);
  const ParticleSet p = annulus_lattice(g);
  std::string refusal;
  const auto d = discretize_if_supported(method, {}, box_of(g), p, refusal);
  if (!d) {
    EXPECT_FALSE(refusal.empty());
    std::cout << "[ring] refuses " << refusal << "\n";
    GTEST_SKIP() << refusal;
  }
  std::cout << "[ring] runs " << method << " (" << d->quadrature.kind << ", "
            << d->quadrature.size() << " points, consistency " << d->consistency() << ")\n";
  ASSERT_EQ(d->quadrature.points.cols(), d->trial_q.points());
  const int n = d->particles.size() + d->enriched_unknowns;
  const Eigen::Vector2d A(0.7, -1.3);
  const double c = 0.4;
  Eigen::VectorXd u_lin = Eigen::VectorXd::Zero(n), u_const = Eigen::VectorXd::Zero(n);
  for (int J = 0; J < d->particles.size(); ++J) {
    u_lin[J] = A.dot(d->particles.x.col(J)) + c;
    u_const[J] = c;
  }
  if (d->consistency() >= 0)
    EXPECT_LT(d->gradient(u_const).cwiseAbs().maxCoeff(), 1e-8) << method;
  if (d->consistency() >= 1) {
    const Eigen::MatrixXd grad = d->gradient(u_lin);
    EXPECT_LT((grad.colwise() - A).cwiseAbs().maxCoeff(), 1e-8) << method;
  }
}

INSTANTIATE_TEST_SUITE_P(EveryMethod, RingConformance, ::testing::ValuesIn(registered_methods()),
                         [](const auto& info) { return test_name(info.param); });

TEST(RingConformance, EfgWithStressPoints) {
  const auto g = ring(1, 2, 5, 24);
  std::string refusal;
  const auto d = discretize_if_supported("efg", Params::parse("integration=stress-points"),
                                         box_of(g), annulus_lattice(g), refusal);
  ASSERT_TRUE(d) << refusal;
  EXPECT_EQ(d->quadrature.kind, "stress-points");
  EXPECT_EQ(d->quadrature.size(), 5 * 24 + 4 * 24);
  Eigen::VectorXd u(d->particles.size());
  for (int J = 0; J < u.size(); ++J) u[J] = 2 * d->particles.x(0, J) - d->particles.x(1, J) + 1;
  const Eigen::MatrixXd grad = d->gradient(u);
  EXPECT_LT((grad.colwise() - Eigen::Vector2d(2, -1)).cwiseAbs().maxCoeff(), 1e-8);
}

TEST(RingConformance, RlmWithAFixedRadius) {
  // RLM's symmetric neighbour lists need one dilation for all particles, which the ring's
  // local spacings do not give; a fixed support radius does.
  const auto g = ring(1, 2, 5, 24);
  std::string refusal;
  const auto d = discretize_if_supported("rlm", Params::parse("radius=0.95"), box_of(g),
                                         annulus_lattice(g), refusal);
  ASSERT_TRUE(d) << refusal;
  std::cout << "[ring] runs rlm radius=0.95 (" << d->quadrature.kind << ", consistency "
            << d->consistency() << ")\n";
  Eigen::VectorXd u(d->particles.size()), one = Eigen::VectorXd::Ones(d->particles.size());
  for (int J = 0; J < u.size(); ++J) u[J] = 2 * d->particles.x(0, J) - d->particles.x(1, J) + 1;
  if (d->consistency() >= 0) EXPECT_LT(d->gradient(one).cwiseAbs().maxCoeff(), 1e-8);
  if (d->consistency() >= 1)
    EXPECT_LT((d->gradient(u).colwise() - Eigen::Vector2d(2, -1)).cwiseAbs().maxCoeff(), 1e-8);
}

}  // namespace
}  // namespace mfv
