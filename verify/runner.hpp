/// Runs cases and refinement studies: resolves a case's parameters once (problem, method and
/// analysis, the analysis defaulting from the problem), builds the problem, the method and
/// the analysis from their registries, and lets the analysis run it.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "analyses/analysis.hpp"
#include "analyses/case.hpp"

namespace mfv {

/// Runs one case. Throws InputError on bad names or parameters, SingularError on a singular
/// moment matrix or global system.
CaseResult run_case(const Registries& plugins, const CaseSpec& spec);

/// Called before each resolution of a study: (index, count, nodes).
using StudyProgress = std::function<void(int, int, int)>;

/// Runs one method on one problem at each resolution and computes the rates.
StudyResult run_study(const Registries& plugins, const CaseSpec& base,
                      const std::vector<int>& nodes, const StudyProgress& progress = {});

/// "rkpm j=1,kernel=gaussian": the method and the parameters the user set.
std::string study_label(const CaseSpec& spec);

}  // namespace mfv
