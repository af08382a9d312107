/// Bilinear (Q4) element shape functions on a 2D particle lattice (the FEM reference).
#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>

#include "methods/approximations/approximation.hpp"
#include "methods/core/errors.hpp"

namespace mfv {

namespace {

/// Reference corners of the nodes, in the order (i,j), (i+1,j), (i+1,j+1), (i,j+1).
constexpr std::array<double, 4> kXi{-1, 1, 1, -1}, kEta{-1, -1, 1, 1};

struct Element {
  std::array<Eigen::Vector2d, 4> x;  ///< node positions
  std::array<int, 4> node;           ///< particle indices
};

Element element(const ParticleSet& p, int i, int j) {
  const int nx = p.lattice[0];
  Element e;
  e.node = {i + nx * j, i + 1 + nx * j, i + 1 + nx * (j + 1), i + nx * (j + 1)};
  for (int a = 0; a < 4; ++a) e.x[a] = p.x.col(e.node[a]);
  return e;
}

/// Whether x lies in the (convex, counter-clockwise) quadrilateral, edges included up to a
/// tolerance of 1e-10 of its size.
bool contains(const Element& e, const Eigen::Vector2d& x) {
  const double size2 = (e.x[2] - e.x[0]).squaredNorm() + (e.x[3] - e.x[1]).squaredNorm();
  for (int a = 0; a < 4; ++a) {
    const Eigen::Vector2d edge = e.x[(a + 1) % 4] - e.x[a], r = x - e.x[a];
    if (edge.x() * r.y() - edge.y() * r.x() < -1e-10 * size2) return false;
  }
  return true;
}

/// Shape functions and their ξ-derivatives at (ξ, η).
void reference(double xi, double eta, double* n, double* dxi, double* deta) {
  for (int a = 0; a < 4; ++a) {
    n[a] = 0.25 * (1 + kXi[a] * xi) * (1 + kEta[a] * eta);
    dxi[a] = 0.25 * kXi[a] * (1 + kEta[a] * eta);
    deta[a] = 0.25 * kEta[a] * (1 + kXi[a] * xi);
  }
}

/// J = ∂x/∂ξ (columns ∂x/∂ξ, ∂x/∂η) at the reference point.
Eigen::Matrix2d jacobian(const Element& e, const double* dxi, const double* deta) {
  Eigen::Matrix2d J = Eigen::Matrix2d::Zero();
  for (int a = 0; a < 4; ++a) {
    J.col(0) += dxi[a] * e.x[a];
    J.col(1) += deta[a] * e.x[a];
  }
  return J;
}

/// The inverse isoparametric map by Newton iteration (quadratic convergence inside a convex
/// quadrilateral, started at its centre).
Eigen::Vector2d inverse_map(const Element& e, const Eigen::Vector2d& x) {
  Eigen::Vector2d xi = Eigen::Vector2d::Zero();
  double n[4], dxi[4], deta[4];
  const double size = (e.x[2] - e.x[0]).norm();
  for (int it = 0; it < 50; ++it) {
    reference(xi[0], xi[1], n, dxi, deta);
    Eigen::Vector2d r = -x;
    for (int a = 0; a < 4; ++a) r += n[a] * e.x[a];
    const Eigen::Matrix2d J = jacobian(e, dxi, deta);
    if (!(J.determinant() > 0))
      throw InputError(fmt::format(
          "Q4 element with nodes {}, {}, {}, {} is inverted or degenerate near the point ({}, "
          "{}); lower the perturbation",
          e.node[0], e.node[1], e.node[2], e.node[3], x.x(), x.y()));
    const Eigen::Vector2d step = J.inverse() * r;
    xi -= step;
    if (r.norm() <= 1e-15 * size || step.lpNorm<Eigen::Infinity>() < 1e-14) return xi;
  }
  return xi;
}

}  // namespace

ShapeTable BilinearElementApproximation::evaluate(const ParticleSet& particles,
                                                  const Eigen::MatrixXd& points,
                                                  int order) const {
  if (particles.dim != 2)
    throw InputError(fmt::format("Q4 elements are 2D, got {}D particles", particles.dim));
  const int nx = particles.lattice[0], ny = particles.lattice[1];
  if (nx == 0 || ny == 0)
    throw InputError("Q4 elements need a lattice particle set (ParticleSet::lattice is zero); "
                     "build the particles with rectangle_lattice");
  if (nx < 2 || ny < 2 || nx * ny != particles.size())
    throw InputError(fmt::format("Q4 elements need a lattice of at least 2 × 2 particles "
                                 "matching the set, got {} × {} for {} particles",
                                 nx, ny, particles.size()));
  // The unperturbed lattice's spacing gives the first guess of a point's element.
  const Eigen::Vector2d lo = particles.x.rowwise().minCoeff();
  const Eigen::Vector2d hi = particles.x.rowwise().maxCoeff();
  const double hx = (hi.x() - lo.x()) / (nx - 1), hy = (hi.y() - lo.y()) / (ny - 1);
  ShapeTable t;
  t.dim = 2;
  t.order = order;
  const int entries = 4 * static_cast<int>(points.cols());
  t.index.reserve(entries);
  t.value.reserve(entries);
  if (order >= 1) t.grad.reserve(2 * entries);
  if (order >= 2) t.hess.reserve(4 * entries);
  double n[4], dxi[4], deta[4];
  for (Eigen::Index q = 0; q < points.cols(); ++q) {
    const Eigen::Vector2d x = points.col(q);
    const int gi = std::clamp(static_cast<int>(std::floor((x.x() - lo.x()) / hx)), 0, nx - 2);
    const int gj = std::clamp(static_cast<int>(std::floor((x.y() - lo.y()) / hy)), 0, ny - 2);
    // Rings of elements around the guess: perturbed lattices usually hit in the first ring;
    // a point outside the mesh exhausts them all.
    bool found = false;
    Element e;
    for (int ring = 0; !found && ring <= std::max(nx, ny); ++ring)
      for (int j = std::max(gj - ring, 0); !found && j <= std::min(gj + ring, ny - 2); ++j)
        for (int i = std::max(gi - ring, 0); !found && i <= std::min(gi + ring, nx - 2); ++i) {
          if (std::max(std::abs(i - gi), std::abs(j - gj)) != ring) continue;
          e = element(particles, i, j);
          found = contains(e, x);
        }
    if (!found)
      throw InputError(fmt::format(
          "point ({}, {}) lies outside the Q4 element mesh of the particles (bounding box [{}, "
          "{}] × [{}, {}]); Q4 elements cover only the lattice: use boundary placement for a "
          "mesh that fills the domain, and keep --perturb small enough (about 0.3 or less) that "
          "no element folds",
          x.x(), x.y(), lo.x(), hi.x(), lo.y(), hi.y()));
    const Eigen::Vector2d xi = inverse_map(e, x);
    reference(xi[0], xi[1], n, dxi, deta);
    for (int a = 0; a < 4; ++a) {
      t.index.push_back(e.node[a]);
      t.value.push_back(n[a]);
    }
    if (order >= 1) {
      // ∇_x N = J⁻ᵀ ∇_ξ N; with G = J⁻¹ the physical Hessian of the bilinear map is
      // H = Gᵀ (∇²_ξ N − Σ_m ∂N/∂x_m ∇²_ξ x_m) G, and both ξ-Hessians have only the mixed
      // ξη entry (N_a: ξ_a η_a / 4, x: c = Σ_a ξ_a η_a x_a / 4), so H = s Gᵀ [0 1; 1 0] G.
      const Eigen::Matrix2d G = jacobian(e, dxi, deta).inverse();
      Eigen::Vector2d c = Eigen::Vector2d::Zero();
      for (int a = 0; a < 4; ++a) c += 0.25 * kXi[a] * kEta[a] * e.x[a];
      Eigen::Matrix2d swap;
      swap << 0, 1, 1, 0;
      const Eigen::Matrix2d S = G.transpose() * swap * G;
      for (int a = 0; a < 4; ++a) {
        const Eigen::Vector2d g = G.transpose() * Eigen::Vector2d(dxi[a], deta[a]);
        t.grad.push_back(g.x());
        t.grad.push_back(g.y());
        if (order >= 2) {
          const double s = 0.25 * kXi[a] * kEta[a] - g.dot(c);
          for (int k = 0; k < 4; ++k) t.hess.push_back(s * S(k / 2, k % 2));
        }
      }
    }
    t.offsets.push_back(t.entries());
  }
  return t;
}

}  // namespace mfv
