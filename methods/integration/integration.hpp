/// Integration schemes: where the weak form is sampled (nodal, background-cell Gauss, stress
/// points) and with what weights. The rule is a batch of points, so any approximation can
/// be evaluated on it in one call.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "methods/core/registry.hpp"
#include "methods/particles.hpp"

namespace mfv {

struct IntegrationRule {
  Eigen::MatrixXd points;     ///< dim × nq
  Eigen::VectorXd weights;    ///< nq
  std::vector<int> cell;      ///< background cell (or owning particle) of each point
  int cells = 0;              ///< number of cells or stress points (reports)
  std::string kind;           ///< "nodal", "gauss-cells", "stress-points"
  /// The first `nodal_points` points are the particles themselves, in particle order (nodal
  /// and stress-point rules); point q < nodal_points is particle q.
  int nodal_points = 0;
  int size() const { return static_cast<int>(weights.size()); }
};

class IntegrationScheme {
 public:
  virtual ~IntegrationScheme() = default;
  virtual IntegrationRule rule(const Domain& domain, const ParticleSet& particles) const = 0;
  /// A rule on one side of the domain (side index s: 0 left, 1 right, 2 bottom, 3 top) for
  /// traction integrals, consistent with the domain rule: nodal rules sample the particles of
  /// that side (weights: their share of the side, 001 eq 61's Γ_J; `cell` is the particle),
  /// cell rules put Gauss points on the side's segments. 1D: one point of weight 1.
  virtual IntegrationRule boundary_rule(const Domain& domain, const ParticleSet& particles,
                                        int side) const;
};

/// The nodal boundary rule: particles flagged on `side`, projected onto it, weighted by half
/// the distance to their neighbours along the side (the rectangle's Voronoi edge lengths).
IntegrationRule nodal_boundary_rule(const Domain& domain, const ParticleSet& particles, int side);

using IntegrationRegistry = Registry<IntegrationScheme>;

/// n-point Gauss–Legendre rule on [a, b] (GSL's fixed tables).
void gauss_legendre(int n, double a, double b, std::vector<double>& x, std::vector<double>& w);

/// Gauss rule over [a, b] split into `cells` equal cells with n points each (error norms).
IntegrationRule uniform_gauss_rule_1d(double a, double b, int cells, int n);
/// n×n Gauss per cell on a uniform cx × cy grid of a 2D box (error norms).
IntegrationRule uniform_gauss_rule_2d(const Domain& box, int cx, int cy, int n);

/// Registers every integration scheme (the list: methods/integration/register_all.cpp).
void register_all_integrations(IntegrationRegistry& r);

}  // namespace mfv
