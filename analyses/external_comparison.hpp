/// The report's page of external solvers beside mfv's methods (external.md, issue 30): for
/// every problem an external solver ran, one table of every method at the resolutions the
/// solver ran — what the problem measures against its closed form (the rod pulse's velocity
/// errors against d'Alembert, the plate's period and amplitude against thin-plate theory),
/// the energy drift, and particle-steps per CPU second — so a reader compares a code that is
/// not mfv's with mfv's own plugins in one place, across problems.
#pragma once
#include <string>
#include <vector>

#include "analyses/report_section.hpp"
#include "reports/convergence_table.hpp"

namespace mfv {

/// Particle-steps per second of a transient case's time loop ("–" when unknown): mfv's steps,
/// or an external solver's own (index.csv's steps column) over its CPU time. Defined with the
/// transient report (transient_report.cpp), which prints the same number.
std::string fmt_particle_steps(const CaseResult& r, const TransientData& t);

/// The comparison: a row per (problem, resolution, method) for every section holding a study
/// run by an external solver, at the resolutions that solver ran; empty when none ran.
TextTable external_comparison(const std::vector<ReportSection>& sections);

/// The page of the comparison: an explanation, then the table; "" when it has no rows.
std::string external_comparison_page(const TextTable& table);

}  // namespace mfv
