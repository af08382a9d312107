/// The `mfv` subcommands, callable from main and from tests.
#pragma once
#include <ostream>
#include <string>
#include <vector>

#include "analyses/case.hpp"
#include "apps/catalogue.hpp"

namespace mfv {

/// `mfv list [WHAT]`: WHAT empty names every kernel, approximation, integration scheme,
/// method, problem and analysis in one line each; a kind ("methods") lists that registry with
/// every parameter; a name shows that entry. InputError ("did you mean") for anything else.
void command_list(const Catalogue& c, const std::string& what, std::ostream& out);

struct RunOptions {
  std::string problem, method, method_params, problem_params;
  int nodes = 0;
  double perturbation = 0;
  std::string vtk;  ///< optional .vtp path
  std::string analysis;  ///< empty: the problem's default analysis
};
/// `mfv run`: one case; prints errors, headline quantity and CPU times. Returns the exit
/// code: 1 when a transient run went unstable (its verdict is printed), 0 otherwise.
int command_run(const Catalogue& c, const RunOptions& o, std::ostream& out);

struct CompareOptions {
  std::string problem, problem_params;
  std::string analysis;  ///< empty: the problem's default analysis
  /// Each "name" or "name:key=value,...", e.g. "rkpm:kernel=gaussian,j=1".
  std::vector<std::string> methods;
  std::vector<int> nodes;  ///< empty: the problem's standard (or, with full, full) resolutions
  bool full = false;
  double perturbation = 0;
  std::string report;  ///< report directory; empty: print only
  bool vtk = true;
  bool vtk_finest_only = false;  ///< --vtk=finest: each study's finest resolution only
  bool force = false;  ///< replace an mfv report that holds files mfv did not write
};
/// `mfv study` / `mfv compare`: refinement studies of one or several methods on one problem;
/// prints a rate table and, with a report directory, writes the comparison report there.
/// Returns the exit code (0, or 3 if a study could not run).
int command_compare(const Catalogue& c, const CompareOptions& o, std::ostream& out,
                    std::ostream& progress);

/// The convergence table `mfv study` and `mfv compare` print per method (as deal.II's
/// ConvergenceTable): the label, then per resolution the particle count, h, each error norm
/// (relative L2; the energy norm for 2D elasticity, the H1 seminorm in 1D; transient runs only
/// their main L2 error) with its pairwise rate, and CPU seconds; a last row with the
/// least-squares rates and the total CPU time. Markdown, units in every header. An analysis
/// (no error norms) shows its measured headline values per resolution instead.
std::string convergence_table(const Registries& plugins, const StudyResult& s);

struct AnalyseOptions {
  std::string problem, method, method_params, problem_params;
  int nodes = 0;       ///< 0: the problem's first standard resolution
  std::string report;  ///< report directory; empty: print only, as run, study and compare
  bool no_report = false;  ///< kept for scripts: print only (the default now)
  bool force = false;  ///< replace an mfv report that holds files mfv did not write
  std::string analysis;  ///< empty: the problem's default analysis
};
/// `mfv analyse` and `mfv dispersion`: one case of any problem (typically dispersion,
/// time-step, enriched-bar, stretch-map) with any method by name; prints what the analysis
/// prints (set-up, verdicts, measured values; errors for field problems) with the published
/// values, and writes a report with the plots and CSV data. Returns the analysis's exit status
/// (1 for a run that went unstable).
int command_analyse(const Catalogue& c, const AnalyseOptions& o, std::ostream& out);

/// "rkpm:kernel=gaussian,j=1" → method name and parameters; throws InputError if malformed.
std::pair<std::string, std::string> split_method_spec(const std::string& spec);

struct VerifyOptions {
  std::string manifest;
  bool full = false;
  std::vector<std::string> cases;  ///< only these ids or globs (Manifest::select); empty: all
  std::string junit;               ///< also write JUnit XML here (verify/junit.hpp); empty: none
  bool list = false;               ///< print the selected cases and run nothing
  /// Append the run to this SQLite history (verify/history.hpp); empty: beside the report,
  /// `<report dir>.history.sqlite`, or none with --no-report.
  std::string history;
  bool no_history = false;
  bool update_baseline = false;
  std::string report;              ///< empty: runs/<suite name> under the working directory
  bool no_report = false;
  bool vtk = true;  ///< the command line's default for verify is false (--vtk=none)
  /// --vtk=finest: each study's finest resolution only.
  bool vtk_finest_only = false;
  bool force = false;  ///< replace an mfv report that holds files mfv did not write
  /// A timing regression (a case far slower than the run's machine factor) fails the run
  /// (also [suite] timing_gate = true); without it timing is reported only.
  bool timing_gate = false;
  /// A case not in the baseline fails; without it a new case is "new: record it".
  bool require_baseline = false;
};
/// `mfv verify` (apps/verify_command.cpp): runs a manifest's studies, checks every band and
/// the baseline, judges CPU against the run's machine factor, writes the report, prints one
/// verdict line per case and every violation. Returns 0 when all cases are inside their bands
/// and no number got worse than the baseline by more than the tolerance (and, under a timing
/// gate, no case was a timing regression), 1 otherwise.
int command_verify(const Catalogue& c, const VerifyOptions& o, std::ostream& out,
                   std::ostream& progress);

struct DiffCommandOptions {
  std::string before, after;  ///< report directories, their results.json, or history run ids
  double tolerance = 0.05;    ///< relative change that counts
  std::string history;        ///< the history file run ids refer to
};
/// `mfv diff A B` (verify/diff.hpp): prints what moved from run A to run B; returns 1 when
/// something got worse (a number beyond the tolerance, a verdict that flipped for the worse,
/// a measurement lost), else 0.
int command_diff(const DiffCommandOptions& o, std::ostream& out);

/// Runs the history judges drift over.
inline constexpr int kHistoryWindow = 10;

struct HistoryCommandOptions {
  std::string history;   ///< the SQLite file
  std::string subject;   ///< "CASE", "CASE/QUANTITY" or empty (the runs)
  std::string quantity;  ///< or given apart
  int last = 20;
};
/// `mfv history`: the runs recorded; a case's quantities with their trend; one quantity over
/// the last runs (time, commit, value).
int command_history(const HistoryCommandOptions& o, std::ostream& out);

/// `mfv docs` (apps/docs_command.cpp): checks (or, with `write`, rewrites) the blocks of
/// `files` generated from a manifest ('<!-- mfv:begin KIND MANIFEST -->' … '<!-- mfv:end -->':
/// the counts, the methods × problems table). Returns 1 when a block is out of date and
/// `write` is false, else 0; InputError for a file without blocks or a malformed one.
int command_docs(const Catalogue& c, const std::vector<std::string>& files, bool write,
                 std::ostream& out);

/// `mfv manifest-ctest`: writes a CTest script with one test per manifest case
/// (`mfv verify <manifest> --case <id> --no-report`), labelled regression, problem, method and
/// the case's labels, so `ctest -L rkpm` and `ctest -j` work.
void command_manifest_ctest(const std::string& manifest, const std::string& mfv_executable,
                            const std::string& output);

}  // namespace mfv
