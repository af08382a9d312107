#include "verify/runner.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "analyses/norms.hpp"
#include "methods/core/errors.hpp"

namespace mfv {

std::string study_label(const CaseSpec& spec) {
  const std::string p = spec.method_params.to_string();
  return p.empty() ? spec.method : spec.method + " " + p;
}

CaseResult run_case(const Registries& plugins, const CaseSpec& spec) {
  CaseResult r;
  // Analysis keys given among the method's parameters (-p solver=petsc) move to the problem's.
  r.spec = routed_spec(plugins, spec);
  const ResolvedCase rc = resolve_case(plugins, r.spec);
  r.analysis = rc.analysis;
  r.problem_params = rc.problem_params;
  r.analysis_params = rc.analysis_params;
  r.method_params = rc.method_params;
  const auto problem = plugins.problems.create(spec.problem, rc.problem_given);
  const auto analysis = plugins.analyses.create(rc.analysis, rc.analysis_given);
  const auto method = plugins.methods.create(r.spec.method, r.spec.method_params);
  analysis->run(AnalysisContext{plugins, *problem, r.spec, *method}, r);
  return r;
}

StudyResult run_study(const Registries& catalogue, const CaseSpec& base,
                      const std::vector<int>& nodes, const StudyProgress& progress) {
  StudyResult s;
  s.label = study_label(base);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (progress) progress(static_cast<int>(i), static_cast<int>(nodes.size()), nodes[i]);
    CaseSpec c = base;
    c.nodes = nodes[i];
    s.cases.push_back(run_case(catalogue, c));
  }
  s.rates = study_rates(s.cases, false);
  s.rates_paper = study_rates(s.cases, true);
  // A resolution whose error is NaN (not measured, or a checkpoint not reached) leaves the
  // fitted rate undefined (the table's rule): a slope over the remaining resolutions would be
  // a different study.
  return s;
}

}  // namespace mfv
