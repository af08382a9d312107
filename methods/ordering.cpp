#include "methods/ordering.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numeric>

#include <fmt/format.h>

#include "methods/core/errors.hpp"

namespace mfv {

namespace {

constexpr int kBits = 16;  // cells per direction 2^16: far finer than any particle spacing
constexpr std::uint32_t kSide = 1u << kBits;

/// Index along Hilbert's curve of cell (x, y) of a kSide × kSide grid: at each level from the
/// coarsest, the quadrant's place along the curve (0, 1, 2, 3 for (0,0), (0,1), (1,1),
/// (1,0)), then the cell rotated/reflected into that quadrant's frame of the curve.
std::uint64_t hilbert_index(std::uint32_t x, std::uint32_t y) {
  std::uint64_t d = 0;
  for (std::uint32_t s = kSide / 2; s > 0; s /= 2) {
    const std::uint32_t rx = (x & s) ? 1 : 0, ry = (y & s) ? 1 : 0;
    d += static_cast<std::uint64_t>(s) * s * ((3 * rx) ^ ry);
    if (ry == 0) {
      if (rx == 1) {
        x = kSide - 1 - x;
        y = kSide - 1 - y;
      }
      std::swap(x, y);
    }
  }
  return d;
}

struct Box {
  Eigen::VectorXd lower, upper;
};

Box bounding_box(const std::vector<const Eigen::MatrixXd*>& sets, int dim) {
  Box b{Eigen::VectorXd::Constant(dim, INFINITY), Eigen::VectorXd::Constant(dim, -INFINITY)};
  for (const Eigen::MatrixXd* m : sets) {
    if (m->rows() != dim)
      throw InputError(fmt::format("points to order have {} coordinates, expected {}", m->rows(),
                                   dim));
    if (!m->allFinite())
      throw InputError("a point to order along the Hilbert curve has a non-finite coordinate");
    if (m->cols() == 0) continue;
    b.lower = b.lower.cwiseMin(m->rowwise().minCoeff());
    b.upper = b.upper.cwiseMax(m->rowwise().maxCoeff());
  }
  return b;
}

/// The points' order along the curve in the box b (new → old; stable).
std::vector<int> order_in(const Eigen::MatrixXd& points, const Box& b) {
  const int n = static_cast<int>(points.cols()), dim = static_cast<int>(points.rows());
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  if (n < 2) return order;
  std::vector<std::uint64_t> key(n);
  // One scale for both directions: the curve's cells stay square.
  const double extent = (b.upper - b.lower).maxCoeff();
  const double scale = extent > 0 ? (kSide - 1) / extent : 0;
  auto cell = [&](int i, int c) {
    const double t = std::floor((points(c, i) - b.lower[c]) * scale);
    return static_cast<std::uint32_t>(std::clamp(t, 0.0, double(kSide - 1)));
  };
  for (int i = 0; i < n; ++i)
    key[i] = dim == 1 ? cell(i, 0) : hilbert_index(cell(i, 0), cell(i, 1));
  std::stable_sort(order.begin(), order.end(), [&](int a, int c) { return key[a] < key[c]; });
  return order;
}

void check_dim(int dim) {
  if (dim != 1 && dim != 2)
    throw InputError(fmt::format("Hilbert ordering is for 1D and 2D points, not {}D", dim));
}

std::vector<int> inverse(const std::vector<int>& old_of_new, const char* what) {
  const int n = static_cast<int>(old_of_new.size());
  std::vector<int> inv(n, -1);
  for (int k = 0; k < n; ++k) {
    const int o = old_of_new[k];
    if (o < 0 || o >= n || inv[o] != -1)
      throw InputError(fmt::format("the {} renumbering is not a permutation of 0..{} (entry {} "
                                   "is {})",
                                   what, n - 1, k, o));
    inv[o] = k;
  }
  return inv;
}

template <class V>
V permuted_vector(const V& v, const std::vector<int>& order) {
  V out(v.size());
  for (std::size_t k = 0; k < order.size(); ++k) out[k] = v[order[k]];
  return out;
}

Eigen::MatrixXd permuted_columns(const Eigen::MatrixXd& m, const std::vector<int>& order) {
  Eigen::MatrixXd out(m.rows(), m.cols());
  for (std::size_t k = 0; k < order.size(); ++k) out.col(k) = m.col(order[k]);
  return out;
}

/// Rows to the new points (point_old), entries to the new particles (particle_new).
ShapeTable renumbered(const ShapeTable& t, const std::vector<int>& point_old,
                      const std::vector<int>& particle_new) {
  ShapeTable r;
  r.dim = t.dim;
  r.order = t.order;
  const int nq = t.points();
  const bool values = static_cast<int>(t.value.size()) == t.entries();
  const bool grads = static_cast<int>(t.grad.size()) == t.entries() * t.dim;
  const int nh = t.nhess();
  const bool hess = static_cast<int>(t.hess.size()) == t.entries() * nh;
  r.offsets.resize(nq + 1);
  r.offsets[0] = 0;
  for (int q = 0; q < nq; ++q)
    r.offsets[q + 1] = r.offsets[q] + t.offsets[point_old[q] + 1] - t.offsets[point_old[q]];
  r.index.resize(t.entries());
  if (values) r.value.resize(t.value.size());
  if (grads) r.grad.resize(t.grad.size());
  if (hess) r.hess.resize(t.hess.size());
  for (int q = 0; q < nq; ++q) {
    int k = r.offsets[q];
    for (int e = t.offsets[point_old[q]]; e < t.offsets[point_old[q] + 1]; ++e, ++k) {
      r.index[k] = particle_new[t.index[e]];
      if (values) r.value[k] = t.value[e];
      if (grads)
        for (int c = 0; c < t.dim; ++c) r.grad[t.dim * k + c] = t.grad[t.dim * e + c];
      if (hess)
        for (int c = 0; c < nh; ++c) r.hess[nh * k + c] = t.hess[nh * e + c];
    }
  }
  return r;
}

}  // namespace

std::vector<int> hilbert_order(const Eigen::MatrixXd& points) {
  check_dim(static_cast<int>(points.rows()));
  return order_in(points, bounding_box({&points}, static_cast<int>(points.rows())));
}

std::vector<int> Renumbering::particle_new() const { return inverse(particle_old, "particle"); }
std::vector<int> Renumbering::point_new() const { return inverse(point_old, "point"); }

Eigen::MatrixXd Renumbering::particles_to_old(const Eigen::MatrixXd& by_new) const {
  if (by_new.cols() != static_cast<Eigen::Index>(particle_old.size()))
    throw InputError(fmt::format("{} columns to renumber, the renumbering has {} particles",
                                 by_new.cols(), particle_old.size()));
  Eigen::MatrixXd out(by_new.rows(), by_new.cols());
  for (std::size_t k = 0; k < particle_old.size(); ++k) out.col(particle_old[k]) = by_new.col(k);
  return out;
}

Renumbering hilbert_renumbering(const Discretization& d) {
  const int dim = d.particles.dim, nq = d.quadrature.size();
  check_dim(dim);
  const int nodal = std::min(d.quadrature.nodal_points, nq);
  const Eigen::MatrixXd rest = d.quadrature.points.rightCols(nq - nodal);
  const Box box = bounding_box({&d.particles.x, &rest}, dim);
  Renumbering r;
  r.particle_old = order_in(d.particles.x, box);
  r.point_old.resize(nq);
  for (int q = 0; q < nodal; ++q) r.point_old[q] = r.particle_old[q];
  const std::vector<int> rest_order = order_in(rest, box);
  for (int k = 0; k < nq - nodal; ++k) r.point_old[nodal + k] = nodal + rest_order[k];
  return r;
}

ParticleSet permuted(const ParticleSet& p, const std::vector<int>& order) {
  const int n = p.size();
  if (static_cast<int>(order.size()) != n)
    throw InputError(fmt::format("a particle order of {} entries for {} particles",
                                 order.size(), n));
  const std::vector<int> new_of_old = inverse(order, "particle");
  ParticleSet s = p;
  s.x = permuted_columns(p.x, order);
  s.volume = permuted_vector(p.volume, order);
  if (p.dilation.size() == n) s.dilation = permuted_vector(p.dilation, order);
  if (static_cast<int>(p.sides.size()) == n) s.sides = permuted_vector(p.sides, order);
  if (p.local_spacing.size() == n) s.local_spacing = permuted_vector(p.local_spacing, order);
  for (auto& quad : s.quads)
    for (int& J : quad) J = new_of_old[J];
  if (p.stress_points && p.stress_points->particle_volume.size() == n) {
    auto sp = std::make_shared<StressPoints>(*p.stress_points);
    sp->particle_volume = permuted_vector(p.stress_points->particle_volume, order);
    s.stress_points = std::move(sp);
  }
  s.lattice.setZero();
  return s;
}

void renumber(Discretization& d, const Renumbering& r) {
  const int n = d.particles.size(), nq = d.quadrature.size();
  if (d.enriched_unknowns > 0)
    throw InputError("a discretization with enrichment unknowns (xefg) cannot be renumbered");
  if (static_cast<int>(r.particle_old.size()) != n || static_cast<int>(r.point_old.size()) != nq)
    throw InputError(fmt::format("a renumbering of {} particles and {} points does not fit a "
                                 "discretization of {} and {}",
                                 r.particle_old.size(), r.point_old.size(), n, nq));
  const std::vector<int> particle_new = r.particle_new();
  (void)r.point_new();  // checks that the points' renumbering is a permutation
  const int nodal = std::min(d.quadrature.nodal_points, nq);
  for (int q = 0; q < nodal; ++q)
    if (r.point_old[q] != r.particle_old[q])
      throw InputError(fmt::format("point {} is a nodal point (particle {}'s own), so it must "
                                   "follow its particle in the renumbering",
                                   q, q));
  for (int q = nodal; q < nq; ++q)
    if (r.point_old[q] < nodal)
      throw InputError(fmt::format("point {} of the renumbering is nodal point {}; nodal points "
                                   "come first, in particle order",
                                   q, r.point_old[q]));
  d.particles = permuted(d.particles, r.particle_old);
  IntegrationRule& rule = d.quadrature;
  rule.points = permuted_columns(rule.points, r.point_old);
  rule.weights = permuted_vector(rule.weights, r.point_old);
  if (static_cast<int>(rule.cell.size()) == nq) {
    // A nodal point's cell is its particle; a cell rule's is its background cell, and a
    // stress point's is its own index among the stress points: those are not renumbered.
    std::vector<int> cell = permuted_vector(rule.cell, r.point_old);
    for (int q = 0; q < nodal; ++q) cell[q] = q;
    rule.cell = std::move(cell);
  }
  d.trial_q = renumbered(d.trial_q, r.point_old, particle_new);
  d.test_q = renumbered(d.test_q, r.point_old, particle_new);
}

}  // namespace mfv
