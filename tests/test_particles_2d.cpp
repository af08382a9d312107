/// 2D particle sets: rectangle lattices, voro++ Voronoi areas and stress points (001 eq 65).
#include <gtest/gtest.h>

#include <random>

#include "methods/core/errors.hpp"
#include "methods/particles.hpp"

namespace mfv {
namespace {

const Domain kRect = Domain::rectangle(-1.0, 2.0, 3.0, 5.0);  // 4 × 3, off the origin

/// Exact lattice volume of particle (i, j) of an unperturbed boundary-placement lattice.
double exact_boundary_volume(int i, int j, int nx, int ny, double dx, double dy) {
  return ((i == 0 || i == nx - 1) ? 0.5 : 1.0) * ((j == 0 || j == ny - 1) ? 0.5 : 1.0) * dx * dy;
}

TEST(Lattice2D, BoundaryPlacementPositionsSidesAndOrdering) {
  const int nx = 5, ny = 4;
  const ParticleSet p = rectangle_lattice(kRect, nx, ny, Placement::boundary);
  ASSERT_EQ(p.size(), nx * ny);
  EXPECT_EQ(p.dim, 2);
  EXPECT_EQ(p.lattice, Eigen::Vector2i(nx, ny));
  EXPECT_EQ(p.placement, Placement::boundary);
  EXPECT_DOUBLE_EQ(p.spacing, 1.0);
  EXPECT_TRUE((p.dilation.array() == p.spacing).all());
  EXPECT_NEAR((p.x.col(0) - Eigen::Vector2d(-1, 2)).norm(), 0, 1e-14);
  EXPECT_NEAR((p.x.col(nx - 1) - Eigen::Vector2d(3, 2)).norm(), 0, 1e-14);
  EXPECT_NEAR((p.x.col(nx * (ny - 1)) - Eigen::Vector2d(-1, 5)).norm(), 0, 1e-14);
  EXPECT_NEAR((p.x.col(nx * ny - 1) - Eigen::Vector2d(3, 5)).norm(), 0, 1e-14);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int J = i + nx * j;
      EXPECT_NEAR(p.x(0, J), -1.0 + i * 1.0, 1e-14);
      EXPECT_NEAR(p.x(1, J), 2.0 + j * 1.0, 1e-14);
      const unsigned want = (i == 0 ? Side::left : 0u) | (i == nx - 1 ? Side::right : 0u) |
                            (j == 0 ? Side::bottom : 0u) | (j == ny - 1 ? Side::top : 0u);
      EXPECT_EQ(p.sides[J], want) << "particle " << J;
      EXPECT_NEAR(p.volume[J], exact_boundary_volume(i, j, nx, ny, 1.0, 1.0), 1e-14);
    }
  EXPECT_EQ(p.sides[0], Side::left | Side::bottom);
  EXPECT_EQ(p.sides[nx + 2], 0u);
  EXPECT_DOUBLE_EQ(p.volume[0], 0.25);
  EXPECT_DOUBLE_EQ(p.volume[1], 0.5);
  EXPECT_DOUBLE_EQ(p.volume[nx + 1], 1.0);
  EXPECT_NEAR(p.volume.sum(), kRect.measure(), 1e-12);
}

TEST(Lattice2D, InsetPlacementEqualVolumes) {
  const int nx = 8, ny = 6;
  const ParticleSet p = rectangle_lattice(kRect, nx, ny, Placement::inset);
  ASSERT_EQ(p.size(), nx * ny);
  EXPECT_EQ(p.placement, Placement::inset);
  EXPECT_DOUBLE_EQ(p.spacing, 0.5);
  EXPECT_NEAR(p.x(0, 0), -1.0 + 0.25, 1e-14);
  EXPECT_NEAR(p.x(1, 0), 2.0 + 0.25, 1e-14);
  EXPECT_NEAR(p.x(0, nx * ny - 1), 3.0 - 0.25, 1e-14);
  EXPECT_NEAR(p.x(1, nx * ny - 1), 5.0 - 0.25, 1e-14);
  EXPECT_NEAR(p.x(0, 3 + nx * 2), -1.0 + 3.5 * 0.5, 1e-14);
  EXPECT_NEAR(p.x(1, 3 + nx * 2), 2.0 + 2.5 * 0.5, 1e-14);
  EXPECT_EQ(p.sides[0], Side::left | Side::bottom);
  EXPECT_EQ(p.sides[nx * ny - 1], Side::right | Side::top);
  EXPECT_EQ(p.sides[3 + nx * 2], 0u);
  EXPECT_NEAR(p.volume.maxCoeff(), 0.25, 1e-14);
  EXPECT_NEAR(p.volume.minCoeff(), 0.25, 1e-14);
  EXPECT_NEAR(p.volume.sum(), kRect.measure(), 1e-12);
}

TEST(Lattice2D, PerturbedKeepsSidesCornersAndBounds) {
  const int nx = 9, ny = 7;
  const double pert = 0.3;
  const ParticleSet ref = rectangle_lattice(kRect, nx, ny, Placement::boundary);
  const ParticleSet p = rectangle_lattice(kRect, nx, ny, Placement::boundary, pert, 42);
  const double dx = 4.0 / (nx - 1), dy = 3.0 / (ny - 1);
  int moved = 0;
  for (int J = 0; J < p.size(); ++J) {
    const Eigen::Vector2d d = p.x.col(J) - ref.x.col(J);
    EXPECT_LE(std::abs(d[0]), pert * dx + 1e-14);
    EXPECT_LE(std::abs(d[1]), pert * dy + 1e-14);
    if (p.sides[J] & (Side::left | Side::right)) {
      EXPECT_EQ(d[0], 0.0) << "particle " << J;
    }
    if (p.sides[J] & (Side::bottom | Side::top)) {
      EXPECT_EQ(d[1], 0.0) << "particle " << J;
    }
    if (d.norm() > 1e-3 * dx) ++moved;
  }
  EXPECT_GT(moved, (nx - 2) * (ny - 2) / 2);
  for (int corner : {0, nx - 1, nx * (ny - 1), nx * ny - 1})
    EXPECT_EQ((p.x.col(corner) - ref.x.col(corner)).norm(), 0.0);
  EXPECT_TRUE((p.volume.array() > 0).all());
  EXPECT_NEAR(p.volume.sum(), kRect.measure(), 1e-10 * kRect.measure());
  EXPECT_GT((p.volume - ref.volume).norm(), 1e-3);

  const ParticleSet same = rectangle_lattice(kRect, nx, ny, Placement::boundary, pert, 42);
  const ParticleSet other = rectangle_lattice(kRect, nx, ny, Placement::boundary, pert, 43);
  EXPECT_EQ((same.x - p.x).norm(), 0.0);
  EXPECT_GT((other.x - p.x).norm(), 1e-3);
}

TEST(Lattice2D, PerturbedInsetMovesEveryParticleInside) {
  const int nx = 6, ny = 5;
  const ParticleSet ref = rectangle_lattice(kRect, nx, ny, Placement::inset);
  const ParticleSet p = rectangle_lattice(kRect, nx, ny, Placement::inset, 0.45, 7);
  for (int J = 0; J < p.size(); ++J) {
    const Eigen::Vector2d d = p.x.col(J) - ref.x.col(J);
    EXPECT_LE(std::abs(d[0]), 0.45 * ref.spacing + 1e-14);
    EXPECT_GT(d.cwiseAbs().minCoeff(), 0.0) << "particle " << J;
    EXPECT_TRUE(p.x(0, J) > -1 && p.x(0, J) < 3 && p.x(1, J) > 2 && p.x(1, J) < 5);
  }
  EXPECT_NEAR(p.volume.sum(), kRect.measure(), 1e-10 * kRect.measure());
}

TEST(Lattice2D, BadInputsThrow) {
  EXPECT_THROW(rectangle_lattice(kRect, 1, 4, Placement::boundary), InputError);
  EXPECT_THROW(rectangle_lattice(kRect, 4, 1, Placement::boundary), InputError);
  EXPECT_NO_THROW(rectangle_lattice(kRect, 1, 1, Placement::inset));
  EXPECT_THROW(rectangle_lattice(kRect, 0, 3, Placement::inset), InputError);
  EXPECT_THROW(rectangle_lattice(Domain::interval(0, 1), 4, 4, Placement::boundary),
               InputError);
  EXPECT_THROW(rectangle_lattice(kRect, 4, 4, Placement::boundary, 0.6), InputError);
  EXPECT_THROW(rectangle_lattice(kRect, 4, 4, Placement::boundary, -0.1), InputError);
}

TEST(Voronoi, LatticeAreasMatchExactVolumes) {
  // Boundary placement puts points on the upper faces, which voro++ itself would reject.
  for (auto [nx, ny] : {std::pair{5, 4}, std::pair{17, 13}, std::pair{2, 2}}) {
    const ParticleSet p = rectangle_lattice(kRect, nx, ny, Placement::boundary);
    const Eigen::VectorXd a = voronoi_areas(p.x, kRect);
    ASSERT_EQ(a.size(), p.size());
    for (int J = 0; J < p.size(); ++J)
      EXPECT_NEAR(a[J], p.volume[J], 1e-12 * p.volume[J]) << nx << "×" << ny << " particle " << J;
  }
  const ParticleSet q = rectangle_lattice(kRect, 10, 7, Placement::inset);
  const Eigen::VectorXd a = voronoi_areas(q.x, kRect);
  for (int J = 0; J < q.size(); ++J) EXPECT_NEAR(a[J], q.volume[J], 1e-12 * q.volume[J]);
}

TEST(Voronoi, RandomPointsSumToAreaInInputOrder) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> ux(-1, 3), uy(2, 5);
  Eigen::MatrixXd pts(2, 2000);
  for (int k = 0; k < pts.cols(); ++k) pts.col(k) = Eigen::Vector2d(ux(rng), uy(rng));
  const Eigen::VectorXd a = voronoi_areas(pts, kRect);
  ASSERT_EQ(a.size(), pts.cols());
  EXPECT_TRUE((a.array() > 0).all());
  EXPECT_NEAR(a.sum(), kRect.measure(), 1e-10 * kRect.measure());
  // Input order: the bisector of these two points is x = 0, leaving 3 × 3 to the right one.
  Eigen::MatrixXd two(2, 2);
  two << 0.5, -0.5,  //
      3.5, 3.5;
  const Eigen::VectorXd b = voronoi_areas(two, kRect);
  EXPECT_NEAR(b[0], 9.0, 1e-12);
  EXPECT_NEAR(b[1], 3.0, 1e-12);
}

TEST(Voronoi, PointOutsideThrows) {
  Eigen::MatrixXd pts(2, 3);
  pts << 0, 1, 3.5,  //
      3, 4, 3;
  EXPECT_THROW(voronoi_areas(pts, kRect), InputError);
  pts(0, 2) = 3.0;
  EXPECT_NO_THROW(voronoi_areas(pts, kRect));
  pts(1, 1) = 1.9;
  EXPECT_THROW(voronoi_areas(pts, kRect), InputError);
}

TEST(StressPoints2D, QuadCentresFormRotatedLattice) {
  const int nx = 7, ny = 7;
  const Domain sq = Domain::rectangle(0, 0, 3, 3);
  const ParticleSet p = rectangle_lattice(sq, nx, ny, Placement::boundary);
  const StressPoints s = make_stress_points(p, sq, StressPointLayout::quad_centres);
  const double h = 0.5, half = h * h / 2;
  ASSERT_EQ(s.x.cols(), (nx - 1) * (ny - 1));
  ASSERT_EQ(s.volume.size(), s.x.cols());
  ASSERT_EQ(s.particle_volume.size(), p.size());
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const int q = i + (nx - 1) * j;
      EXPECT_NEAR(s.x(0, q), (i + 0.5) * h, 1e-14);
      EXPECT_NEAR(s.x(1, q), (j + 0.5) * h, 1e-14);
      EXPECT_NEAR(s.volume[q], half, 1e-12 * half) << "stress point " << q;
    }
  // Particles: diamonds of area h²/2, halved on a side and quartered at a corner.
  for (int J = 0; J < p.size(); ++J) {
    const int i = J % nx, j = J / nx;
    EXPECT_NEAR(s.particle_volume[J], exact_boundary_volume(i, j, nx, ny, 1, 1) * half,
                1e-12 * half)
        << "particle " << J;
  }
  EXPECT_NEAR(s.particle_volume.sum() + s.volume.sum(), sq.measure(), 1e-12);  // 001 eq 65
}

TEST(StressPoints2D, TriangleCentresOnPerturbedLattice) {
  const int nx = 6, ny = 5;
  const ParticleSet p = rectangle_lattice(kRect, nx, ny, Placement::boundary, 0.25, 11);
  const StressPoints s = make_stress_points(p, kRect, StressPointLayout::triangle_centres);
  ASSERT_EQ(s.x.cols(), 2 * (nx - 1) * (ny - 1));
  const int i = 2, j = 3, q = i + (nx - 1) * j;
  const Eigen::Vector2d a = p.x.col(i + nx * j), b = p.x.col(i + 1 + nx * j),
                        c = p.x.col(i + 1 + nx * (j + 1)), d = p.x.col(i + nx * (j + 1));
  EXPECT_NEAR((s.x.col(2 * q) - (a + b + c) / 3).norm(), 0, 1e-14);
  EXPECT_NEAR((s.x.col(2 * q + 1) - (a + c + d) / 3).norm(), 0, 1e-14);
  EXPECT_TRUE((s.volume.array() > 0).all());
  EXPECT_TRUE((s.particle_volume.array() > 0).all());
  EXPECT_NEAR(s.particle_volume.sum() + s.volume.sum(), kRect.measure(),
              1e-10 * kRect.measure());

  const StressPoints sq = make_stress_points(p, kRect, StressPointLayout::quad_centres);
  ASSERT_EQ(sq.x.cols(), (nx - 1) * (ny - 1));
  EXPECT_NEAR((sq.x.col(q) - (a + b + c + d) / 4).norm(), 0, 1e-14);
  EXPECT_NEAR(sq.particle_volume.sum() + sq.volume.sum(), kRect.measure(),
              1e-10 * kRect.measure());
}

TEST(StressPoints2D, NeedLatticeAndMatchingDomain) {
  ParticleSet p = rectangle_lattice(kRect, 4, 4, Placement::boundary);
  EXPECT_THROW(make_stress_points(p, Domain::interval(0, 1)), InputError);
  p.lattice = Eigen::Vector2i::Zero();
  EXPECT_THROW(make_stress_points(p, kRect), InputError);
}

TEST(StressPoints1D, MidpointsAndJointVolumes) {
  const Domain line = Domain::interval(0, 1);
  const ParticleSet p = uniform_line(line, 5, 0.3, 9);
  const StressPoints s = make_stress_points(p, line);
  ASSERT_EQ(s.x.cols(), 4);
  ASSERT_EQ(s.particle_volume.size(), 5);
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(s.x(0, k), 0.5 * (p.x(0, k) + p.x(0, k + 1)), 1e-15);
    // Between particle k, stress point k and particle k+1 the bisectors are quarter points.
    EXPECT_NEAR(s.volume[k], 0.5 * (p.x(0, k + 1) - p.x(0, k)), 1e-15);
  }
  EXPECT_NEAR(s.particle_volume[0], 0.25 * (p.x(0, 1) - p.x(0, 0)), 1e-15);
  EXPECT_NEAR(s.particle_volume[2], 0.25 * (p.x(0, 3) - p.x(0, 1)), 1e-15);
  EXPECT_NEAR(s.particle_volume.sum() + s.volume.sum(), 1.0, 1e-14);  // 001 eq 65
}

}  // namespace
}  // namespace mfv
