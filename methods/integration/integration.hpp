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
  int size() const { return static_cast<int>(weights.size()); }
};

class IntegrationScheme {
 public:
  virtual ~IntegrationScheme() = default;
  virtual IntegrationRule rule(const Domain& domain, const ParticleSet& particles) const = 0;
};

using IntegrationRegistry = Registry<IntegrationScheme>;

/// n-point Gauss–Legendre rule on [a, b] (GSL's fixed tables).
void gauss_legendre(int n, double a, double b, std::vector<double>& x, std::vector<double>& w);

/// Gauss rule over [a, b] split into `cells` equal cells with n points each (error norms).
IntegrationRule uniform_gauss_rule_1d(double a, double b, int cells, int n);

void register_nodal(IntegrationRegistry&);
void register_gauss_cells(IntegrationRegistry&);
void register_stress_points(IntegrationRegistry&);

/// Registers every integration scheme: add one line here for a new one.
inline void register_all_integrations(IntegrationRegistry& r) {
  register_nodal(r);
  register_gauss_cells(r);
  register_stress_points(r);
}

}  // namespace mfv
