/// The reproduction ledger (suites/ledger.toml): one row per quantitative claim or stated
/// finding of the papers, the suite case that measures ours, and a verdict computed from the run.
#pragma once
// Format (suites/ledger.toml is the complete, checked-in instance):
//
//   [[row]]
//   id = "004-II-T1-fem"                 # required, unique
//   source = "004 II §7, Table 1"        # required: paper, section, table/figure/equation
//   claim = "FEM peak u'(3), 21…241 nodes"  # required, one line
//   reading = "..."                      # optional: the reading under which it is reproduced
//   reason = "..."                       # optional: best explanation of a gap (shown unless
//                                        # the row is reproduced)
//   # then exactly one of four kinds:
//   # (1) published values of a problem (Problem::published()): the row names them and
//   #     restates them; loading checks value and tolerance against the problem's
//   case = "laplace-tanh/fem"            # a case id of the manifest (or, when no suite case
//                                        # measures it: problem, problem_params, method,
//                                        # method_params, and the row is "not run")
//   published = "004 II Table 1"         # PublishedValue::source
//   quantity = "peak du/dx at x=3"       # PublishedValue::quantity
//   nodes = [21, 41]                     # PublishedValue::nodes, one per paper value
//   paper = [3.3168, 6.0343]             # PublishedValue::value, in the order of nodes
//   tolerance = 0.05                     # PublishedValue::tolerance
//   compare = "ratio"                    # or "difference" (default ratio), or a one-sided
//                                        # claim: "at_least" (ours ≥ paper·(1 − tolerance))
//                                        # or "at_most" (ours ≤ paper·(1 + tolerance))
//   # (2) a number the paper states that no problem holds (rates "up to 15.92"):
//   cases = ["laplace-tanh/a", "laplace-tanh/b"]  # ours = the largest measure over them
//   measure = "l2_rate"                  # l2_rate, h1_rate, energy_rate or headline:<name>
//   paper = [15.92]; tolerance = 0.1; compare = "ratio"
//   # (3) a finding (Problem::findings()), checked on the run's studies of that problem:
//   finding = "cantilever:kbm-si-rate"   # "<problem>:<Finding::id>"
//   problem_params = { a = 0 }           # optional: only studies with these problem parameters
//   # (4) an open row: a problem that is not built yet ("not yet built" while the catalogue
//   #     has no such problem; an error once it has one, so the row must then name a case)
//   problem = "rubber-ring"
//
// A finding row whose problem exists but has no finding of that id yet is "not yet built"
// too. Every error is "<file>:<line>: <what>; <fix>" (mfv::InputError, exit 2).
//
// Every kind may also say what its own reading rests on, and which statistic it takes:
//   quote = "“…” (004 II eq 7.3)"        # the paper's sentence or equation behind the row's
//                                        # own reading (the row as written)
//   statistic = "finest_pair"            # measure rows with a rate: least_squares (default,
//                                        # the slope over every resolution), finest_pair (the
//                                        # slope between the two finest), best_pair (the
//                                        # largest slope between successive resolutions)
//
// The reading search: other readings the paper's text allows, each a suite case or an option
// of one, justified by a quote. Each replaces some of the row's keys and inherits the rest:
//   [[row.try]]
//   name = "DEM derivative (eq 6.6)"     # required, short: what differs from the row's reading
//   quote = "“…” (004 II §6)"            # required: the sentence or equation that allows it
//   fitted = true                        # optional: a constant fitted to the paper's numbers;
//                                        # shown for scale, never counted in the verdict
//   case = "..." / cases = [...]         # any of: case, cases, nodes (published rows: where
//   nodes = [349]                        # ours is read; the paper values stay the row's),
//   statistic = "best_pair"              # measure, statistic, quantity (another headline of
//                                        # the case), finding, problem_params
// The verdict is that of the closest reading that is not fitted: the best verdict (reproduced,
// partly, not reproduced, not reached), then the smallest largest |ln(ours/paper)| (ratio
// rows) or |ours − paper|/tolerance (difference rows); the row's own reading wins a tie. A
// try that reproduces makes the row "reproduced under a stated reading" and is named.
//
// Evidence, how sure ours is: checks compute the chosen reading's value by a second route.
//   [[row.check]]                        # a check of the row's own reading;
//                                        # [[row.try.check]] checks that try
//   kind = "independent"                 # or "converged"
//   route = "closed form: …"             # required: what the second computation is
//   case = "..."                         # the same overrides as a try
// A value check agrees when each of its values is within the row's tolerance of ours (ratio
// or difference as the row compares); a finding check when its verdict is ours. The evidence
// is "independent" when an independent check agrees, else "converged" when a converged one
// does (a finer resolution, quadrature or time step moved ours by less than the tolerance),
// else "single run"; a check that disagrees is listed with its value.
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "methods/core/params.hpp"
#include "analyses/case.hpp"
#include "problems/comparison.hpp"

namespace mfv {

struct Registries;
struct Manifest;

/// Verdict words the ledger adds to problems/comparison.hpp's.
inline constexpr const char* kNotRun = "not run";  ///< its case did not run in this invocation

/// The verdicts in the order the summary counts them.
const std::vector<std::string>& ledger_verdicts();

struct LedgerRow {
  enum class Kind { published, measure, finding, open };
  std::string id, source, claim, reading, reason;
  Kind kind = Kind::open;
  int line = 0;
  std::vector<std::string> cases;  ///< published: at most one; measure: one or more
  // published / open / finding
  std::string problem;
  Params problem_params, method_params;
  std::string method;
  std::string published_source, quantity;
  std::vector<int> nodes;
  std::vector<double> paper;
  double tolerance = 0;
  CompareBy compare = CompareBy::ratio;
  /// A one-sided claim ("keeps at least 84 %"): ours may lie anywhere on the stated side;
  /// the tolerance (relative) applies only on the other. 0: two-sided.
  enum class Bound { none, at_least, at_most } bound = Bound::none;
  std::string measure;  ///< measure rows
  std::string finding;  ///< finding rows: the Finding::id
};

struct Ledger {
  std::filesystem::path path;
  std::vector<LedgerRow> rows;
};

/// Reads and checks a ledger against the manifest (every case it names exists) and the
/// catalogue (every published value it names exists with that value and tolerance).
Ledger load_ledger(const std::filesystem::path& path, const Manifest& manifest,
                   const Registries& catalogue);

/// What one manifest case did in this invocation.
struct CaseOutcome {
  const StudyResult* study = nullptr;  ///< null: could not run (see error)
  std::string error;
};

/// One evaluated row.
struct LedgerEntry {
  const LedgerRow* row = nullptr;
  std::vector<double> ours;       ///< per paper value (NaN: not reached or not run)
  std::vector<Comparison> compared;
  std::string ours_text;          ///< finding rows: the measured numbers behind the verdict
  std::string criterion;          ///< finding rows: how the verdict is decided
  std::string verdict;            ///< one of ledger_verdicts()
  std::string why;                ///< the gap and the reason, or why it is open / not run
};

/// Evaluates every row on the cases that ran (`ran`: case id → outcome; a case absent from
/// it did not run in this invocation).
std::vector<LedgerEntry> evaluate_ledger(const Ledger& ledger, const Registries& catalogue,
                                         const Manifest& manifest,
                                         const std::map<std::string, CaseOutcome>& ran);

/// Verdict → count, every verdict of ledger_verdicts() present.
std::map<std::string, int> count_verdicts(const std::vector<LedgerEntry>& entries);
/// "31 reproduced, 4 reproduced under a stated reading, …" (non-zero counts, in order).
std::string verdict_counts_line(const std::vector<LedgerEntry>& entries);

/// The ledger as a Markdown table (id, source, claim, paper, ours, ratio/difference,
/// tolerance, verdict, gap/reason).
std::string ledger_markdown(const std::vector<LedgerEntry>& entries);
/// The ledger as index.md shows it: one short row per claim (id, source, claim, ours/paper,
/// verdict); the full table (ledger_markdown) is on its own page.
std::string ledger_summary_markdown(const std::vector<LedgerEntry>& entries);
/// ledger.csv (RFC 4180 quoting).
std::string ledger_csv(const std::vector<LedgerEntry>& entries);

/// Our value of a published quantity in one case: "error u" is the relative L2 error on the
/// common rule, "error du/dx" the relative H1 seminorm, anything else a headline (NaN if absent).
double our_published_value(const CaseResult& r, const std::string& quantity);

}  // namespace mfv
