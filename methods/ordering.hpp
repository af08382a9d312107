/// Renumbering of particles and integration points along a space-filling curve, so that
/// neighbours in space are neighbours in memory (the force loops of explicit dynamics read
/// the fields of every neighbour of a point).
///
/// The curve is Hilbert's (Hilbert 1891; the iterative rotate-and-reflect index, as in
/// Warren, Hacker's Delight, 2nd ed., ch. 16 "Hilbert's Curve"): the bounding box is cut into
/// 2^16 × 2^16 cells, each point gets the index of its cell along the curve, and the points
/// are sorted by it (stable: points in one cell keep their order). Unlike Morton's Z order,
/// consecutive cells of Hilbert's curve always share a side, so a run of consecutive indices
/// is a compact patch. In 1D the curve is the order along x.
#pragma once
#include <vector>

#include <Eigen/Dense>

#include "methods/methods/method.hpp"

namespace mfv {

/// The points (dim × n, dim 1 or 2) in Hilbert-curve order: order[k] is the old index of the
/// k-th point. Throws InputError for another dimension or a non-finite coordinate.
std::vector<int> hilbert_order(const Eigen::MatrixXd& points);

/// A renumbering of a discretization, new → old for the particles and for the integration
/// points (the first nodal_points points follow their particles).
struct Renumbering {
  std::vector<int> particle_old, point_old;
  /// old → new, the inverses.
  std::vector<int> particle_new() const;
  std::vector<int> point_new() const;
  /// Columns of a per-particle matrix (dim × N) moved back to the old numbering.
  Eigen::MatrixXd particles_to_old(const Eigen::MatrixXd& by_new) const;
};

/// The Hilbert renumbering of `d`: particles along the curve, the rule's own points (after
/// the nodal ones) along it too, in one bounding box.
Renumbering hilbert_renumbering(const Discretization& d);

/// Applies r to the discretization in place: the particle set (positions, volumes,
/// dilations, sides, local spacings, quadrilateral cells, the joint Voronoi volumes of the
/// stress points), the integration rule (points, weights, the owning particle of nodal
/// points) and the trial and test tables (rows to the new points, entries to the new
/// particles, each row's entries in their old order). The set's `lattice` becomes zero: its
/// J = i + nx·j numbering no longer holds, so methods that need it (fem's Q4 elements) refuse
/// the renumbered set. Throws InputError when r does not fit d (sizes, nodal points that do
/// not follow their particles, repeated indices) or d has enrichment unknowns.
void renumber(Discretization& d, const Renumbering& r);

/// The particle set with its particles in `order` (new → old), every per-particle field
/// moved with them and `lattice` zero; quadrilateral cells name the new indices.
ParticleSet permuted(const ParticleSet& p, const std::vector<int>& order);

}  // namespace mfv
