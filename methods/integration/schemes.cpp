/// Nodal integration (001 §5.1), background-cell Gauss quadrature (001 §5.3, eq 66) and stress
/// points at cell centres (000 §2.4, 001 §5.2), in 1D; 2D cells arrive with 2D problems.
#include <algorithm>
#include <cmath>

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

std::vector<double> sorted_line(const ParticleSet& p) {
  if (p.dim != 1)
    throw InputError("this integration scheme is implemented in 1D so far (2D cells arrive with "
                     "the 2D problems)");
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

class Nodal final : public IntegrationScheme {
 public:
  IntegrationRule rule(const Domain&, const ParticleSet& p) const override {
    IntegrationRule r;
    r.kind = "nodal";
    r.points = p.x;
    r.weights = p.volume;
    r.cells = p.size();
    for (int i = 0; i < p.size(); ++i) r.cell.push_back(i);
    return r;
  }
};

class GaussCells final : public IntegrationScheme {
 public:
  GaussCells(int n, int cells) : n_(n), cells_(cells) {}
  IntegrationRule rule(const Domain& d, const ParticleSet& p) const override {
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

 private:
  int n_, cells_;
};

class StressPointIntegration final : public IntegrationScheme {
 public:
  IntegrationRule rule(const Domain& d, const ParticleSet& p) const override {
    // 1D: one stress point at each interval midpoint, weighted by the interval (000 §2.4).
    const auto e = cell_edges(d, p, 0);
    IntegrationRule r;
    r.kind = "stress-points";
    r.cells = static_cast<int>(e.size()) - 1;
    r.points.resize(1, r.cells);
    r.weights.resize(r.cells);
    for (int c = 0; c < r.cells; ++c) {
      r.points(0, c) = 0.5 * (e[c] + e[c + 1]);
      r.weights[c] = e[c + 1] - e[c];
      r.cell.push_back(c);
    }
    return r;
  }
};

}  // namespace

void register_nodal(IntegrationRegistry& r) {
  r.add("nodal", "nodal integration: particles are the quadrature points, weights their volumes "
                 "(001 §5.1)",
        {}, [](const Params&) { return std::make_unique<Nodal>(); });
}

void register_gauss_cells(IntegrationRegistry& r) {
  r.add("gauss-cells",
        "Gauss-Legendre cells: between neighbouring particles, or a uniform grid (001 §5.3)",
        {ParamSpec::count("n", 10, 1, "Gauss points per cell and direction"),
         ParamSpec::count("cells", 0, 0, "uniform background cells (0: cells between particles)")},
        [](const Params& p) { return std::make_unique<GaussCells>(p.integer("n"), p.integer("cells")); });
}

void register_stress_points(IntegrationRegistry& r) {
  r.add("stress-points", "stress points at cell centres, weights from the Voronoi/cell measure "
                         "(000 §2.4, 001 §5.2)",
        {}, [](const Params&) { return std::make_unique<StressPointIntegration>(); });
}

}  // namespace mfv

namespace mfv {
IntegrationRule IntegrationScheme::boundary_rule(const Domain& domain, const ParticleSet& particles,
                                                 int side) const {
  return nodal_boundary_rule(domain, particles, side);
}
IntegrationRule nodal_boundary_rule(const Domain&, const ParticleSet&, int) {
  throw std::logic_error("nodal_boundary_rule: not yet implemented");
}
}  // namespace mfv
