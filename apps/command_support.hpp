/// What the subcommands share: the report writer (index.md, the problem sections, the files
/// beside them, swapped in atomically), the staging of a report directory, the run's
/// description for results.json, progress lines and the clocks. Each subcommand lives in a
/// file of its own (commands.cpp: list, run, analyse, study/compare; verify_command.cpp;
/// history_commands.cpp: diff, history, manifest-ctest).
#pragma once
#include <filesystem>
#include <memory>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "analyses/report_section.hpp"
#include "apps/catalogue.hpp"
#include "reports/atomic.hpp"
#include "verify/results_json.hpp"
#include "verify/runner.hpp"

namespace mfv::cli {

/// How reports print the time.
inline constexpr const char* kReportTime = "%Y-%m-%d %H:%M:%S UTC";
/// Where write_report puts the list of problem sections in a report's head.
inline constexpr const char* kProblemsToc = "<!-- mfv: problems toc -->";

/// Hardware threads (at least 1).
unsigned cores();
/// A monotonic wall clock in seconds.
double wall_seconds();

/// Per study a convergence table (as deal.II's ConvergenceTable prints): one row per
/// resolution with each error and its pairwise rate, then the least-squares rate.
void print_rate_table(const Registries& c, const std::vector<StudyResult>& studies,
                      std::ostream& out);

/// Report header line shared by compare and verify.
std::string machine_line(double wall, double cpu);

/// Writes index.md (the head, then each section's summary), the files beside it (name →
/// content, e.g. results.json) and the sections' own files into the staging directory (made,
/// checked and locked before the computation) and swaps it in for the target. A kProblemsToc
/// marker in the head becomes a list of links to the sections' first "## " headings.
void write_report(const Catalogue& c, StagedDirectory& staged, const std::string& head,
                  std::vector<ReportSection> sections, bool vtk, bool vtk_finest_only,
                  const std::vector<std::pair<std::string, std::string>>& files = {});

/// The report's staging directory, made before the computation so that a target mfv may not
/// replace, an unwritable parent or a second writer fails at once (InputError, exit 2).
std::unique_ptr<StagedDirectory> stage_report(const std::filesystem::path& dir, bool force,
                                              const std::string& suite);

/// Heads of the single files mfv writes and may replace (check_output_file).
bool written_by_mfv_verify(const std::string& head);
bool written_by_manifest_ctest(const std::string& head);
bool is_vtk_xml(const std::string& head);

RunInfo run_info(const Catalogue& c, const std::string& kind, double wall, double cpu);

/// "<prefix> resolution i/n: N nodes" before each resolution of a study.
StudyProgress progress_printer(std::ostream& progress, const std::string& prefix);

}  // namespace mfv::cli
