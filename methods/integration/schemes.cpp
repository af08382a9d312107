/// Nodal integration (001 §5.1), background-cell Gauss quadrature (001 §5.3, eqs 66-68) and
/// stress points (000 §2.4, 001 §5.2), in 1D and 2D, with their rules on the domain's sides.
#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

#include <fmt/format.h>
#include <gsl/gsl_integration.h>

#include "methods/core/errors.hpp"
#include "methods/integration/integration.hpp"

namespace mfv {

void gauss_legendre(int n, double a, double b, std::vector<double>& x, std::vector<double>& w) {
  if (n < 1) throw InputError(fmt::format("a Gauss rule needs at least 1 point, got {}", n));
  gsl_integration_glfixed_table* t = gsl_integration_glfixed_table_alloc(n);
  if (!t) throw std::runtime_error("GSL could not allocate a Gauss-Legendre table");
  x.resize(n);
  w.resize(n);
  for (int i = 0; i < n; ++i) gsl_integration_glfixed_point(a, b, i, &x[i], &w[i], t);
  gsl_integration_glfixed_table_free(t);
}

IntegrationRule uniform_gauss_rule_1d(double a, double b, int cells, int n) {
  IntegrationRule r;
  r.kind = "gauss-cells";
  r.cells = cells;
  r.points.resize(1, cells * n);
  r.weights.resize(cells * n);
  std::vector<double> x, w;
  const double h = (b - a) / cells;
  for (int c = 0; c < cells; ++c) {
    gauss_legendre(n, a + c * h, a + (c + 1) * h, x, w);
    for (int i = 0; i < n; ++i) {
      r.points(0, c * n + i) = x[i];
      r.weights[c * n + i] = w[i];
      r.cell.push_back(c);
    }
  }
  return r;
}


namespace {

void check_dimension(const Domain& d, const ParticleSet& p) {
  if (p.dim != 1 && p.dim != 2)
    throw InputError(fmt::format("integration schemes are implemented in 1D and 2D, got {}D "
                                 "particles",
                                 p.dim));
  if (d.dim != p.dim)
    throw InputError(fmt::format("the domain is {}D but the particles are {}D; build them for "
                                 "the same dimension",
                                 d.dim, p.dim));
}

void check_side(const Domain& d, int side) {
  if (side < 0 || side >= 2 * d.dim)
    throw InputError(fmt::format("side index {} is out of range: a {}D domain has sides 0..{} "
                                 "(0 left, 1 right, 2 bottom, 3 top)",
                                 side, d.dim, 2 * d.dim - 1));
}

std::vector<double> sorted_line(const ParticleSet& p) {
  std::vector<double> xs(p.x.row(0).data(), p.x.row(0).data() + p.size());
  std::sort(xs.begin(), xs.end());
  return xs;
}

/// Particle positions, or every cell boundary of a uniform background grid.
std::vector<double> cell_edges(const Domain& d, const ParticleSet& p, int cells) {
  if (cells <= 0) {
    auto xs = sorted_line(p);
    xs.front() = std::min(xs.front(), d.lower[0]);
    xs.back() = std::max(xs.back(), d.upper[0]);
    return xs;
  }
  std::vector<double> e(cells + 1);
  for (int c = 0; c <= cells; ++c) e[c] = d.lower[0] + (d.upper[0] - d.lower[0]) * c / cells;
  return e;
}

/// 001 eq 66: n_Q = ceil(sqrt(m)) + 2 Gauss points per direction for a cell holding m particles.
int eq66_points(int m) {
  return static_cast<int>(std::ceil(std::sqrt(static_cast<double>(m)))) + 2;
}

bool is_lattice(const ParticleSet& p) {
  return p.lattice[0] >= 2 && p.lattice[1] >= 2 && p.lattice[0] * p.lattice[1] == p.size();
}

/// The set carries its own cells or stress points (an annulus) and no box sides, so no rule
/// on a side of the domain's box applies.
bool sideless(const ParticleSet& p) {
  if (p.quads.empty() && !p.stress_points) return false;
  return std::all_of(p.sides.begin(), p.sides.end(), [](unsigned s) { return s == 0; });
}

void refuse_sideless(const ParticleSet& p, int side) {
  if (sideless(p))
    throw InputError(fmt::format(
        "the particle set has no box sides (it supplies its own cells, e.g. an annulus), so "
        "there is no boundary rule on side {}; load its surfaces with a follower pressure from "
        "the problem instead of tractions on box sides",
        side));
}

/// The cells of a 2D gauss-cells rule (001 §5.3): the lattice quadrilaterals, the set's own
/// quadrilaterals (ParticleSet::quads, cx of them in one row), or a uniform background grid on
/// the domain's box; cell k = i + cx·j.
struct CellLayout {
  bool quads = false;
  bool explicit_quads = false;  ///< the quads are ParticleSet::quads, not lattice cells
  int cx = 0, cy = 0;
  Eigen::Vector2d origin, h;  ///< background grid only
  std::vector<int> n;         ///< Gauss points per direction of each cell
};

CellLayout cell_layout(const Domain& d, const ParticleSet& p, int cells, int nq) {
  CellLayout c;
  if (!p.quads.empty()) {
    // A background grid over the box would put points outside a non-rectangular domain.
    if (cells > 0)
      throw InputError(fmt::format(
          "the particle set supplies its own {} quadrilateral cells (e.g. an annulus), which a "
          "background grid of cells = {} cannot follow; leave cells = 0",
          p.quads.size(), cells));
    for (std::size_t k = 0; k < p.quads.size(); ++k)
      for (int J : p.quads[k])
        if (J < 0 || J >= p.size())
          throw InputError(fmt::format("quadrilateral cell {} names particle {}, but the set "
                                       "has particles 0..{}; fix ParticleSet::quads",
                                       k, J, p.size() - 1));
    if (!p.quad_particles.empty() && p.quad_particles.size() != p.quads.size())
      throw InputError(fmt::format("the particle set gives particle counts for {} of its {} "
                                   "quadrilateral cells; fix ParticleSet::quad_particles (one "
                                   "per quad, or none)",
                                   p.quad_particles.size(), p.quads.size()));
    c.quads = c.explicit_quads = true;
    c.cx = static_cast<int>(p.quads.size());
    c.cy = 1;
    // Each cell holds about one particle, as a lattice cell does (m = 1, n_Q = 3), unless the
    // set says how many its larger cells hold.
    c.n.resize(p.quads.size());
    for (std::size_t k = 0; k < p.quads.size(); ++k) {
      const int m = p.quad_particles.empty() ? 1 : p.quad_particles[k];
      if (m < 1)
        throw InputError(fmt::format("quadrilateral cell {} holds {} particles; "
                                     "ParticleSet::quad_particles must be >= 1",
                                     k, m));
      c.n[k] = nq > 0 ? nq : eq66_points(m);
    }
    return c;
  }
  const double lx = d.upper[0] - d.lower[0], ly = d.upper[1] - d.lower[1];
  // Hexagonal lattices have parallelogram quads: they get a background grid.
  if (cells == 0 && p.placement == Placement::boundary && is_lattice(p) && !p.hexagonal) {
    c.quads = true;
    c.cx = p.lattice[0] - 1;
    c.cy = p.lattice[1] - 1;
    // The half-open lattice cell holds its lower-left particle only: m = 1, n_Q = 3.
    c.n.assign(static_cast<std::size_t>(c.cx) * c.cy, nq > 0 ? nq : eq66_points(1));
    return c;
  }
  if (cells > 0) {
    c.cx = cells;
    c.cy = std::max(1, static_cast<int>(std::lround(cells * ly / lx)));
  } else if (is_lattice(p)) {
    // Inset lattice: one cell around each particle.
    c.cx = p.lattice[0];
    c.cy = p.lattice[1];
  } else {
    // Unstructured: about one particle per (nearly square) cell.
    c.cx = std::max(1, static_cast<int>(std::lround(std::sqrt(p.size() * lx / ly))));
    c.cy = std::max(1, static_cast<int>(std::lround(c.cx * ly / lx)));
  }
  c.origin = d.lower;
  c.h << lx / c.cx, ly / c.cy;
  // m of eq 66: particles in each half-open cell (the last row and column closed).
  std::vector<int> m(static_cast<std::size_t>(c.cx) * c.cy, 0);
  for (int J = 0; J < p.size(); ++J) {
    const auto index = [&](int a, int count) {
      const double s = (p.x(a, J) - c.origin[a]) / c.h[a];
      return std::clamp(static_cast<int>(std::floor(s + 1e-12)), 0, count - 1);
    };
    ++m[index(0, c.cx) + c.cx * index(1, c.cy)];
  }
  c.n.resize(m.size());
  for (std::size_t k = 0; k < m.size(); ++k) c.n[k] = nq > 0 ? nq : eq66_points(m[k]);
  return c;
}

/// Bilinear shape functions of the reference square and their ξ-derivatives, nodes in the
/// order (-1,-1), (1,-1), (1,1), (-1,1).
void bilinear(double xi, double eta, double* n, double* dxi, double* deta) {
  constexpr std::array<double, 4> a{-1, 1, 1, -1}, b{-1, -1, 1, 1};
  for (int k = 0; k < 4; ++k) {
    n[k] = 0.25 * (1 + a[k] * xi) * (1 + b[k] * eta);
    dxi[k] = 0.25 * a[k] * (1 + b[k] * eta);
    deta[k] = 0.25 * b[k] * (1 + a[k] * xi);
  }
}

IntegrationRule gauss_cells_2d(const ParticleSet& p, const CellLayout& c) {
  IntegrationRule r;
  r.kind = "gauss-cells";
  r.cells = c.cx * c.cy;
  Eigen::Index total = 0;
  for (int n : c.n) total += n * n;
  r.points.resize(2, total);
  r.weights.resize(total);
  r.cell.reserve(total);
  std::vector<double> gx, wx, gy, wy;
  double N[4], dxi[4], deta[4];
  Eigen::Index q = 0;
  for (int j = 0; j < c.cy; ++j)
    for (int i = 0; i < c.cx; ++i) {
      const int k = i + c.cx * j, n = c.n[k];
      if (c.quads) {
        // 001 eqs 67-68: the bilinear map of [-1,1]² onto the quadrilateral, weights w_a w_b det J.
        const int nx = c.cx + 1;
        const std::array<int, 4> node =
            c.explicit_quads ? p.quads[k]
                             : std::array<int, 4>{i + nx * j, i + 1 + nx * j,
                                                  i + 1 + nx * (j + 1), i + nx * (j + 1)};
        gauss_legendre(n, -1, 1, gx, wx);
        for (int b = 0; b < n; ++b)
          for (int a = 0; a < n; ++a, ++q) {
            bilinear(gx[a], gx[b], N, dxi, deta);
            Eigen::Vector2d x = Eigen::Vector2d::Zero();
            Eigen::Matrix2d J = Eigen::Matrix2d::Zero();
            for (int v = 0; v < 4; ++v) {
              x += N[v] * p.x.col(node[v]);
              J.col(0) += dxi[v] * p.x.col(node[v]);
              J.col(1) += deta[v] * p.x.col(node[v]);
            }
            const double det = J.determinant();
            if (!(det > 0) && c.explicit_quads)
              throw InputError(fmt::format(
                  "quadrilateral cell {} with particles {}, {}, {}, {} is inverted or "
                  "degenerate; lower the jitter or list its corners counter-clockwise",
                  k, node[0], node[1], node[2], node[3]));
            if (!(det > 0))
              throw InputError(fmt::format(
                  "lattice cell ({}, {}) with particles {}, {}, {}, {} is inverted or "
                  "degenerate; lower the perturbation or use a background grid (cells > 0)",
                  i, j, node[0], node[1], node[2], node[3]));
            r.points.col(q) = x;
            r.weights[q] = wx[a] * wx[b] * det;
            r.cell.push_back(k);
          }
      } else {
        gauss_legendre(n, c.origin[0] + i * c.h[0], c.origin[0] + (i + 1) * c.h[0], gx, wx);
        gauss_legendre(n, c.origin[1] + j * c.h[1], c.origin[1] + (j + 1) * c.h[1], gy, wy);
        for (int b = 0; b < n; ++b)
          for (int a = 0; a < n; ++a, ++q) {
            r.points.col(q) << gx[a], gy[b];
            r.weights[q] = wx[a] * wy[b];
            r.cell.push_back(k);
          }
      }
    }
  return r;
}

/// Gauss points on the segments of side s that bound the domain rule's cells, with the
/// adjacent cell's point count.
IntegrationRule gauss_cells_boundary_2d(const Domain& d, const ParticleSet& p,
                                        const CellLayout& c, int side) {
  const int along = side < 2 ? 1 : 0, normal = 1 - along;
  const double at = side % 2 == 0 ? d.lower[normal] : d.upper[normal];
  const int segments = along == 0 ? c.cx : c.cy;
  // Cell (i, j) next to segment k of the side.
  const auto cell_of = [&](int k) {
    switch (side) {
      case 0: return c.cx * k;
      case 1: return c.cx - 1 + c.cx * k;
      case 2: return k;
      default: return k + c.cx * (c.cy - 1);
    }
  };
  std::vector<double> t(segments + 1);
  for (int k = 0; k <= segments; ++k) {
    if (c.quads) {
      // Boundary particles stay on their side, so the lattice's side particles are the
      // cells' corners there.
      const int nx = c.cx + 1, ny = c.cy + 1;
      const int J = side == 0   ? nx * k
                    : side == 1 ? nx - 1 + nx * k
                    : side == 2 ? k
                                : k + nx * (ny - 1);
      t[k] = p.x(along, J);
    } else {
      t[k] = c.origin[along] + k * c.h[along];
    }
  }
  t.front() = d.lower[along];
  t.back() = d.upper[along];
  IntegrationRule r;
  r.kind = "gauss-cells-boundary";
  r.cells = segments;
  std::vector<double> g, w;
  std::vector<double> px, pw;
  for (int k = 0; k < segments; ++k) {
    gauss_legendre(c.n[cell_of(k)], t[k], t[k + 1], g, w);
    for (std::size_t a = 0; a < g.size(); ++a) {
      px.push_back(g[a]);
      pw.push_back(w[a]);
      r.cell.push_back(k);
    }
  }
  r.points.resize(2, static_cast<Eigen::Index>(px.size()));
  r.points.row(along) = Eigen::Map<const Eigen::RowVectorXd>(px.data(), px.size());
  r.points.row(normal).setConstant(at);
  r.weights = Eigen::Map<const Eigen::VectorXd>(pw.data(), pw.size());
  return r;
}

class Nodal final : public IntegrationScheme {
 public:
  IntegrationRule rule(const Domain&, const ParticleSet& p) const override {
    IntegrationRule r;
    r.kind = "nodal";
    r.points = p.x;
    r.weights = p.volume;
    r.cells = p.size();
    r.nodal_points = p.size();
    for (int i = 0; i < p.size(); ++i) r.cell.push_back(i);
    return r;
  }
};

class GaussCells final : public IntegrationScheme {
 public:
  GaussCells(int n, int cells, int nq) : n_(n), cells_(cells), nq_(nq) {}
  IntegrationRule rule(const Domain& d, const ParticleSet& p) const override {
    check_dimension(d, p);
    if (p.dim == 2) return gauss_cells_2d(p, cell_layout(d, p, cells_, nq_));
    const auto e = cell_edges(d, p, cells_);
    IntegrationRule r;
    r.kind = "gauss-cells";
    r.cells = static_cast<int>(e.size()) - 1;
    r.points.resize(1, r.cells * n_);
    r.weights.resize(r.cells * n_);
    std::vector<double> x, w;
    for (int c = 0; c < r.cells; ++c) {
      gauss_legendre(n_, e[c], e[c + 1], x, w);
      for (int i = 0; i < n_; ++i) {
        r.points(0, c * n_ + i) = x[i];
        r.weights[c * n_ + i] = w[i];
        r.cell.push_back(c);
      }
    }
    return r;
  }
  IntegrationRule boundary_rule(const Domain& d, const ParticleSet& p, int side) const override {
    check_dimension(d, p);
    check_side(d, side);
    if (p.dim == 1) return nodal_boundary_rule(d, p, side);
    refuse_sideless(p, side);
    return gauss_cells_boundary_2d(d, p, cell_layout(d, p, cells_, nq_), side);
  }

 private:
  int n_, cells_, nq_;
};

class StressPointIntegration final : public IntegrationScheme {
 public:
  explicit StressPointIntegration(StressPointLayout layout) : layout_(layout) {}
  IntegrationRule rule(const Domain& d, const ParticleSet& p) const override {
    check_dimension(d, p);
    IntegrationRule r;
    r.kind = "stress-points";
    // 001 eqs 64-65, 000 eq 3.19: the particles, then the stress points (1D: the interval
    // midpoints), each weighted by its cell of the joint Voronoi diagram; `cell` is the
    // particle, then the stress point's index.
    if (p.stress_points && layout_ == StressPointLayout::triangle_centres)
      throw InputError(
          "the particle set supplies quad-centre stress points (e.g. an annulus), so the "
          "triangle-centres layout cannot apply; use layout=quad-centres");
    const StressPoints s = p.stress_points ? *p.stress_points : make_stress_points(p, d, layout_);
    if (s.particle_volume.size() != p.size() || s.volume.size() != s.x.cols() ||
        s.x.rows() != p.dim)
      throw InputError(fmt::format(
          "the set's stress points do not match it: {} particle volumes for {} particles, {} "
          "volumes for {} {}D stress points",
          s.particle_volume.size(), p.size(), s.volume.size(), s.x.cols(), s.x.rows()));
    const int n = p.size(), ns = static_cast<int>(s.x.cols());
    r.points.resize(p.dim, n + ns);
    r.points << p.x, s.x;
    r.weights.resize(n + ns);
    r.weights << s.particle_volume, s.volume;
    r.cells = ns;
    r.nodal_points = n;
    for (int q = 0; q < n + ns; ++q) r.cell.push_back(q < n ? q : q - n);
    return r;
  }

 private:
  StressPointLayout layout_;
};

}  // namespace

IntegrationRule IntegrationScheme::boundary_rule(const Domain& domain, const ParticleSet& particles,
                                                 int side) const {
  return nodal_boundary_rule(domain, particles, side);
}

IntegrationRule nodal_boundary_rule(const Domain& domain, const ParticleSet& p, int side) {
  check_dimension(domain, p);
  check_side(domain, side);
  if (p.size() == 0) throw InputError("a boundary rule needs particles, got none");
  if (p.dim == 2) refuse_sideless(p, side);
  IntegrationRule r;
  r.kind = "nodal-boundary";
  r.cells = 1;
  if (p.dim == 1) {
    // The end point itself, measure 1, carried by the end particle.
    Eigen::Index J = 0;
    if (side == 0) p.x.row(0).minCoeff(&J);
    else p.x.row(0).maxCoeff(&J);
    r.points.resize(1, 1);
    r.points(0, 0) = side == 0 ? domain.lower[0] : domain.upper[0];
    r.weights = Eigen::VectorXd::Ones(1);
    r.cell = {static_cast<int>(J)};
    return r;
  }
  if (p.sides.size() != static_cast<std::size_t>(p.size()))
    throw InputError("the nodal boundary rule needs the particles' side flags "
                     "(ParticleSet::sides); build the particles with rectangle_lattice");
  std::vector<int> on;
  for (int J = 0; J < p.size(); ++J)
    if (p.sides[J] & side_bit(side)) on.push_back(J);
  if (on.empty())
    throw InputError(fmt::format("no particle is flagged on side {} (0 left, 1 right, 2 bottom, "
                                 "3 top); the set's `sides` must mark its boundary layer",
                                 side));
  const int along = side < 2 ? 1 : 0, normal = 1 - along;
  std::stable_sort(on.begin(), on.end(),
                   [&](int a, int b) { return p.x(along, a) < p.x(along, b); });
  // 001 eq 61's Γ_J: each particle's share of the side reaches halfway to its neighbours,
  // the ends to the corners, so the weights telescope to the side length.
  const int n = static_cast<int>(on.size());
  const double lo = domain.lower[along], hi = domain.upper[along];
  r.cells = n;
  r.points.resize(2, n);
  r.weights.resize(n);
  double from = lo;
  for (int k = 0; k < n; ++k) {
    const double to = k + 1 < n ? 0.5 * (p.x(along, on[k]) + p.x(along, on[k + 1])) : hi;
    r.points(along, k) = p.x(along, on[k]);
    r.points(normal, k) = side % 2 == 0 ? domain.lower[normal] : domain.upper[normal];
    r.weights[k] = to - from;
    from = to;
  }
  r.cell = on;
  return r;
}

void register_nodal(IntegrationRegistry& r) {
  r.add("nodal", "nodal integration: particles are the quadrature points, weights their volumes "
                 "(001 §5.1)",
        {}, [](const Params&) { return std::make_unique<Nodal>(); });
}

void register_gauss_cells(IntegrationRegistry& r) {
  r.add("gauss-cells",
        "Gauss-Legendre cells (001 §5.3): 1D between neighbouring particles or a uniform grid; "
        "2D the lattice quadrilaterals (boundary placement, eqs 67-68), the set's own "
        "quadrilaterals (an annulus) or a background grid",
        {capped(ParamSpec::count("n", 10, 1, "1D: Gauss points per cell (2D uses nq; at most 64)"),
                64),
         capped(ParamSpec::count("cells", 0, 0,
                                 "uniform background cells along x (0: cells between particles; "
                                 "2D: lattice quadrilaterals, else about one particle per cell); "
                                 "2D rows follow for nearly square cells; at most 10^6"),
                1e6),
         capped(ParamSpec::count("nq", 0, 0,
                                 "2D: Gauss points per cell and direction; 0: n_Q = ceil(sqrt(m)) "
                                 "+ 2 with m particles in the cell (001 eq 66); at most 64"),
                64)},
        [](const Params& p) {
          return std::make_unique<GaussCells>(p.integer("n"), p.integer("cells"), p.integer("nq"));
        });
}

void register_stress_points(IntegrationRegistry& r) {
  r.add("stress-points",
        "the particles plus stress points, weights from their joint Voronoi diagram (000 §2.4, "
        "001 §5.2 eqs 64-65; 1D: the particles and the interval midpoints, 000 eq 3.19)",
        {ParamSpec::choice("layout", "quad-centres", {"quad-centres", "triangle-centres"},
                           "2D: stress points at lattice quadrilateral or triangle centres "
                           "(000 Fig. 8)")},
        [](const Params& p) {
          return std::make_unique<StressPointIntegration>(
              p.text("layout") == "quad-centres" ? StressPointLayout::quad_centres
                                                 : StressPointLayout::triangle_centres);
        });
}

}  // namespace mfv
