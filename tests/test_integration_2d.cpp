/// 2D integration rules (gauss-cells, stress points, boundary rules), Q4 elements and `fem` on a
/// lattice.
#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "methods/approximations/approximation.hpp"
#include "methods/core/errors.hpp"
#include "methods/integration/integration.hpp"
#include "test_support.hpp"

namespace mfv {
namespace {

const Domain kRect = Domain::rectangle(0.0, 0.0, 2.0, 1.0);  // 2 × 1

Eigen::MatrixXd random_points(const Domain& d, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  Eigen::MatrixXd x(2, n);
  for (int q = 0; q < n; ++q)
    for (int a = 0; a < 2; ++a) x(a, q) = d.lower[a] + u(rng) * (d.upper[a] - d.lower[a]);
  return x;
}

IntegrationRule make_rule(const std::string& scheme, const std::string& params,
                          const ParticleSet& p, const Domain& d = kRect) {
  return test_catalogue().integrations.create(scheme, Params::parse(params))->rule(d, p);
}

IntegrationRule make_boundary_rule(const std::string& scheme, const std::string& params,
                                   const ParticleSet& p, int side, const Domain& d = kRect) {
  return test_catalogue()
      .integrations.create(scheme, Params::parse(params))
      ->boundary_rule(d, p, side);
}

/// Σ_q w_q f(x_q).
template <class F>
double integrate(const IntegrationRule& r, F f) {
  double s = 0;
  for (int q = 0; q < r.size(); ++q) s += r.weights[q] * f(r.points(0, q), r.points(1, q));
  return s;
}

// ---- Q4 elements ----

TEST(Q4Elements, PartitionOfUnityAndLinearReproduction) {
  const BilinearElementApproximation q4;
  for (double perturbation : {0.0, 0.3}) {
    const ParticleSet p = rectangle_lattice(kRect, 9, 6, Placement::boundary, perturbation, 3);
    const Eigen::MatrixXd x = random_points(kRect, 300, 7);
    const ShapeTable t = q4.evaluate(p, x, 1);
    ASSERT_EQ(t.points(), x.cols());
    const Eigen::VectorXd one = Eigen::VectorXd::Ones(p.size());
    const Eigen::VectorXd u = (1 + 2 * p.x.row(0).array() - 3 * p.x.row(1).array()).transpose();
    const Eigen::VectorXd uh = t.interpolate(u), gx = t.interpolate_derivative(u, 0),
                          gy = t.interpolate_derivative(u, 1);
    const Eigen::VectorXd sum = t.interpolate(one), dsum = t.interpolate_derivative(one, 1);
    for (int q = 0; q < x.cols(); ++q) {
      EXPECT_EQ(t.offsets[q + 1] - t.offsets[q], 4);
      EXPECT_NEAR(sum[q], 1.0, 1e-13) << "perturbation " << perturbation;
      EXPECT_NEAR(dsum[q], 0.0, 1e-11);
      EXPECT_NEAR(uh[q], 1 + 2 * x(0, q) - 3 * x(1, q), 1e-12) << "perturbation " << perturbation;
      EXPECT_NEAR(gx[q], 2.0, 1e-11);
      EXPECT_NEAR(gy[q], -3.0, 1e-11);
    }
  }
}

TEST(Q4Elements, InterpolatesAtTheParticles) {
  const BilinearElementApproximation q4;
  const ParticleSet p = rectangle_lattice(kRect, 6, 5, Placement::boundary, 0.3, 11);
  const ShapeTable t = q4.evaluate(p, p.x, 0);
  for (int I = 0; I < p.size(); ++I) {
    double own = 0;
    for (int k = t.offsets[I]; k < t.offsets[I + 1]; ++k) {
      if (t.index[k] == I) {
        own += t.value[k];
      } else {
        EXPECT_NEAR(t.value[k], 0.0, 1e-12) << "N_" << t.index[k] << "(x_" << I << ")";
      }
    }
    EXPECT_NEAR(own, 1.0, 1e-12) << "N_" << I << "(x_" << I << ")";
  }
}

TEST(Q4Elements, OutsideTheMeshAndUnstructuredSetsThrow) {
  const BilinearElementApproximation q4;
  ParticleSet p = rectangle_lattice(kRect, 5, 4, Placement::boundary, 0.2, 5);
  Eigen::MatrixXd x(2, 2);
  x << 1.0, 2.5, 0.5, 0.5;
  try {
    q4.evaluate(p, x, 1);
    FAIL() << "a point outside the mesh was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("(2.5, 0.5)"), std::string::npos) << e.what();
  }
  // Points on the mesh's edges and corners are inside.
  Eigen::MatrixXd edge(2, 3);
  edge << 0.0, 2.0, 1.3, 0.4, 1.0, 0.0;
  EXPECT_NO_THROW(q4.evaluate(p, edge, 1));
  p.lattice.setZero();
  try {
    q4.evaluate(p, edge, 0);
    FAIL() << "an unstructured set was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("lattice"), std::string::npos) << e.what();
  }
}

TEST(Q4Elements, SecondDerivativesMatchFiniteDifferences) {
  const BilinearElementApproximation q4;
  const ParticleSet p = rectangle_lattice(kRect, 7, 5, Placement::boundary, 0.3, 2);
  const Eigen::MatrixXd x = random_points(kRect, 200, 13);
  const double h = 1e-6;
  const ShapeTable t = q4.evaluate(p, x, 2);
  int compared = 0;
  double largest = 0;
  for (int d = 0; d < 2; ++d) {
    Eigen::MatrixXd xp = x, xm = x;
    xp.row(d).array() += h;
    xm.row(d).array() -= h;
    // Points pushed off the mesh are dropped: evaluate them one by one.
    for (int q = 0; q < x.cols(); ++q) {
      ShapeTable tp, tm;
      try {
        tp = q4.evaluate(p, xp.col(q), 1);
        tm = q4.evaluate(p, xm.col(q), 1);
      } catch (const InputError&) {
        continue;
      }
      // Compare only where the three points share an element (the Hessian is per element).
      bool same = true;
      for (int a = 0; a < 4; ++a)
        same = same && tp.index[a] == t.index[t.offsets[q] + a] &&
               tm.index[a] == t.index[t.offsets[q] + a];
      if (!same) continue;
      ++compared;
      for (int a = 0; a < 4; ++a) {
        const int k = t.offsets[q] + a;
        for (int i = 0; i < 2; ++i) {
          const double fd = (tp.grad[2 * a + i] - tm.grad[2 * a + i]) / (2 * h);
          const double exact = t.hess[4 * k + 2 * i + d];
          largest = std::max(largest, std::abs(exact));
          EXPECT_NEAR(exact, fd, 1e-5 * (1 + std::abs(fd))) << "point " << q << " entry " << a;
        }
      }
    }
  }
  EXPECT_GT(compared, 250);
  EXPECT_GT(largest, 1e-2) << "a distorted quad's Hessian should not vanish";
  // Second derivatives of a reproduced linear field are zero.
  const Eigen::VectorXd u = (2 * p.x.row(0).array() + 5 * p.x.row(1).array()).transpose();
  EXPECT_LT(t.interpolate_second_derivative(u, 0).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT(t.interpolate_second_derivative(u, 1).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(Q4Elements, LinearFeDispatchesOnDimension) {
  const auto fe = test_catalogue().approximations.create("linear-fe");
  EXPECT_EQ(fe->minimum_support_count(1), 2);
  EXPECT_EQ(fe->minimum_support_count(2), 4);
  const ParticleSet p2 = rectangle_lattice(kRect, 4, 3, Placement::boundary);
  const ShapeTable t2 = fe->evaluate(p2, random_points(kRect, 5, 1), 1);
  EXPECT_EQ(t2.dim, 2);
  EXPECT_EQ(t2.entries(), 20);
  const Domain line = Domain::interval(0, 1);
  const ParticleSet p1 = uniform_line(line, 5);
  Eigen::MatrixXd x1(1, 3);
  x1 << 0.1, 0.5, 0.95;
  const ShapeTable t1 = fe->evaluate(p1, x1, 1);
  const ShapeTable hats = LinearElementApproximation().evaluate(p1, x1, 1);
  EXPECT_EQ(t1.index, hats.index);
  EXPECT_EQ(t1.value, hats.value);
  EXPECT_EQ(t1.grad, hats.grad);
}

// ---- gauss-cells ----

TEST(GaussCells2D, WeightsSumToTheArea) {
  const struct {
    const char* params;
    Placement placement;
    double perturbation;
  } cases[] = {{"", Placement::boundary, 0.0},
               {"", Placement::boundary, 0.3},
               {"cells=5", Placement::boundary, 0.3},
               {"", Placement::inset, 0.2},
               {"nq=2", Placement::inset, 0.0}};
  for (const auto& c : cases) {
    const ParticleSet p = rectangle_lattice(kRect, 9, 5, c.placement, c.perturbation, 4);
    const IntegrationRule r = make_rule("gauss-cells", c.params, p);
    EXPECT_EQ(r.kind, "gauss-cells");
    EXPECT_NEAR(r.weights.sum(), 2.0, 1e-12) << c.params << " " << c.perturbation;
    EXPECT_GT(r.weights.minCoeff(), 0);
    EXPECT_GE(r.points.row(0).minCoeff(), 0.0);
    EXPECT_LE(r.points.row(0).maxCoeff(), 2.0);
    EXPECT_GE(r.points.row(1).minCoeff(), 0.0);
    EXPECT_LE(r.points.row(1).maxCoeff(), 1.0);
    ASSERT_EQ(r.cell.size(), static_cast<std::size_t>(r.size()));
    EXPECT_EQ(*std::max_element(r.cell.begin(), r.cell.end()), r.cells - 1);
  }
  // An unstructured set gets a background grid too.
  ParticleSet u = rectangle_lattice(kRect, 9, 5, Placement::boundary, 0.3, 4);
  u.lattice.setZero();
  EXPECT_NEAR(make_rule("gauss-cells", "", u).weights.sum(), 2.0, 1e-12);
}

TEST(GaussCells2D, ExactOnPerturbedLatticeCells) {
  // x² y² pulled back by the bilinear map times det J has degree 5 per direction: 3 points do.
  const ParticleSet p = rectangle_lattice(kRect, 7, 5, Placement::boundary, 0.3, 9);
  const IntegrationRule r = make_rule("gauss-cells", "nq=3", p);
  EXPECT_EQ(r.cells, 6 * 4);
  EXPECT_EQ(r.size(), 6 * 4 * 9);
  EXPECT_NEAR(integrate(r, [](double x, double) { return x * x; }), 8.0 / 3, 1e-12);
  EXPECT_NEAR(integrate(r, [](double x, double y) { return x * y; }), 1.0, 1e-12);
  EXPECT_NEAR(integrate(r, [](double, double y) { return y * y; }), 2.0 / 3, 1e-12);
  EXPECT_NEAR(integrate(r, [](double x, double y) { return x * x * y * y; }), 8.0 / 9, 1e-12);
  // The cells follow the perturbed particles, not a grid: every point of cell (i, j) lies in
  // the quadrilateral's bounding box.
  const int nx = 7;
  for (int q = 0; q < r.size(); ++q) {
    const int i = r.cell[q] % 6, j = r.cell[q] / 6;
    const int a = i + nx * j, c = i + 1 + nx * (j + 1);
    EXPECT_LE(r.points(0, q), std::max(p.x(0, c), p.x(0, a + 1)) + 1e-12);
    EXPECT_GE(r.points(1, q), std::min(p.x(1, a), p.x(1, a + 1)) - 1e-12);
  }
}

TEST(GaussCells2D, Eq66PointCounts) {
  const auto per_cell = [](const IntegrationRule& r) {
    std::vector<int> n(r.cells, 0);
    for (int c : r.cell) ++n[c];
    return n;
  };
  // Lattice cells hold one particle each: n_Q = ceil(sqrt(1)) + 2 = 3.
  const ParticleSet lattice = rectangle_lattice(kRect, 5, 4, Placement::boundary, 0.2, 1);
  const IntegrationRule a = make_rule("gauss-cells", "", lattice);
  EXPECT_EQ(a.cells, 4 * 3);
  for (int n : per_cell(a)) EXPECT_EQ(n, 9);
  // An inset 8 × 4 lattice under a 4 × 2 grid of 0.5 × 0.5 cells: 4 particles per cell, n_Q = 4.
  const ParticleSet inset = rectangle_lattice(kRect, 8, 4, Placement::inset);
  const IntegrationRule b = make_rule("gauss-cells", "cells=4", inset);
  EXPECT_EQ(b.cells, 8);
  for (int n : per_cell(b)) EXPECT_EQ(n, 16);
  EXPECT_NEAR(integrate(b, [](double x, double y) { return std::pow(x * y, 7); }),
              std::pow(2.0, 8) / 64, 1e-11);
  // nq forces the count; the 1D default n = 10 does not apply in 2D.
  for (int n : per_cell(make_rule("gauss-cells", "cells=4,nq=2", inset))) EXPECT_EQ(n, 4);
  for (int n : per_cell(make_rule("gauss-cells", "n=10", lattice))) EXPECT_EQ(n, 9);
}

TEST(Nodal2D, ParticlesAreTheRule) {
  const ParticleSet p = rectangle_lattice(kRect, 6, 4, Placement::boundary, 0.2, 8);
  const IntegrationRule r = make_rule("nodal", "", p);
  EXPECT_EQ(r.nodal_points, p.size());
  EXPECT_EQ(r.points, p.x);
  EXPECT_NEAR(r.weights.sum(), 2.0, 1e-12);
}

// ---- stress points ----

TEST(StressPointRule2D, ParticlesThenQuadCentres) {
  const int nx = 6, ny = 5;
  for (double perturbation : {0.0, 0.3}) {
    const ParticleSet p = rectangle_lattice(kRect, nx, ny, Placement::boundary, perturbation, 6);
    const IntegrationRule r = make_rule("stress-points", "", p);
    const int n = nx * ny, ns = (nx - 1) * (ny - 1);
    EXPECT_EQ(r.kind, "stress-points");
    EXPECT_EQ(r.size(), n + ns);
    EXPECT_EQ(r.nodal_points, n);
    EXPECT_EQ(r.cells, ns);
    EXPECT_EQ(r.points.leftCols(n), p.x);
    EXPECT_NEAR(r.weights.sum(), 2.0, 1e-12) << "perturbation " << perturbation;
    EXPECT_GT(r.weights.minCoeff(), 0);
    // The first stress point is the centre of quad (0, 0).
    const Eigen::Vector2d centre =
        0.25 * (p.x.col(0) + p.x.col(1) + p.x.col(nx) + p.x.col(nx + 1));
    EXPECT_NEAR((r.points.col(n) - centre).norm(), 0, 1e-14);
  }
}

TEST(StressPointRule2D, TriangleLayoutHasTwoPerQuad) {
  const ParticleSet p = rectangle_lattice(kRect, 5, 4, Placement::boundary, 0.1, 2);
  const IntegrationRule r = make_rule("stress-points", "layout=triangle-centres", p);
  EXPECT_EQ(r.size(), 20 + 2 * 4 * 3);
  EXPECT_EQ(r.nodal_points, 20);
  EXPECT_EQ(r.cells, 24);
  EXPECT_NEAR(r.weights.sum(), 2.0, 1e-12);
  EXPECT_THROW(make_rule("stress-points", "layout=hexagons", p), InputError);
}

// ---- boundary rules ----

double side_value(int side) { return side == 0 ? 0.0 : side == 1 ? 2.0 : side == 2 ? 0.0 : 1.0; }
double side_length(int side) { return side < 2 ? 1.0 : 2.0; }

TEST(BoundaryRules, NodalSharesOfEachSide) {
  for (Placement placement : {Placement::boundary, Placement::inset}) {
    const ParticleSet p = rectangle_lattice(kRect, 7, 5, placement, 0.3, 12);
    for (const char* scheme : {"nodal", "stress-points"})
      for (int side = 0; side < 4; ++side) {
        const IntegrationRule r = make_boundary_rule(scheme, "", p, side);
        const int normal = side < 2 ? 0 : 1, along = 1 - normal;
        EXPECT_EQ(r.kind, "nodal-boundary");
        EXPECT_EQ(r.nodal_points, 0);
        EXPECT_NEAR(r.weights.sum(), side_length(side), 1e-13) << scheme << " side " << side;
        EXPECT_GT(r.weights.minCoeff(), 0);
        std::vector<int> flagged;
        for (int J = 0; J < p.size(); ++J)
          if (p.sides[J] & side_bit(side)) flagged.push_back(J);
        std::vector<int> cells = r.cell;
        std::sort(cells.begin(), cells.end());
        EXPECT_EQ(cells, flagged) << "side " << side;
        for (int q = 0; q < r.size(); ++q) {
          EXPECT_EQ(r.points(normal, q), side_value(side));
          EXPECT_EQ(r.points(along, q), p.x(along, r.cell[q]));
          if (q > 0) {
            EXPECT_GT(r.points(along, q), r.points(along, q - 1));
          }
        }
      }
  }
  // Unperturbed boundary placement: half spacings at the ends, full ones between.
  const ParticleSet u = rectangle_lattice(kRect, 5, 3, Placement::boundary);
  const IntegrationRule bottom = nodal_boundary_rule(kRect, u, 2);
  ASSERT_EQ(bottom.size(), 5);
  EXPECT_NEAR(bottom.weights[0], 0.25, 1e-15);
  EXPECT_NEAR(bottom.weights[2], 0.5, 1e-15);
  EXPECT_THROW(nodal_boundary_rule(kRect, u, 4), InputError);
}

TEST(BoundaryRules, GaussCellsAlongTheSides) {
  for (const char* params : {"", "nq=2", "cells=4"}) {
    const ParticleSet p = rectangle_lattice(kRect, 7, 5, Placement::boundary, 0.3, 12);
    for (int side = 0; side < 4; ++side) {
      const IntegrationRule r = make_boundary_rule("gauss-cells", params, p, side);
      const int normal = side < 2 ? 0 : 1;
      EXPECT_NEAR(r.weights.sum(), side_length(side), 1e-13) << params << " side " << side;
      for (int q = 0; q < r.size(); ++q) EXPECT_EQ(r.points(normal, q), side_value(side));
      // Segments: the lattice's boundary edges or the grid's cell edges (4 × 2 cells).
      const int segments = std::string(params) == "cells=4" ? (side < 2 ? 2 : 4)
                                                            : (side < 2 ? 4 : 6);
      EXPECT_EQ(r.cells, segments);
      EXPECT_EQ(*std::max_element(r.cell.begin(), r.cell.end()), segments - 1);
    }
    // Same per-direction count as the domain rule: y² (3 points) and y³ (2 points) exactly.
    const IntegrationRule right = make_boundary_rule("gauss-cells", params, p, 1);
    EXPECT_NEAR(integrate(right, [](double, double y) { return y * y; }), 1.0 / 3, 1e-14);
    EXPECT_NEAR(integrate(right, [](double, double y) { return y * y * y; }), 0.25, 1e-14);
  }
  // Lattice segments end at the boundary particles: 3 points per segment by eq 66.
  const ParticleSet p = rectangle_lattice(kRect, 7, 5, Placement::boundary, 0.3, 12);
  const IntegrationRule top = make_boundary_rule("gauss-cells", "", p, 3);
  EXPECT_EQ(top.size(), 6 * 3);
  for (int q = 0; q < top.size(); ++q) {
    const int k = top.cell[q], J0 = 7 * 4 + k;
    EXPECT_GT(top.points(0, q), p.x(0, J0));
    EXPECT_LT(top.points(0, q), p.x(0, J0 + 1));
  }
}

TEST(BoundaryRules, OneDimensionalEndPoints) {
  const Domain line = Domain::interval(0.5, 2.0);
  const ParticleSet p = uniform_line(line, 9, 0.3, 4);
  for (const char* scheme : {"nodal", "gauss-cells", "stress-points"})
    for (int side = 0; side < 2; ++side) {
      const IntegrationRule r = make_boundary_rule(scheme, "", p, side, line);
      ASSERT_EQ(r.size(), 1) << scheme;
      EXPECT_EQ(r.points(0, 0), side == 0 ? 0.5 : 2.0);
      EXPECT_EQ(r.weights[0], 1.0);
      Eigen::Index end = 0;
      if (side == 0) p.x.row(0).minCoeff(&end);
      else p.x.row(0).maxCoeff(&end);
      EXPECT_EQ(r.cell[0], end);
    }
  EXPECT_THROW(make_boundary_rule("nodal", "", p, 2, line), InputError);
}

// ---- fem on a lattice ----

TEST(Fem2D, DiscretizesALattice) {
  const auto fem = test_catalogue().methods.create("fem");
  const ParticleSet p = rectangle_lattice(kRect, 7, 5, Placement::boundary, 0.3, 21);
  const Discretization d = fem->discretize(kRect, p, 1);
  EXPECT_EQ(d.quadrature.kind, "gauss-cells");
  EXPECT_EQ(d.quadrature.size(), 6 * 4 * 9);
  EXPECT_NEAR(d.quadrature.weights.sum(), 2.0, 1e-12);
  const Eigen::VectorXd u = (0.5 - p.x.row(0).array() + 4 * p.x.row(1).array()).transpose();
  const Eigen::VectorXd uh = d.trial_q.interpolate(u);
  const Eigen::MatrixXd g = d.gradient(u);
  for (int q = 0; q < d.quadrature.size(); ++q) {
    const Eigen::Vector2d x = d.quadrature.points.col(q);
    EXPECT_NEAR(uh[q], 0.5 - x.x() + 4 * x.y(), 1e-12);
    EXPECT_NEAR(g(0, q), -1.0, 1e-11);
    EXPECT_NEAR(g(1, q), 4.0, 1e-11);
  }
  // The traction rule of the right side is the gauss-cells boundary rule.
  EXPECT_NEAR(d.boundary_rule(1).weights.sum(), 1.0, 1e-13);
}

}  // namespace
}  // namespace mfv
