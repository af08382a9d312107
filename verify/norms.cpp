#include "verify/norms.hpp"

#include <algorithm>
#include <cmath>

#include <gsl/gsl_fit.h>

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

ErrorNorms error_norms(const Problem& problem, const Discretization& d, const Eigen::VectorXd& u,
                       const IntegrationRule& rule) {
  const ShapeTable t = d.trial_at(rule.points, 1);
  const Eigen::VectorXd uh = t.interpolate(u), duh = t.interpolate_derivative(u);
  Eigen::VectorXd ue, due;
  problem.exact(rule.points, ue, due);
  const Eigen::VectorXd& w = rule.weights;
  const double e0 = std::sqrt(w.dot((uh - ue).cwiseAbs2()));
  const double e1 = std::sqrt(w.dot((duh - due).cwiseAbs2()));
  const double n0 = std::sqrt(w.dot(ue.cwiseAbs2()));
  const double n1 = std::sqrt(w.dot(due.cwiseAbs2()));
  ErrorNorms e;
  e.l2 = e0;
  e.h1_semi = e1;
  e.h1 = std::hypot(e0, e1);
  e.l2_rel = n0 > 0 ? e0 / n0 : NAN;
  e.h1_semi_rel = n1 > 0 ? e1 / n1 : NAN;
  e.h1_rel = std::hypot(n0, n1) > 0 ? e.h1 / std::hypot(n0, n1) : NAN;
  return e;
}

double fitted_rate(const std::vector<double>& h, const std::vector<double>& e) {
  std::vector<double> lx, ly;
  for (std::size_t i = 0; i < h.size() && i < e.size(); ++i)
    if (h[i] > 0 && e[i] > 0 && std::isfinite(e[i])) {
      lx.push_back(std::log(h[i]));
      ly.push_back(std::log(e[i]));
    }
  if (lx.size() < 2) return NAN;
  double c0, c1, cov00, cov01, cov11, sumsq;
  gsl_fit_linear(lx.data(), 1, ly.data(), 1, lx.size(), &c0, &c1, &cov00, &cov01, &cov11, &sumsq);
  return c1;
}

std::vector<double> pairwise_rates(const std::vector<double>& h, const std::vector<double>& e) {
  std::vector<double> out;
  for (std::size_t i = 1; i < h.size() && i < e.size(); ++i)
    out.push_back(std::log(e[i] / e[i - 1]) / std::log(h[i] / h[i - 1]));
  return out;
}

Rates study_rates(const std::vector<CaseResult>& cases, bool paper_rule) {
  std::vector<double> h, l2, h1;
  for (const auto& c : cases) {
    const ErrorNorms& e = paper_rule ? c.errors_paper : c.errors;
    h.push_back(c.h);
    l2.push_back(e.l2);
    h1.push_back(e.h1_semi);
  }
  Rates r;
  r.l2 = fitted_rate(h, l2);
  r.h1_semi = fitted_rate(h, h1);
  r.l2_pairwise = pairwise_rates(h, l2);
  r.h1_semi_pairwise = pairwise_rates(h, h1);
  return r;
}

}  // namespace mfv
