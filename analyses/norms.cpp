#include "analyses/norms.hpp"

#include "reports/convergence_table.hpp"

#include <algorithm>
#include <cmath>


namespace mfv {

IntegrationRule common_error_rule(const Domain& domain, int nodes) {
  const int cells = std::max(1200, 4 * (nodes - 1));
  return uniform_gauss_rule_1d(domain.lower[0], domain.upper[0], cells, 6);
}

IntegrationRule paper_error_rule(const Domain& domain, const ParticleSet& particles, int points) {
  std::vector<double> xs(particles.x.row(0).data(), particles.x.row(0).data() + particles.size());
  std::sort(xs.begin(), xs.end());
  IntegrationRule r;
  r.kind = "gauss-cells";
  std::vector<double> gx, gw;
  std::vector<double> px, pw;
  for (std::size_t c = 0; c + 1 < xs.size(); ++c) {
    gauss_legendre(points, xs[c], xs[c + 1], gx, gw);
    px.insert(px.end(), gx.begin(), gx.end());
    pw.insert(pw.end(), gw.begin(), gw.end());
  }
  r.cells = static_cast<int>(xs.size()) - 1;
  r.points = Eigen::Map<Eigen::RowVectorXd>(px.data(), static_cast<Eigen::Index>(px.size()));
  r.weights = Eigen::Map<Eigen::VectorXd>(pw.data(), static_cast<Eigen::Index>(pw.size()));
  return r;
}

namespace {

/// Norms of the differences between computed and exact values and gradients on a rule.
ErrorNorms norms_from(const BoundaryValueProblem& problem, const IntegrationRule& rule, const Eigen::MatrixXd& uh,
                      const Eigen::MatrixXd& gh) {
  Eigen::MatrixXd ue, ge;
  problem.exact_field(rule.points, ue, ge);
  const Eigen::VectorXd& w = rule.weights;
  const double e0 = std::sqrt(w.dot((uh - ue).colwise().squaredNorm().transpose()));
  const double e1 = std::sqrt(w.dot((gh - ge).colwise().squaredNorm().transpose()));
  const double n0 = std::sqrt(w.dot(ue.colwise().squaredNorm().transpose()));
  const double n1 = std::sqrt(w.dot(ge.colwise().squaredNorm().transpose()));
  const double ee = std::sqrt(std::max(0.0, w.dot(problem.energy_density(gh - ge))));
  const double ne = std::sqrt(std::max(0.0, w.dot(problem.energy_density(ge))));
  ErrorNorms e;
  e.l2 = e0;
  e.h1_semi = e1;
  e.h1 = std::hypot(e0, e1);
  e.l2_rel = n0 > 0 ? e0 / n0 : NAN;
  e.h1_semi_rel = n1 > 0 ? e1 / n1 : NAN;
  e.h1_rel = std::hypot(n0, n1) > 0 ? e.h1 / std::hypot(n0, n1) : NAN;
  e.energy = ee;
  e.energy_rel = ne > 0 ? ee / ne : NAN;
  return e;
}

}  // namespace

ErrorNorms error_norms(const BoundaryValueProblem& problem, const Discretization& d, const Eigen::VectorXd& u,
                       const IntegrationRule& rule) {
  Eigen::MatrixXd uh, gh;
  d.trial_at(rule.points, 1).field(u, problem.components(), uh, gh);
  return norms_from(problem, rule, uh, gh);
}

ErrorNorms method_rule_error_norms(const BoundaryValueProblem& problem, const Discretization& d,
                                   const Eigen::VectorXd& u) {
  Eigen::MatrixXd uh, gh;
  d.trial_q.field(u, problem.components(), uh, gh);
  return norms_from(problem, d.quadrature, uh, gh);
}

Rates study_rates(const std::vector<CaseResult>& cases, bool paper_rule) {
  ConvergenceTable table("h");
  for (const auto& c : cases) {
    const ErrorNorms& e = paper_rule ? c.errors_paper : c.errors;
    table.add_row({{"h", c.h}, {kRateL2, e.l2}, {kRateH1Semi, e.h1_semi}, {kRateEnergy, e.energy}});
  }
  Rates r;
  for (const char* column : {kRateL2, kRateH1Semi, kRateEnergy}) {
    r.fitted[column] = cases.empty() ? NAN : table.rate(column);
    r.pairwise[column] = cases.empty() ? std::vector<double>{} : table.pairwise(column);
  }
  return r;
}

}  // namespace mfv
