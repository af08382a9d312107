/// Ring particle sets: a polar lattice on an annulus with its exact polar cell volumes, its
/// quadrilateral cells and its quad-centre stress points (the joint Voronoi split of 001 eq 65).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include <fmt/format.h>

#include "methods/core/errors.hpp"
#include "methods/core/resources.hpp"
#include "methods/particles.hpp"

namespace mfv {

namespace {

void check_ring(const AnnulusLattice& g) {
  if (!std::isfinite(g.inner) || !(g.inner > 0))
    throw InputError(fmt::format("annulus inner radius must be finite and > 0, got {}",
                                 g.inner));
  if (!std::isfinite(g.outer) || !(g.outer > g.inner))
    throw InputError(fmt::format(
        "annulus outer radius must be finite and larger than the inner radius {}, got {}",
        g.inner, g.outer));
  // The volumes square the radii: b² - a² must neither overflow nor vanish.
  if (!std::isfinite(g.outer * g.outer) || !(g.outer * g.outer - g.inner * g.inner > 0))
    throw InputError(fmt::format(
        "annulus outer radius {} with inner radius {}: b² - a² must be a positive finite "
        "number; rescale the lengths",
        g.outer, g.inner));
  if (g.radial < 2)
    throw InputError(fmt::format(
        "annulus radial count must be >= 2 (both surfaces carry particles), got {}", g.radial));
  if (g.circumferential < 3)
    throw InputError(fmt::format(
        "annulus circumferential count must be >= 3 (a ring of cells), got {}",
        g.circumferential));
  if (!(g.jitter >= 0 && g.jitter < 0.5))
    throw InputError(fmt::format(
        "annulus jitter must be in [0, 0.5) of the spacing so particles keep their lattice "
        "order, got {}",
        g.jitter));
}

}  // namespace

ParticleSet annulus_lattice(const AnnulusLattice& g) {
  check_ring(g);
  // Counted in 64 bits before anything is allocated (the int tables' limit).
  const std::int64_t count =
      checked_particle_count(g.radial, g.circumferential, "annulus lattice (radial × circumferential)");
  check_case_memory(count, 2, fmt::format("a {} × {} annulus lattice", g.radial,
                                          g.circumferential));
  const int nr = g.radial, nt = g.circumferential, n = static_cast<int>(count);
  const double a = g.inner, b = g.outer;
  const double dr = (b - a) / (nr - 1), dt = 2 * std::numbers::pi / nt;
  const auto radius = [&](int i) { return i == nr - 1 ? b : a + i * dr; };
  // Radii of the cell faces between rings, clipped to the surfaces (half cells there).
  const auto face = [&](int i) {  // r_{i-½}
    return i <= 0 ? a : i >= nr ? b : 0.5 * (radius(i - 1) + radius(i));
  };
  const auto cell_area = [&](int i) {  // polar cell between rings i and i+1
    return 0.5 * dt * (radius(i + 1) * radius(i + 1) - radius(i) * radius(i));
  };

  ParticleSet p;
  p.dim = 2;
  p.x.resize(2, n);
  p.volume.resize(n);
  p.local_spacing.resize(n);
  p.sides.assign(n, 0u);
  std::mt19937_64 rng(g.seed);
  std::uniform_real_distribution<double> u(-g.jitter, g.jitter);
  for (int i = 0; i < nr; ++i) {
    const double r0 = radius(i);
    const double lo = face(i), hi = face(i + 1);
    const double dv = 0.5 * dt * (hi * hi - lo * lo);
    for (int j = 0; j < nt; ++j) {
      const int J = j + nt * i;
      double r = r0, t = j * dt;
      if (g.jitter > 0) {
        // Two draws per particle whatever moves, so a particle's offsets depend only on the
        // seed and its index (as rectangle_lattice); surface particles stay on their circle.
        const double o_r = u(rng) * dr, o_t = u(rng) * dt;
        if (i != 0 && i != nr - 1) r += o_r;
        t += o_t;
      }
      p.x(0, J) = r * std::cos(t);
      p.x(1, J) = r * std::sin(t);
      p.volume[J] = dv;
      p.local_spacing[J] = std::max(dr, r0 * dt);
    }
  }

  const int ncell = nt * (nr - 1);
  p.quads.reserve(ncell);
  auto sp = std::make_shared<StressPoints>();
  sp->x.resize(2, ncell);
  sp->volume.resize(ncell);
  sp->particle_volume = Eigen::VectorXd::Zero(n);
  for (int i = 0; i + 1 < nr; ++i) {
    const double ac = cell_area(i), rc = 0.5 * (radius(i) + radius(i + 1));
    for (int j = 0; j < nt; ++j) {
      const int s = j + nt * i, jn = (j + 1) % nt;
      // (r, θ) is right-handed, so r first then θ runs counter-clockwise.
      const std::array<int, 4> q{j + nt * i, j + nt * (i + 1), jn + nt * (i + 1), jn + nt * i};
      p.quads.push_back(q);
      const double tc = (j + 0.5) * dt;
      sp->x(0, s) = rc * std::cos(tc);
      sp->x(1, s) = rc * std::sin(tc);
      // The split of a square lattice's joint Voronoi diagram with quad-centre stress points
      // (make_stress_points; test RingParticles.SquareLatticeSplitIsHalfAndEighths checks
      // it): the cells are diamonds, A/2 for the stress point and A/8 from each corner.
      sp->volume[s] = 0.5 * ac;
      for (int J : q) sp->particle_volume[J] += 0.125 * ac;
    }
  }
  p.stress_points = std::move(sp);
  p.dilation = p.local_spacing;
  p.spacing = std::max(dr, 0.5 * (a + b) * dt);
  return p;
}

}  // namespace mfv
