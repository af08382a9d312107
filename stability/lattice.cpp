#include "stability/lattice.hpp"

#include <cmath>
#include <numbers>
#include <sstream>

#include <fmt/format.h>

#include "methods/core/errors.hpp"

namespace mfv {

LatticeKind lattice_kind_from(const std::string& name) {
  if (name == "line") return LatticeKind::line;
  if (name == "rectangular") return LatticeKind::rectangular;
  if (name == "hexagonal") return LatticeKind::hexagonal;
  throw InputError(
      fmt::format("unknown lattice '{}'; valid: line, rectangular, hexagonal", name));
}

std::string to_string(LatticeKind kind) {
  switch (kind) {
    case LatticeKind::line: return "line";
    case LatticeKind::rectangular: return "rectangular";
    case LatticeKind::hexagonal: return "hexagonal";
  }
  return "?";
}

LatticePatch lattice_patch(LatticeKind kind, double dx, int half_width) {
  if (!(dx > 0)) throw InputError(fmt::format("lattice spacing {} must be positive", dx));
  if (half_width < 2)
    throw InputError(fmt::format("a lattice patch needs a half width of at least 2 spacings, "
                                 "got {}",
                                 half_width));
  LatticePatch p;
  p.kind = kind;
  p.spacing = dx;
  const int n = 2 * half_width + 1;
  const double L = half_width * dx;
  if (kind == LatticeKind::line) {
    p.domain = Domain::interval(-L, L);
    p.particles = uniform_line(p.domain, n);
    p.centre = half_width;
    p.cell_volume = dx;
    return p;
  }
  if (kind == LatticeKind::rectangular) {
    p.domain = Domain::rectangle(-L, -L, L, L);
    p.particles = rectangle_lattice(p.domain, n, n, Placement::boundary);
    p.centre = half_width + n * half_width;
    p.cell_volume = dx * dx;
    return p;
  }
  // Even rows of the lattice must be the unshifted ones (make_stress_points splits by parity).
  if (half_width % 2 != 0)
    throw InputError(fmt::format("a hexagonal patch needs an even half width, got {}", half_width));
  // Hexagonal: row j at y = (j − hw) √3/2 dx, shifted by dx/2 when j − hw is odd, so the
  // centre row (j = hw) is unshifted and holds the origin.
  const double dy = std::sqrt(3.0) / 2 * dx;
  p.domain = Domain::rectangle(-L - dx, -half_width * dy - dy / 2, L + dx, half_width * dy + dy / 2);
  ParticleSet& s = p.particles;
  s.dim = 2;
  s.x.resize(2, n * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int row = j - half_width;
      s.x(0, i + n * j) = (i - half_width) * dx + (std::abs(row) % 2 == 1 ? dx / 2 : 0.0);
      s.x(1, i + n * j) = row * dy;
    }
  s.spacing = dx;
  s.lattice = Eigen::Vector2i(n, n);
  s.hexagonal = true;
  s.placement = Placement::boundary;
  s.sides.assign(n * n, 0u);
  s.dilation = Eigen::VectorXd::Ones(n * n);
  s.volume = voronoi_areas(s.x, p.domain);
  p.centre = half_width + n * half_width;
  p.cell_volume = dx * dy;
  return p;
}

double brillouin_boundary(LatticeKind kind, double dx, double theta) {
  const double pi = std::numbers::pi;
  const double c = std::abs(std::cos(theta)), s = std::abs(std::sin(theta));
  switch (kind) {
    case LatticeKind::line: return pi / dx;
    case LatticeKind::rectangular:
      return std::min(c > 1e-14 ? pi / (dx * c) : 1e300, s > 1e-14 ? pi / (dx * s) : 1e300);
    case LatticeKind::hexagonal: {
      // Edge normals of the zone at 30° + k·60°, inscribed radius 2π/(√3 Δx).
      const double r = 2 * pi / (std::sqrt(3.0) * dx);
      double best = 1e300;
      for (int k = 0; k < 6; ++k) {
        const double ck = std::cos(theta - (pi / 6 + k * pi / 3));
        if (ck > 1e-14) best = std::min(best, r / ck);
      }
      return best;
    }
  }
  return pi / dx;
}

}  // namespace mfv
