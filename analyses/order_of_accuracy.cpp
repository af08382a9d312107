#include "analyses/order_of_accuracy.hpp"

#include <cmath>

#include <fmt/format.h>

#include "analyses/analysis.hpp"
#include "reports/convergence.hpp"

namespace mfv {

std::string OrderJudgement::text() const {
  std::vector<std::string> parts;
  for (const auto& n : norms)
    parts.push_back(fmt::format("{} {}{} (least squares {}): {}", n.norm,
                                std::isfinite(n.observed) ? fmt::format("{:.2f}", n.observed)
                                                          : std::string("–"),
                                std::isfinite(n.formal) ? fmt::format(" against {:g}", n.formal)
                                                        : std::string(),
                                std::isfinite(n.least_squares)
                                    ? fmt::format("{:.2f}", n.least_squares)
                                    : std::string("–"),
                                n.verdict));
  return fmt::format("formal order {}: {}; observed on the finest pair {}",
                     formal.declared() ? fmt::format("L2 {:g}, gradient norm {:g}", formal.l2,
                                                     formal.h1)
                                       : std::string("none declared"),
                     formal.source, fmt::join(parts, "; "));
}

OrderJudgement judge_order(const Registries& catalogue, const StudyResult& s) {
  OrderJudgement j;
  if (s.cases.empty()) return j;
  const CaseSpec& spec = s.cases.front().spec;
  if (catalogue.methods.contains(spec.method))
    j.formal = catalogue.methods.create(spec.method, spec.method_params)->formal_order();
  else
    j.formal = {NAN, NAN, fmt::format("'{}' is not a registered method", spec.method)};
  // The gradient's norm: the H1 seminorm of a scalar field, the energy norm of a vector one
  // (2D elasticity is judged in it); both of order h1.
  const bool vector = s.cases.front().components > 1;
  std::vector<double> h;
  for (const auto& c : s.cases) h.push_back(c.h);
  struct Norm {
    const char* name;
    double formal;
    double ErrorNorms::*rel;
  };
  for (const Norm& n :
       {Norm{"L2", j.formal.l2, &ErrorNorms::l2_rel},
        vector ? Norm{"energy", j.formal.h1, &ErrorNorms::energy_rel}
               : Norm{"H1-semi", j.formal.h1, &ErrorNorms::h1_semi_rel}}) {
    NormOrder o;
    o.norm = n.name;
    o.formal = n.formal;
    std::vector<double> e;
    for (const auto& c : s.cases) e.push_back(c.errors.*n.rel);
    // From the cases' own errors and spacings, so the orders judged are those of the errors
    // the page shows (the same slopes as the study's convergence table).
    const auto pairs = pairwise_rates(h, e);
    o.observed = pairs.empty() ? NAN : pairs.back();
    o.least_squares = s.cases.size() >= 2 ? fitted_rate(h, e) : NAN;
    const ConvergenceJudgement trend = judge_convergence(e, h);
    if (!std::isfinite(o.observed)) o.verdict = "no rate (fewer than two resolutions)";
    else if (!trend.converges()) o.verdict = fmt::format("does not converge ({})", trend.label());
    else if (!std::isfinite(o.formal)) o.verdict = "no formal order declared";
    else if (std::abs(o.observed - o.formal) <= kOrderTolerance) o.verdict = "at formal order";
    else if (o.observed > o.formal) o.verdict = "above (superconvergent)";
    else o.verdict = "below";
    j.norms.push_back(std::move(o));
  }
  return j;
}

}  // namespace mfv
