/// Defaults of the Problem interface: 1D scalar problems on a line of particles.
#include <algorithm>

#include "problems/problem.hpp"

namespace mfv {

void ScalarProblem::exact_field(const Eigen::MatrixXd& x, Eigen::MatrixXd& u,
                          Eigen::MatrixXd& grad) const {
  Eigen::VectorXd v, dv;
  exact(x, v, dv);
  u = v.transpose();
  grad = dv.transpose();
}

ParticleSet ParticleProblem::particles(int nodes, double perturbation) const {
  return uniform_line(domain(), nodes, perturbation);
}

IntegrationRule BoundaryValueProblem::common_error_rule(const ParticleSet& particles) const {
  // Uniform cells (at least 1200, four per particle interval), 6 Gauss points each.
  const Domain d = domain();
  const int cells = std::max(1200, 4 * (particles.size() - 1));
  return uniform_gauss_rule_1d(d.lower[0], d.upper[0], cells, 6);
}

}  // namespace mfv
