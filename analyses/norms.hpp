/// Error norms (004 II eq 7.2) on quadrature independent of the method, and convergence rates
/// as least-squares slopes of ln(error) against ln(h) (004 II eq 7.3).
#pragma once
#include <vector>

#include "methods/methods/method.hpp"
#include "problems/problem.hpp"
#include "analyses/case.hpp"
#include "reports/convergence.hpp"

namespace mfv {

/// The common rule: uniform cells (at least 1200, four per particle interval) with 6 Gauss
/// points each, the same for every method at a given resolution.
IntegrationRule common_error_rule(const Domain& domain, int nodes);
/// The paper's rule: `points` Gauss points in every interval between neighbouring particles.
IntegrationRule paper_error_rule(const Domain& domain, const ParticleSet& particles, int points);

/// Errors of the trial field on `rule` (any number of components; energy from the problem).
ErrorNorms error_norms(const BoundaryValueProblem& problem, const Discretization& d, const Eigen::VectorXd& u,
                       const IntegrationRule& rule);
/// Errors on the method's own quadrature with its own values and gradients (001 §9.1: "by the
/// procedure that is used to evaluate the nodal forces").
ErrorNorms method_rule_error_norms(const BoundaryValueProblem& problem, const Discretization& d,
                                   const Eigen::VectorXd& u);

/// Rates of a study from its cases (common or paper rule).
Rates study_rates(const std::vector<CaseResult>& cases, bool paper_rule);

}  // namespace mfv
