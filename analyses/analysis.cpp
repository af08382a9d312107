#include "analyses/analysis.hpp"

#include <algorithm>
#include <set>

#include "methods/core/clock.hpp"

namespace mfv {

Params problem_own_params(const Registries& plugins, const std::string& problem,
                          const Params& given) {
  std::set<std::string> keys;
  for (const auto& s : plugins.problems.entry(problem).schema) keys.insert(s.name);
  Params own;
  for (const auto& [k, v] : given.values())
    if (keys.count(k)) own.set(k, v);
  return own;
}

std::unique_ptr<Problem> create_problem(const Registries& plugins, const std::string& problem,
                                        const Params& given) {
  return plugins.problems.create(problem, problem_own_params(plugins, problem, given));
}

ResolvedCase resolve_case(const Registries& plugins, const CaseSpec& spec) {
  ResolvedCase rc;
  const auto& problem_entry = plugins.problems.entry(spec.problem);
  std::set<std::string> problem_keys;
  for (const auto& s : problem_entry.schema) problem_keys.insert(s.name);
  std::vector<std::string> others;
  for (const auto& [k, v] : spec.problem_params.values()) {
    if (problem_keys.count(k)) rc.problem_given.set(k, v);
    else others.push_back(k);
  }
  const auto problem = plugins.problems.create(spec.problem, rc.problem_given);
  const std::vector<std::string> declared = problem->analyses();
  rc.analysis = spec.analysis.empty() ? declared.front() : spec.analysis;
  if (std::find(declared.begin(), declared.end(), rc.analysis) == declared.end())
    throw InputError(fmt::format("problem '{}' has no analysis '{}'; its analyses: {} (leave "
                                 "`analysis` out for the first)",
                                 spec.problem, rc.analysis, fmt::join(declared, ", ")));
  const auto& analysis_entry = plugins.analyses.entry(rc.analysis);
  std::set<std::string> analysis_keys;
  for (const auto& s : analysis_entry.schema) analysis_keys.insert(s.name);
  rc.analysis_given = problem->analysis_defaults(rc.analysis);
  for (const auto& k : others) {
    if (!analysis_keys.count(k))
      throw InputError(fmt::format(
          "unknown parameter '{}' of problem '{}' (analysis '{}'); the problem's: {}; the "
          "analysis's: {}",
          k, spec.problem, rc.analysis, fmt::join(problem_keys, ", "),
          analysis_keys.empty() ? std::string("none") : fmt::format("{}", fmt::join(analysis_keys, ", "))));
    rc.analysis_given.set(k, spec.problem_params.values().at(k));
  }
  rc.problem_params = plugins.problems.resolve(spec.problem, rc.problem_given);
  rc.analysis_params = plugins.analyses.resolve(rc.analysis, rc.analysis_given);
  rc.method_params = plugins.methods.resolve(spec.method, spec.method_params);
  return rc;
}


std::string analysis_of(const Registries& plugins, const CaseResult& r) {
  if (!r.analysis.empty()) return r.analysis;
  if (!r.spec.analysis.empty()) return r.spec.analysis;
  return create_problem(plugins, r.spec.problem, r.spec.problem_params)->analyses().front();
}

Params resolved_case_params(const Registries& plugins, const std::string& problem,
                            const Params& given, const std::string& analysis) {
  const Params own = problem_own_params(plugins, problem, given);
  Params all = plugins.problems.resolve(problem, own);
  const auto p = plugins.problems.create(problem, own);
  const std::string a = analysis.empty() ? p->analyses().front() : analysis;
  Params a_given = p->analysis_defaults(a);
  for (const auto& [k, v] : given.values())
    if (!own.has(k)) a_given.set(k, v);
  const Params resolved = plugins.analyses.resolve(a, a_given);
  for (const auto& [k, v] : resolved.values()) all.set(k, v);
  return all;
}

Discretization discretize_case(const ParticleProblem& problem, const AnalysisContext& c,
                               CaseResult& r) {
  const double t0 = cpu_seconds();
  const Domain domain = problem.domain();
  ParticleSet particles = problem.particles(c.spec.nodes, c.spec.perturbation);
  Discretization d =
      c.method.discretize(domain, std::move(particles), problem.derivative_order());
  refuse_enrichment(d, fmt::format("problem '{}'", c.spec.problem));
  r.cpu.setup = cpu_seconds() - t0;
  r.method_description = d.description;
  r.h = d.particles.spacing;
  r.dim = domain.dim;
  r.components = problem.components();
  r.particles = d.particles.size();
  r.quadrature_points = d.quadrature.size();
  r.cells = d.quadrature.cells;
  r.quadrature_kind = d.quadrature.kind;
  r.stress_points = d.quadrature.kind == "stress-points"
                        ? d.quadrature.size() - d.quadrature.nodal_points
                        : 0;
  return d;
}

}  // namespace mfv
