/// Analyses as plugins: what a case does with a problem and a method — `static-solve`,
/// `transient`, `dispersion`, `time-step`, `stretch-map`, `crack-sweep` — each with a
/// parameter schema, its own result type (behind CaseResult::data<T>()) and its own report
/// page. A problem declares the analyses that apply to it (Problem::analyses()); the runner
/// (verify/runner.hpp) asks this registry, never the kind of the problem.
#pragma once
#include <algorithm>
#include <filesystem>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "analyses/case.hpp"
#include "methods/core/errors.hpp"
#include "methods/core/registry.hpp"
#include "methods/materials/material.hpp"
#include "methods/methods/register.hpp"
#include "problems/problem.hpp"

namespace mfv {

class Analysis;
using AnalysisRegistry = Registry<Analysis>;

/// Every registry, empty until the composition root (apps/catalogue.hpp) fills them with
/// their register_all lists. Analyses and the runner read them through this type.
struct Registries {
  Registries() = default;
  // Factories hold references into this object, so it stays where it was built.
  Registries(const Registries&) = delete;
  Registries& operator=(const Registries&) = delete;

  MethodParts parts() const { return MethodParts{kernels, approximations, integrations}; }

  KernelRegistry kernels{"kernel"};
  ApproximationRegistry approximations{"approximation"};
  IntegrationRegistry integrations{"integration scheme"};
  MethodRegistry methods{"method"};
  ProblemRegistry problems{"problem"};
  MaterialRegistry materials{"material"};
  AnalysisRegistry analyses{"analysis"};
};

/// What an analysis gets for one case: the registries (to build variants of the method, e.g.
/// with a crack moved, or the problem's materials), the problem, the case and its method.
struct AnalysisContext {
  const Registries& plugins;
  const Problem& problem;
  const CaseSpec& spec;
  const Method& method;
};

struct ReportSection;

/// The error norms the cases of an analysis measure, by their results.json names ("l2",
/// "h1_seminorm", "h1", "energy"; energy for vector fields only), whether their absolute values
/// are measured too, and why a norm that is not listed is absent.
struct MeasuredErrors {
  std::vector<std::string> relative;
  bool absolute = false;
  std::string why_not;
  bool has(const std::string& norm) const {
    return std::find(relative.begin(), relative.end(), norm) != relative.end();
  }
};

class Analysis {
 public:
  virtual ~Analysis() = default;
  /// Runs one case: fills r's common fields (errors, headline values, CPU times, particle
  /// counts, the method's description) and its own result (r.emplace<T>()). Throws
  /// InputError when the problem does not provide what the analysis reads.
  virtual void run(const AnalysisContext& c, CaseResult& r) const = 0;
  /// Whether `problem` provides the definition this analysis reads (a weak form, a transient
  /// run, a lattice ...); a problem declares only analyses that accept it (a test checks).
  virtual bool accepts(const Problem& problem) const = 0;
  /// The page of one problem's studies run by this analysis (problems/<slug>.md).
  virtual std::string page(const Registries& plugins, const ReportSection& section,
                           const std::string& title, const std::filesystem::path& dir,
                           bool vtk) const = 0;
  /// The block index.md shows for the section: a ranking of the methods, or each case's
  /// verdict.
  virtual std::string summary(const Problem& problem, const ReportSection& section) const = 0;
  /// What the page holds, for the link to it ("every resolution's errors, rates and CPU …").
  virtual std::string page_contents(bool vtk) const = 0;
  /// The error norms its cases measure (reports, the study table and results.json show these
  /// and say why the others are absent, never a 0).
  virtual MeasuredErrors measured_errors() const = 0;
  /// Prints one case for `mfv run` / `mfv analyse` (what ran, errors or verdicts, headline
  /// values, CPU) and returns the exit status it calls for: 1 for a run that failed (went
  /// unstable), else 0.
  virtual int print_case(const CaseResult& r, std::ostream& out) const = 0;
  /// true: studies with other problem parameters get a section of their own (they are other
  /// problems, e.g. another exact solution); false: one section per problem, whose findings
  /// compare across the parameters (Lagrangian vs Eulerian, σ̄ sweeps).
  virtual bool section_per_problem_params() const { return false; }
};

/// A case's parameters resolved once, for every consumer: the analysis (spec.analysis, or
/// the problem's default), the problem's own parameters and the analysis's (the keys of
/// spec.problem_params the problem does not declare go to the analysis; the problem's
/// analysis_defaults come under them), each resolved against its schema. A key of
/// spec.method_params the method does not declare but the analysis does goes to the analysis
/// too (`mfv run cantilever -m efg-ni -p solver=petsc`); one both declare stays the method's.
struct ResolvedCase {
  std::string analysis;
  Params problem_given, analysis_given;  ///< spec.problem_params split (+ routed method keys)
  Params method_given;                   ///< spec.method_params the method declares
  Params problem_params, analysis_params, method_params;  ///< resolved
};
/// Throws InputError naming the parameter and what is valid (the problem's and the
/// analysis's keys, or the method's and the analysis's; the problem's analyses), and when an
/// analysis key comes with two values (method and problem parameters).
ResolvedCase resolve_case(const Registries& plugins, const CaseSpec& spec);

/// `spec` with the analysis keys of its method parameters moved to its problem parameters
/// (where an analysis's keys are given), so that every later consumer reads the method's
/// own parameters only. Throws as resolve_case.
CaseSpec routed_spec(const Registries& plugins, const CaseSpec& spec);

/// The analysis that ran `r`: its own record, or for a case built by hand (no record) the
/// problem's default.
std::string analysis_of(const Registries& plugins, const CaseResult& r);

/// The keys of `given` the problem declares (the others are its analysis's parameters).
Params problem_own_params(const Registries& plugins, const std::string& problem,
                          const Params& given);
/// The problem built from a case's problem parameters (its analysis's keys left out).
std::unique_ptr<Problem> create_problem(const Registries& plugins, const std::string& problem,
                                        const Params& given);

/// Every parameter of a case in one resolved set: the problem's and its analysis's (given
/// over the problem's analysis_defaults over the analysis's defaults); `analysis` empty: the
/// problem's default analysis. What published values and ledger rows are matched against.
Params resolved_case_params(const Registries& plugins, const std::string& problem,
                            const Params& given, const std::string& analysis = "");

/// The particles of `problem` at the case's resolution, discretized by the case's method
/// (no crack enrichment: refuse_enrichment), with r's setup CPU time and counts (h, dim,
/// components, particles, quadrature points, cells, stress points, the description).
Discretization discretize_case(const ParticleProblem& problem, const AnalysisContext& c,
                               CaseResult& r);

/// The problem as the definition type an analysis reads, or InputError naming the problem,
/// the analysis and what it needs.
template <class Definition>
const Definition& definition_of(const AnalysisContext& c, const std::string& analysis,
                                const std::string& needs) {
  if (const auto* d = dynamic_cast<const Definition*>(&c.problem)) return *d;
  throw InputError(fmt::format("problem '{}' does not define {}, which the analysis '{}' needs; "
                               "its analyses: {}",
                               c.spec.problem, needs, analysis, fmt::join(c.problem.analyses(), ", ")));
}

/// Registers every built-in analysis (the list: analyses/register_all.cpp).
void register_all_analyses(AnalysisRegistry& r);

}  // namespace mfv
