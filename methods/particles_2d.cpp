/// 2D particle sets: rectangle lattices, Voronoi volumes (voro++), stress points (001 eq 65).
#include <voro++/voro++.hh>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <stdexcept>

#include <fmt/format.h>

#include "methods/core/errors.hpp"
#include "methods/core/resources.hpp"
#include "methods/particles.hpp"

namespace mfv {

namespace {

/// Lattice coordinate of index i along one side: on the boundary (Fig. 4b) or half a spacing
/// inside (Fig. 4a).
double lattice_coordinate(double lo, double d, int i, Placement placement) {
  return lo + (placement == Placement::boundary ? i : i + 0.5) * d;
}

/// Exact lattice cell volumes of an unperturbed set (001 §6): boundary placement halves the
/// cells on a side and quarters them at corners; inset placement gives every particle dx·dy.
double lattice_volume(double dx, double dy, int i, int j, int nx, int ny, Placement placement) {
  if (placement == Placement::inset) return dx * dy;
  const double fx = (i == 0 || i == nx - 1) ? 0.5 : 1.0;
  const double fy = (j == 0 || j == ny - 1) ? 0.5 : 1.0;
  return fx * dx * fy * dy;
}

/// voro++'s block index of a coordinate (container_base::put_remap: step_int((x-a)·xsp)).
int voro_block(double x, double sp) {
  const double t = x * sp;
  return t < 0 ? static_cast<int>(t) - 1 : static_cast<int>(t);
}

/// A coordinate in [0, side] moved into voro++'s half-open range [0, side) of `blocks` blocks:
/// voro++ rejects points on the upper face, so those go down by a few ulps (at most 1e-12 of
/// the side, far below any cell size), which changes the areas only at round-off level.
double inside_blocks(double x, double side, double sp, int blocks) {
  const double floor_x = side * (1.0 - 1e-12);
  while (voro_block(x, sp) >= blocks) {
    x = std::nextafter(x, 0.0);
    if (x < floor_x)
      throw std::runtime_error(fmt::format(
          "voronoi_areas: cannot place coordinate {} inside voro++'s container of side {}", x,
          side));
  }
  return x;
}

}  // namespace

ParticleSet rectangle_lattice(const Domain& domain, std::int64_t nx_in, std::int64_t ny_in,
                              Placement placement, double perturbation, std::uint64_t seed) {
  if (domain.dim != 2)
    throw InputError(fmt::format(
        "rectangle_lattice needs a 2D rectangle domain, got a {}D one; build it with "
        "Domain::rectangle",
        domain.dim));
  const int min_n = placement == Placement::boundary ? 2 : 1;
  if (nx_in < min_n || ny_in < min_n)
    throw InputError(fmt::format(
        "a {} lattice needs at least {} particles per direction, got nx = {}, ny = {}; raise "
        "--nodes",
        placement == Placement::boundary ? "boundary-placement" : "inset", min_n, nx_in, ny_in));
  // Counted in 64 bits and checked before anything is allocated: past 46,340 per side the
  // int product overflows, and long before that the case outgrows the machine.
  const std::int64_t count = checked_particle_count(nx_in, ny_in, "2D lattice");
  check_case_memory(count, 2, fmt::format("a {} × {} lattice", nx_in, ny_in));
  const int nx = static_cast<int>(nx_in), ny = static_cast<int>(ny_in);
  if (!(perturbation >= 0 && perturbation < 0.5))
    throw InputError(fmt::format(
        "perturbation must be in [0, 0.5) of the spacing so particles keep their lattice "
        "order, got {}",
        perturbation));
  const double x0 = domain.lower[0], y0 = domain.lower[1];
  const double x1 = domain.upper[0], y1 = domain.upper[1];
  const double dx = (x1 - x0) / (placement == Placement::boundary ? nx - 1 : nx);
  const double dy = (y1 - y0) / (placement == Placement::boundary ? ny - 1 : ny);
  const int n = nx * ny;

  ParticleSet p;
  p.dim = 2;
  p.x.resize(2, n);
  p.volume.resize(n);
  p.sides.assign(n, 0u);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-perturbation, perturbation);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int J = i + nx * j;
      unsigned s = 0;
      if (i == 0) s |= Side::left;
      if (i == nx - 1) s |= Side::right;
      if (j == 0) s |= Side::bottom;
      if (j == ny - 1) s |= Side::top;
      p.sides[J] = s;
      double x = lattice_coordinate(x0, dx, i, placement);
      double y = lattice_coordinate(y0, dy, j, placement);
      if (perturbation > 0) {
        // Two draws per particle whatever moves, so the offsets of a particle depend only on
        // the seed and its index. Boundary placement: a particle on a left/right side keeps
        // its x, on a bottom/top side its y (so corners stay).
        const double ox = u(rng) * dx, oy = u(rng) * dy;
        const bool free = placement == Placement::inset;
        if (free || !(s & (Side::left | Side::right))) x = std::clamp(x + ox, x0, x1);
        if (free || !(s & (Side::bottom | Side::top))) y = std::clamp(y + oy, y0, y1);
      }
      p.x(0, J) = x;
      p.x(1, J) = y;
      p.volume[J] = lattice_volume(dx, dy, i, j, nx, ny, placement);
    }
  if (perturbation > 0) p.volume = voronoi_areas(p.x, domain);
  p.dilation = Eigen::VectorXd::Constant(n, dx);
  p.spacing = dx;
  p.lattice = Eigen::Vector2i(nx, ny);
  p.placement = placement;
  return p;
}

/// voro++ is 3D: the rectangle becomes a non-periodic slab container with every point at
/// mid-height, so each cell is a prism whose volume is the 2D area times the slab height. The
/// coordinates are shifted and scaled so the longer side is 1 (voro++'s tolerances are
/// absolute); the slab is about one mean spacing high, since a prism much taller than wide
/// makes voro++ search far blocks for cutting neighbours (O(N²) at unit height). The block
/// grid holds about 5 points per block (the voro++ recommendation), so the cost is O(N).
Eigen::VectorXd voronoi_areas(const Eigen::MatrixXd& points, const Domain& domain) {
  if (domain.dim != 2 || points.rows() != 2)
    throw InputError(fmt::format(
        "voronoi_areas needs 2D points (got {} rows) in a 2D rectangle (got a {}D domain)",
        points.rows(), domain.dim));
  const int n = static_cast<int>(points.cols());
  if (n == 0) return Eigen::VectorXd();
  const Eigen::Vector2d lo = domain.lower.head<2>(), hi = domain.upper.head<2>();
  const Eigen::Vector2d side = hi - lo;
  const double scale = side.maxCoeff();
  const double sx = side[0] / scale, sy = side[1] / scale;
  const double per_block = 5.0;
  const double blocks = std::max(1.0, n / per_block);
  const int bx = std::max(1, static_cast<int>(std::lround(std::sqrt(blocks * sx / sy))));
  const int by = std::max(1, static_cast<int>(std::lround(std::sqrt(blocks * sy / sx))));
  const double height = std::sqrt(sx * sy / n);
  voro::container con(0, sx, 0, sy, 0, height, bx, by, 1, false, false, false, 8);

  // Points outside by at most 1e-12 of a side (round-off of their construction) are clamped.
  const double slack = 1e-12;
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector2d t = (points.col(k) - lo).cwiseQuotient(side);
    if (!(t.minCoeff() >= -slack && t.maxCoeff() <= 1 + slack))
      throw InputError(fmt::format(
          "voronoi_areas: point {} at ({}, {}) lies outside the rectangle [{}, {}] × [{}, {}]; "
          "move it inside or enlarge the domain",
          k, points(0, k), points(1, k), lo[0], hi[0], lo[1], hi[1]));
    const double x = inside_blocks(std::clamp(t[0], 0.0, 1.0) * sx, sx, con.xsp, bx);
    const double y = inside_blocks(std::clamp(t[1], 0.0, 1.0) * sy, sy, con.ysp, by);
    con.put(k, x, y, 0.5 * height);
  }
  if (con.total_particles() != n)
    throw std::runtime_error(fmt::format(
        "voronoi_areas: voro++ stored {} of {} points", con.total_particles(), n));

  Eigen::VectorXd area = Eigen::VectorXd::Constant(n, -1.0);
  voro::c_loop_all loop(con);
  voro::voronoicell cell;
  if (loop.start()) do {
      const int k = loop.pid();
      if (!con.compute_cell(cell, loop))
        throw std::runtime_error(fmt::format(
            "voronoi_areas: voro++ could not compute the cell of point {} at ({}, {})", k,
            points(0, k), points(1, k)));
      area[k] = cell.volume() / height * scale * scale;
    } while (loop.inc());
  for (int k = 0; k < n; ++k)
    if (!(area[k] > 0))
      throw std::runtime_error(
          fmt::format("voronoi_areas: voro++ gave no positive cell for point {}", k));
  return area;
}

StressPoints make_stress_points(const ParticleSet& particles, const Domain& domain,
                                StressPointLayout layout) {
  if (domain.dim != particles.dim)
    throw InputError(fmt::format(
        "stress points need a domain of the particles' dimension: particles are {}D, the "
        "domain {}D",
        particles.dim, domain.dim));
  const int n = particles.size();
  StressPoints sp;
  if (particles.dim == 1) {
    // Midpoints of consecutive sorted particles; one 1D Voronoi diagram of the merged,
    // alternating set p0 s0 p1 s1 ... gives V^P and V^SP (001 eq 65).
    if (n < 2) throw InputError("stress points on a line need at least 2 particles");
    std::vector<int> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return particles.x(0, a) < particles.x(0, b); });
    Eigen::VectorXd merged(2 * n - 1);
    for (int k = 0; k < n; ++k) {
      merged[2 * k] = particles.x(0, order[k]);
      if (k + 1 < n)
        merged[2 * k + 1] = 0.5 * (particles.x(0, order[k]) + particles.x(0, order[k + 1]));
    }
    const Eigen::VectorXd v = voronoi_volumes_1d(merged, domain.lower[0], domain.upper[0]);
    sp.x.resize(1, n - 1);
    sp.volume.resize(n - 1);
    sp.particle_volume.resize(n);
    for (int k = 0; k < n; ++k) {
      sp.particle_volume[order[k]] = v[2 * k];
      if (k + 1 < n) {
        sp.x(0, k) = merged[2 * k + 1];
        sp.volume[k] = v[2 * k + 1];
      }
    }
    return sp;
  }
  if (particles.dim != 2)
    throw InputError(fmt::format("stress points need 1D or 2D particles, got {}D", particles.dim));
  const int nx = particles.lattice[0], ny = particles.lattice[1];
  if (nx == 0 || ny == 0)
    throw InputError(
        "stress points need a lattice particle set (ParticleSet::lattice is zero); build the "
        "particles with rectangle_lattice");
  if (nx < 2 || ny < 2 || nx * ny != n)
    throw InputError(fmt::format(
        "stress points need a lattice of at least 2 × 2 particles matching the set, got {} × {} "
        "for {} particles",
        nx, ny, n));
  // Quad (i, j) has corners (i,j), (i+1,j), (i+1,j+1), (i,j+1) (000 Fig. 8); quad centres are
  // the corner averages, triangle centres the centroids of its split along (i,j)-(i+1,j+1).
  const int per_quad = layout == StressPointLayout::quad_centres ? 1 : 2;
  const int nq = (nx - 1) * (ny - 1);
  sp.x.resize(2, per_quad * nq);
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const int q = i + (nx - 1) * j;
      const Eigen::Vector2d a = particles.x.col(i + nx * j);
      const Eigen::Vector2d b = particles.x.col(i + 1 + nx * j);
      const Eigen::Vector2d c = particles.x.col(i + 1 + nx * (j + 1));
      const Eigen::Vector2d d = particles.x.col(i + nx * (j + 1));
      if (per_quad == 1) {
        sp.x.col(q) = 0.25 * (a + b + c + d);
      } else if (particles.hexagonal && j % 2 == 0) {
        // Row j + 1 is shifted right: the equilateral triangles share the diagonal b–d.
        sp.x.col(2 * q) = (a + b + d) / 3.0;
        sp.x.col(2 * q + 1) = (b + c + d) / 3.0;
      } else {
        sp.x.col(2 * q) = (a + b + c) / 3.0;
        sp.x.col(2 * q + 1) = (a + c + d) / 3.0;
      }
    }
  // One Voronoi diagram of particles then stress points (001 eq 65).
  Eigen::MatrixXd joint(2, n + sp.x.cols());
  joint << particles.x, sp.x;
  const Eigen::VectorXd v = voronoi_areas(joint, domain);
  sp.particle_volume = v.head(n);
  sp.volume = v.tail(sp.x.cols());
  return sp;
}

}  // namespace mfv
