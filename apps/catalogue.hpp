/// The composition root: every registry (kernels, approximations, integration schemes,
/// methods, problems, materials, analyses) filled by the explicit register_all lists at
/// construction, plus out-of-tree plugins.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "analyses/analysis.hpp"
#include "methods/materials/material.hpp"
#include "methods/methods/register.hpp"
#include "problems/register.hpp"

namespace mfv {

/// Out-of-tree plugins (tests, user code): each hook runs right after the built-in list of
/// its kind, so a kernel added here is a valid `kernel=` choice of every method.
struct Extensions {
  std::vector<std::function<void(KernelRegistry&)>> kernels;
  std::vector<std::function<void(ApproximationRegistry&, const KernelRegistry&)>> approximations;
  std::vector<std::function<void(MethodRegistry&, const MethodParts&)>> methods;
  std::vector<std::function<void(ProblemRegistry&)>> problems;
  std::vector<std::function<void(AnalysisRegistry&)>> analyses;
  /// Where the hooks came from (the plugin libraries, apps/plugins.hpp), for provenance.
  std::vector<std::string> sources;
};

class Catalogue : public Registries {
 public:
  explicit Catalogue(const Extensions& extra = {}) : plugins(extra.sources) {
    register_all_kernels(kernels);
    for (const auto& f : extra.kernels) f(kernels);
    register_all_approximations(approximations, kernels);
    for (const auto& f : extra.approximations) f(approximations, kernels);
    register_all_integrations(integrations);
    register_all_methods(methods, parts());
    for (const auto& f : extra.methods) f(methods, parts());
    register_all_problems(problems);
    for (const auto& f : extra.problems) f(problems);
    register_all_materials(materials);
    register_all_analyses(analyses);
    for (const auto& f : extra.analyses) f(analyses);
  }
  /// The plugin libraries whose registrations this catalogue holds (reports name them).
  const std::vector<std::string> plugins;
};

}  // namespace mfv
