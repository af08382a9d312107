#include "analyses/analysis.hpp"

#include <algorithm>
#include <set>

#include "methods/core/clock.hpp"
#include "methods/core/names.hpp"

namespace mfv {

namespace {

std::set<std::string> keys_of(const ParamSchema& schema) {
  std::set<std::string> keys;
  for (const auto& s : schema) keys.insert(s.name);
  return keys;
}

/// The names a schema answers to: its parameters' and their deprecated aliases.
std::set<std::string> names_of(const ParamSchema& schema) {
  std::set<std::string> names = keys_of(schema);
  for (const auto& s : schema) names.insert(s.aliases.begin(), s.aliases.end());
  return names;
}

/// resolve_case without the method: the split of the given parameters between the problem
/// and its analysis, each resolved.
ResolvedCase resolve_problem_and_analysis(const Registries& plugins, const std::string& name,
                                          const Params& given, const std::string& analysis) {
  ResolvedCase rc;
  rc.problem_given = problem_own_params(plugins, name, given);
  const auto problem = plugins.problems.create(name, rc.problem_given);
  const std::vector<std::string> declared = problem->analyses();
  rc.analysis = analysis.empty() ? declared.front() : analysis;
  if (std::find(declared.begin(), declared.end(), rc.analysis) == declared.end())
    throw InputError(fmt::format("problem '{}' has no analysis '{}'; its analyses: {} (leave "
                                 "`analysis` out for the first)",
                                 name, rc.analysis, fmt::join(declared, ", ")));
  const std::set<std::string> analysis_keys =
      keys_of(plugins.analyses.entry(rc.analysis).schema);
  rc.analysis_given = problem->analysis_defaults(rc.analysis);
  for (const auto& [k, v] : given.values()) {
    if (rc.problem_given.has(k)) continue;
    if (!analysis_keys.count(k))
      throw InputError(fmt::format(
          "unknown parameter '{}' of problem '{}' (analysis '{}'); the problem's: {}; the "
          "analysis's: {}",
          shown_name(k), name, rc.analysis,
          fmt::join(keys_of(plugins.problems.entry(name).schema), ", "),
          analysis_keys.empty() ? std::string("none")
                                : fmt::format("{}", fmt::join(analysis_keys, ", "))));
    rc.analysis_given.set(k, v);
  }
  rc.problem_params = plugins.problems.resolve(name, rc.problem_given);
  rc.analysis_params = plugins.analyses.resolve(rc.analysis, rc.analysis_given);
  return rc;
}

}  // namespace

Params problem_own_params(const Registries& plugins, const std::string& problem,
                          const Params& given) {
  const std::set<std::string> keys = keys_of(plugins.problems.entry(problem).schema);
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
  ResolvedCase rc =
      resolve_problem_and_analysis(plugins, spec.problem, spec.problem_params, spec.analysis);
  // `mfv run … -p solver=petsc`: a method parameter the method does not declare but the
  // analysis does is the analysis's (a key both declare stays the method's).
  const ParamSchema& method_schema = plugins.methods.entry(spec.method).schema;
  const std::set<std::string> method_names = names_of(method_schema);
  const std::set<std::string> analysis_keys = keys_of(plugins.analyses.entry(rc.analysis).schema);
  bool routed = false;
  for (const auto& [k, v] : spec.method_params.values()) {
    if (method_names.count(k)) {
      rc.method_given.set(k, v);
      continue;
    }
    if (!analysis_keys.count(k)) {
      std::vector<std::string> valid;
      for (const auto& s : method_schema) valid.push_back(s.name);
      valid.insert(valid.end(), analysis_keys.begin(), analysis_keys.end());
      throw InputError(fmt::format(
          "unknown parameter '{}' of method '{}' (analysis '{}'); {}the method's: {}; the "
          "analysis's: {}",
          shown_name(k), spec.method, rc.analysis, did_you_mean(k, valid),
          fmt::join(keys_of(method_schema), ", "),
          analysis_keys.empty() ? std::string("none")
                                : fmt::format("{}", fmt::join(analysis_keys, ", "))));
    }
    if (spec.problem_params.has(k) &&
        format_value(spec.problem_params.values().at(k)) != format_value(v))
      throw InputError(fmt::format(
          "parameter '{}' of analysis '{}' is given twice, {} in the method's parameters and "
          "{} in the problem's: give it once",
          k, rc.analysis, format_value(v), format_value(spec.problem_params.values().at(k))));
    rc.analysis_given.set(k, v);
    routed = true;
  }
  if (routed) rc.analysis_params = plugins.analyses.resolve(rc.analysis, rc.analysis_given);
  rc.method_params = plugins.methods.resolve(spec.method, rc.method_given);
  return rc;
}

CaseSpec routed_spec(const Registries& plugins, const CaseSpec& spec) {
  const ResolvedCase rc = resolve_case(plugins, spec);
  CaseSpec out = spec;
  out.method_params = rc.method_given;
  for (const auto& [k, v] : spec.method_params.values())
    if (!rc.method_given.has(k)) out.problem_params.set(k, v);
  return out;
}

std::string analysis_of(const Registries& plugins, const CaseResult& r) {
  if (!r.analysis.empty()) return r.analysis;
  if (!r.spec.analysis.empty()) return r.spec.analysis;
  return create_problem(plugins, r.spec.problem, r.spec.problem_params)->analyses().front();
}

Params resolved_case_params(const Registries& plugins, const std::string& problem,
                            const Params& given, const std::string& analysis) {
  const ResolvedCase rc = resolve_problem_and_analysis(plugins, problem, given, analysis);
  Params all = rc.problem_params;
  for (const auto& [k, v] : rc.analysis_params.values()) all.set(k, v);
  return all;
}

Discretization discretize_case(const ParticleProblem& problem, const AnalysisContext& c,
                               CaseResult& r) {
  const double t0 = cpu_seconds();
  const Domain domain = problem.discretized_domain(c.spec.nodes);
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
