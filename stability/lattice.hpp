/// Lattice patches for von Neumann (Bloch-wave) analyses: a finite piece of an infinite
/// uniform lattice (000 §3–4) large enough that its centre particle sees only interior
/// neighbours, so the centre's row of the stiffness is the infinite lattice's.
#pragma once
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "methods/particles.hpp"

namespace mfv {

/// The particle arrangements of 000: a 1D line, and the 2D rectangular and hexagonal
/// (triangular) lattices of its Fig. 8, each with one particle per unit cell.
enum class LatticeKind { line, rectangular, hexagonal };

LatticeKind lattice_kind_from(const std::string& name);  ///< throws InputError listing the kinds
std::string to_string(LatticeKind kind);

struct LatticePatch {
  LatticeKind kind = LatticeKind::line;
  ParticleSet particles;
  Domain domain;
  int centre = 0;  ///< the particle whose stiffness row is taken
  double spacing = 1;
  /// Volume per particle of the infinite lattice: Δx, Δx², √3/2 Δx².
  double cell_volume = 1;
};

/// A patch of (2 half_width + 1) particles per direction with spacing dx, the centre at the
/// origin; hexagonal: odd rows shifted by dx/2, rows √3/2 dx apart (ParticleSet::hexagonal).
/// Volumes are the patch's Voronoi cells (the interior ones equal cell_volume).
LatticePatch lattice_patch(LatticeKind kind, double dx, int half_width);

/// Distance from the origin to the boundary of the first Brillouin zone in direction θ (rad):
/// the largest wave number of a Bloch wave e^{iκ n·X} that the lattice can tell apart.
/// Line: π/Δx; rectangular: min(π/(Δx|cos θ|), π/(Δx|sin θ|)); hexagonal: the hexagon of
/// inscribed radius 2π/(√3 Δx) (4π/(3Δx) at θ = 0).
double brillouin_boundary(LatticeKind kind, double dx, double theta);

}  // namespace mfv
