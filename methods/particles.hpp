/// Particle sets: positions, integration volumes (Voronoi cells) and dilations (support sizes).
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Dense>

namespace mfv {

/// Axis-aligned box domain [lower, upper].
struct Domain {
  int dim = 1;
  Eigen::VectorXd lower, upper;
  static Domain interval(double a, double b);
  /// The rectangle [x0, x1] × [y0, y1].
  static Domain rectangle(double x0, double y0, double x1, double y1);
  double measure() const;
};

/// Sides of a box, as bits of ParticleSet::sides: 1D uses left/right only.
enum Side : unsigned { left = 1u, right = 2u, bottom = 4u, top = 8u };
/// Side bit of index s = 0..3 (left, right, bottom, top).
inline unsigned side_bit(int s) { return 1u << s; }

/// Where a lattice puts its outermost particles (001 §6, Fig. 4).
enum class Placement {
  boundary,  ///< on the boundary (Fig. 4b): boundary particles get half, corners a quarter volume
  inset      ///< half a spacing inside (Fig. 4a): all volumes equal
};

/// Stress points and the volumes of 001 eq 65: one Voronoi diagram of particles and stress
/// points together, so Σ particle_volume + Σ volume = the domain's measure.
struct StressPoints {
  Eigen::MatrixXd x;                  ///< dim × N_S positions
  Eigen::VectorXd volume;             ///< V^SP of each stress point
  Eigen::VectorXd particle_volume;    ///< V^P of each particle in the joint diagram
};

struct ParticleSet {
  int dim = 1;
  Eigen::MatrixXd x;          ///< dim × N positions
  Eigen::VectorXd volume;     ///< Voronoi volume ΔV_J (1D: half the distance to each neighbour)
  Eigen::VectorXd dilation;   ///< support scale a_J: the kernel argument is |x - x_J| / a_J
  double spacing = 0;         ///< nominal Δx of the lattice the set was built from
  /// Particles per direction of a structured lattice (x fastest: J = i + nx·j), 0 when the
  /// set is unstructured. Q4 elements and lattice cells read it.
  Eigen::Vector2i lattice = Eigen::Vector2i::Zero();
  /// The lattice is hexagonal (000 §4): odd rows shifted by Δx/2, rows √3/2 Δx apart, so the
  /// equilateral triangles split each lattice quadrilateral along the diagonal that is
  /// one spacing long (stress points at triangle centres follow it).
  bool hexagonal = false;
  Placement placement = Placement::boundary;
  /// Bits of Side: the particle lies on (Placement::boundary) or is the layer nearest to
  /// (Placement::inset) that side of the domain.
  std::vector<unsigned> sides;
  /// Explicit quadrilateral cells of a structured lattice that is not a rectangle (an
  /// annulus): four particle indices each, counter-clockwise. Gauss cells integrate over them
  /// with the bilinear map (001 eqs 67-68). Empty for rectangle lattices, whose cells follow
  /// from `lattice`.
  std::vector<std::array<int, 4>> quads;
  /// Particles each of `quads` holds, m of 001 eq 66 (n_Q = ⌈√m⌉ + 2 Gauss points per
  /// direction), for quads that span several lattice cells; empty: 1 each (one lattice cell).
  std::vector<int> quad_particles;
  /// Stress points built with the set, for domains make_stress_points cannot cut from a
  /// rectangle (an annulus); null: stress-point integration builds them from the lattice.
  std::shared_ptr<const StressPoints> stress_points;
  /// Lattice spacing at each particle when it varies over the set (an annulus: Δr or r Δθ),
  /// so dilations follow the local spacing; empty: `spacing` for every particle.
  Eigen::VectorXd local_spacing;

  int size() const { return static_cast<int>(x.cols()); }
};

/// N equally spaced particles on [a, b] (both ends included), optionally perturbed by
/// uniform random offsets of ±perturbation·Δx on interior particles (seeded, reproducible);
/// volumes from the 1D Voronoi diagram (the trapezoidal rule of 004 II §6).
ParticleSet uniform_line(const Domain& domain, int n, double perturbation = 0.0,
                         std::uint64_t seed = 1);

/// An nx × ny lattice on a 2D rectangle, spacing (x1-x0)/(nx-1) by (y1-y0)/(ny-1) for
/// Placement::boundary or (x1-x0)/nx by (y1-y0)/ny for inset. perturbation > 0 moves every
/// particle by uniform random offsets of ±perturbation·Δ per direction (seeded,
/// reproducible); boundary particles move only along their side and corners stay. Volumes:
/// exact lattice cells when unperturbed (001 §6: half on sides, a quarter at corners),
/// otherwise the Voronoi diagram clipped to the rectangle (voronoi_areas).
ParticleSet rectangle_lattice(const Domain& domain, std::int64_t nx_in, std::int64_t ny_in,
                              Placement placement,
                              double perturbation = 0.0, std::uint64_t seed = 1);

/// Areas of the Voronoi cells of 2D points, clipped to the rectangle `domain` (voro++); the
/// areas sum to the rectangle's area. Every point must lie in the rectangle.
Eigen::VectorXd voronoi_areas(const Eigen::MatrixXd& points, const Domain& domain);

/// Where stress points go between the particles of a lattice (000 §4, Fig. 8).
enum class StressPointLayout {
  quad_centres,     ///< one at the centre of each lattice quadrilateral
  triangle_centres  ///< two per quadrilateral: centroids of the triangles of its diagonal split
};

/// A polar lattice on the annulus inner ≤ r ≤ outer (the ring of the catalogue): `radial`
/// rings of `circumferential` particles each, surfaces included.
struct AnnulusLattice {
  double inner = 0, outer = 0;  ///< radii a < b
  int radial = 0;               ///< n_r ≥ 2 rings, r_i = a + i (b - a)/(n_r - 1)
  int circumferential = 0;      ///< n_θ ≥ 3 particles per ring, θ_j = 2π j / n_θ
  /// Uniform random offsets of ±jitter·Δr in r and ±jitter·r_i Δθ along the ring, in [0, 0.5)
  /// so particles keep their lattice order; surface particles move only along their circle.
  double jitter = 0;
  std::uint64_t seed = 1;  ///< std::mt19937_64 seed of the jitter (reproducible)
};

/// The particles of an AnnulusLattice, J = j + n_θ i (circumferential fastest; ring i = 0 is
/// the inner surface, counter-clockwise). Volumes are the exact polar cells
/// ΔV = (Δθ/2)(r_{i+½}² - r_{i-½}²), r_{-½} = a, r_{n_r-½} = b (half cells on the surfaces),
/// summing to π(b² - a²); `quads` are the n_θ (n_r - 1) polar cells (i,j), (i+1,j),
/// (i+1,j+1), (i,j+1) (counter-clockwise, j + 1 wrapping round to 0), index j + n_θ i; `stress_points` sit at the polar cell centres with
/// the quad-centre split of the joint Voronoi diagram (cell area A_c: A_c/2 to its stress
/// point, A_c/8 to each corner particle); local_spacing = max(Δr, r_i Δθ). Jittered sets keep
/// the volumes and stress points of the unjittered lattice. `lattice` stays zero and `sides`
/// 0: the set has no box sides. Bad input throws InputError naming the field.
ParticleSet annulus_lattice(const AnnulusLattice& ring);

/// Stress points of a lattice particle set (1D: interval midpoints; 2D: as `layout` says).
StressPoints make_stress_points(const ParticleSet& particles, const Domain& domain,
                                StressPointLayout layout = StressPointLayout::quad_centres);

/// Recomputes 1D Voronoi volumes for sorted positions.
Eigen::VectorXd voronoi_volumes_1d(const Eigen::VectorXd& sorted_x, double a, double b);

}  // namespace mfv
