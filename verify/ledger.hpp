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
//                                        # or "at_most" (ours ≤ paper·(1 + tolerance)), or a
//                                        # range: "range" with paper = [low, high] at one
//                                        # resolution (ours in [low(1 − tol), high(1 + tol)])
//   role = "check"                       # optional: our own check, not a paper's claim
//                                        # (counted apart; default "claim")
//   # (2) a number the paper states that no problem holds (rates "up to 15.92"):
//   cases = ["laplace-tanh/a", "laplace-tanh/b"]  # ours = the largest measure over them
//   measure = "l2_rate"                  # l2_rate, h1_rate, energy_rate or headline:<name>
//   paper = [15.92]; tolerance = 0.1; compare = "ratio"
//   # (3) a finding (Problem::findings()), checked on the run's studies of that problem:
//   finding = "cantilever:kbm-si-rate"   # "<problem>:<Finding::id>"
//   problem_params = { a = 0 }           # optional: only studies with these problem parameters
//   cases = ["rubber-ring/kbm-si-lagrangian", ...]  # optional: only these suite cases' studies
//                                        # (the paper's own method or counts), each must run
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
//   follow = "004-II-rates-spline-l2"    # measure rows: read the measure on the case the
//                                        # named earlier row's value came from, reading by
//                                        # reading (a figure's L2 and H1 claims on one study)
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
//                                        # the case), finding, problem_params (and, for
//                                        # finding rows, cases)
// The verdict of a row in a [[source]] (below: one reading for a whole table or figure) is
// that of the source's reading. Otherwise it is that of the closest reading that is not
// fitted: the best verdict (reproduced, partly, not reproduced, not reached), then the
// smallest largest |ln(ours/paper)| (ratio rows) or |ours − paper|/tolerance (difference
// rows); the row's own reading wins a tie. A try that reproduces makes the row "reproduced
// under a stated reading" and is named.
//
// Evidence, how sure ours is: checks compute the chosen reading's value by a second route.
//   [[row.check]]                        # a check of the row's own reading;
//                                        # [[row.try.check]] checks that try
//   kind = "independent"                 # or "converged"
//   route = "closed form: …"             # required: what the second computation is
//   case = "..."                         # the same overrides as a try
//   refinement = 2, order = 2            # converged checks: h over the check's h, and the
//                                        # formal order (the two-level GCI of a value of one
//                                        # resolution; defaults 2 and 1)
//   reference = "../tests/reference/x.json"  # finding rows: judged on an independent
//   studies = ["kbm-si (independent)"]   # implementation's recorded studies instead of cases
//                                        # (verify/reference_studies.hpp; the path relative
//                                        # to the ledger; studies: their labels, default all)
// A value check agrees when each of its values is within the row's tolerance of ours (ratio
// or difference as the row compares); a finding check when its verdict is ours. The evidence
// is "independent" when an independent check agrees and none that ran disagrees, else
// "converged" when a converged one does and none that ran disagrees (every finer resolution,
// quadrature or time step moved ours by less than the tolerance), else "single run"; a check
// that disagrees is listed with its value. A reading that reproduces while a converged check
// that ran disagrees is "partly" (reproduced at its resolution, not under refinement).
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "methods/core/params.hpp"
#include "analyses/case.hpp"
#include "problems/comparison.hpp"
#include "problems/problem.hpp"
#include "reports/uncertainty.hpp"

namespace mfv {

struct Registries;
struct Manifest;

/// Verdict words the ledger adds to problems/comparison.hpp's.
inline constexpr const char* kNotRun = "not run";  ///< its case did not run in this invocation

/// The verdicts in the order the summary counts them.
const std::vector<std::string>& ledger_verdicts();

/// How a measure row reads a convergence rate off a study (004 II eq 7.3 defines the rate as
/// a slope of ln error against ln Δx; a paper's "as high as" may be a local slope).
enum class RateStatistic {
  least_squares,  ///< the least-squares slope over every resolution
  finest_pair,    ///< the slope between the two finest resolutions
  best_pair,      ///< the largest slope between successive resolutions
};

struct LedgerRow;

/// A second computation of a reading's value: the row's evidence.
struct LedgerCheck {
  enum class Kind { independent, converged };
  Kind kind = Kind::converged;
  std::string route;  ///< what the second computation is
  int line = 0;
  /// A converged check: how much finer its run is than the reading's (h over the check's h,
  /// e.g. 2 for half the step) and the formal order of what it refines: the two-level GCI of
  /// a single-resolution value (defaults 2 and 1: r^p = 2, stated as assumed).
  double refinement = 2, order = 1;
  std::shared_ptr<const LedgerRow> row;  ///< the reading with the check's replacements
};

/// Another reading of the claim that the paper's text allows ([[row.try]]).
struct LedgerReading {
  std::string name, quote;
  bool fitted = false;  ///< a constant fitted to the paper's numbers: shown, never counted
  int line = 0;
  std::shared_ptr<const LedgerRow> row;  ///< the row with the reading's replacements
  std::vector<LedgerCheck> checks;
};

struct LedgerRow {
  enum class Kind { published, measure, finding, open };
  std::string id, source, claim, reading, reason;
  std::string quote;  ///< the paper's words behind the row's own reading
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
  /// range: the claim is an interval, paper = [low, high] at one resolution; ours within the
  /// interval widened by the tolerance (relative) at each end.
  enum class Bound { none, at_least, at_most, range } bound = Bound::none;
  /// A claim of a paper (counted per paper), our own check of the suite (a closed form, a
  /// column at rest: listed and counted apart, never among the papers' claims), or a paper's
  /// claim about CPU time (cost): judged on this machine's CPU seconds, whose ratios move
  /// with its load (two runs of one commit here: 001-9.3-eulerian-slower's Eulerian
  /// efg-ni/sph 1.39 and 1.59 against its bound 1.5), so listed and counted apart from the
  /// claims judged on computed numbers, whose counts a run of the same commit repeats.
  enum class Role { claim, check, cost } role = Role::claim;
  std::string measure;  ///< measure rows
  /// Measure rows: the earlier row whose chosen case this row reads its measure on, under the
  /// reading of the same name (a figure's L2 and H1 claims judged on one study, issue 44);
  /// empty: the largest over the row's own cases.
  std::string follow;
  RateStatistic statistic = RateStatistic::least_squares;  ///< measure rows of a rate
  std::string finding;  ///< finding rows: the Finding::id
  /// A check of a finding row judged on an independent implementation's recorded studies
  /// (verify/reference_studies.hpp) instead of cases: the file (resolved against the ledger's
  /// directory) and the labels of its studies (empty: all).
  std::filesystem::path reference;
  std::vector<std::string> reference_studies;
  std::vector<LedgerReading> tries;  ///< the other readings tried (the reading search)
  std::vector<LedgerCheck> checks;   ///< evidence for the row's own reading
};

/// One reading for a whole source, a table or figure of a paper (issue 43): where the text
/// leaves a choice open, the reading is chosen for the source from its quoted text before the
/// values are compared, and every row of the source is judged under it. The other readings
/// the rows try are reported per row and per source (how many rows each reproduces), never
/// counted: a reading that passes one row and fails its sibling is not a reading of the table.
///   [[source]]
///   name = "001 Table 3"                  # required, unique
///   rows = ["001-T3-*-1Lc", "001-T3-*-2Lc"]  # required: row ids or globs, each row in one source
///   reading = ""                          # optional: a [[row.try]] name every row has; empty
///                                         # (the default): each row's own reading
///   quote = "“…” (001 §9.2)"              # required: the text the reading is chosen from
///   pairs = [["001-T3-sph-1Lc", "001-T3-sph-2Lc"]]  # optional: rows whose ratio (second over
///                                         # first, ours beside the paper's) the page shows per reading
struct LedgerSource {
  std::string name, reading, quote;
  std::vector<std::string> rows;  ///< row ids, in ledger order
  std::vector<std::pair<std::string, std::string>> pairs;
  int line = 0;
};

struct Ledger {
  std::filesystem::path path;
  std::vector<LedgerRow> rows;
  std::vector<LedgerSource> sources;
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

/// One check of a reading, evaluated.
struct LedgerCheckOutcome {
  const LedgerCheck* check = nullptr;
  std::vector<double> values;  ///< value rows: the check's values (NaN: not reached)
  std::string ours_text;       ///< finding rows: the check's numbers
  std::vector<FindingNumber> numbers;  ///< finding rows: the numbers its verdict rests on
  std::string verdict;         ///< the check's own verdict against the paper
  bool agrees = false;         ///< within the row's tolerance of the reading (or same verdict)
};

/// One reading of a row (its own, or a try), evaluated.
struct LedgerReadingOutcome {
  const LedgerRow* row = nullptr;          ///< the reading's row
  const LedgerReading* reading = nullptr;  ///< null: the row's own reading
  std::vector<double> ours;
  std::vector<Comparison> compared;
  std::string ours_text, criterion;
  std::string verdict;  ///< as compared, before a stated reading is named
  std::string why;      ///< why it could not be compared (not run, could not run, …)
  /// How far from the paper: the largest |ln(ours/paper)| (ratio rows) or
  /// |ours − paper|/tolerance (difference rows); 0 for findings; ∞ when not compared.
  double distance = 0;
  std::string from_case;  ///< measure rows: the case whose value is ours
  std::vector<LedgerCheckOutcome> checks;
  std::string evidence;  ///< kEvidence*, or "–" when the reading did not run
  /// Per value: its discretization uncertainty (reports/uncertainty.hpp) from the study's
  /// resolutions up to it (a rate: from its pairwise rates), or, with a single level, from
  /// the first converged check's value (two levels, F_s = 3, the check's refinement and
  /// order); `why_none` says why not. A finding's: one per number its verdict rests on
  /// (`numbers`), from that number's levels, or, read at one resolution, from the same number
  /// in the first converged check that has it (two levels, F_s = 3).
  std::vector<Uncertainty> uncertainty;
  /// Finding rows: the numbers the verdict was decided on, and the name of each uncertainty
  /// (`uncertainty_of[i]` names `uncertainty[i]`; empty for value rows, whose values are ours).
  std::vector<FindingNumber> numbers;
  std::vector<std::string> uncertainty_of;
  /// Per value: whether the paper's value lies inside ours ± (U + tolerance); false when U is
  /// not known.
  std::vector<bool> paper_inside;
  /// The reading's name: the try's, the row's stated reading, or "as printed".
  std::string name() const;
};

/// Evidence words: how sure ours is.
inline constexpr const char* kEvidenceIndependent = "independent";
inline constexpr const char* kEvidenceConverged = "converged";
inline constexpr const char* kEvidenceSingle = "single run";

/// One evaluated row: the verdict, values and evidence of the closest counted reading.
struct LedgerEntry {
  const LedgerRow* row = nullptr;
  const LedgerRow* read = nullptr;  ///< the reading the verdict comes from (row or a try's)
  std::vector<double> ours;       ///< per paper value (NaN: not reached or not run)
  std::vector<Comparison> compared;
  std::string ours_text;          ///< finding rows: the measured numbers behind the verdict
  std::string criterion;          ///< finding rows: how the verdict is decided
  std::string verdict;            ///< one of ledger_verdicts()
  std::string why;                ///< the gap and the reason, or why it is open / not run
  std::string evidence;           ///< kEvidence*, or "–" (not run, not yet built)
  std::string reading;            ///< the name of the reading the verdict comes from
  std::vector<LedgerReadingOutcome> readings;  ///< [0] the row's own, then every try
  std::size_t chosen = 0;         ///< index into readings
  /// The [[source]] whose one reading the row is judged under (null: the row alone).
  const LedgerSource* source = nullptr;
};

/// Evaluates every row on the cases that ran (`ran`: case id → outcome; a case absent from
/// it did not run in this invocation).
std::vector<LedgerEntry> evaluate_ledger(const Ledger& ledger, const Registries& catalogue,
                                         const Manifest& manifest,
                                         const std::map<std::string, CaseOutcome>& ran);

/// Verdict → count over the rows of `role` (the papers' claims by default), every verdict
/// of ledger_verdicts() present.
std::map<std::string, int> count_verdicts(const std::vector<LedgerEntry>& entries,
                                          LedgerRow::Role role = LedgerRow::Role::claim);
/// "31 reproduced, 4 reproduced under a stated reading, … of 110 claims" (non-zero counts,
/// in order), then "; our own checks: …" when the ledger has any.
std::string verdict_counts_line(const std::vector<LedgerEntry>& entries);

/// The paper a row belongs to ("000", "001", "003", "004", or "other" for claims of other
/// sources) and its section ("II §7", "§9.2", …, from the row's source).
std::string ledger_paper(const LedgerRow& row);
std::string ledger_section(const LedgerRow& row);

/// The ledger page, by paper: verdict and evidence counts per paper and section, then per
/// paper the rows (id, claim, paper, ours, ratio/difference, tolerance, verdict, evidence,
/// reading), then per row the readings tried and the checks.
std::string ledger_markdown(const std::vector<LedgerEntry>& entries);
/// How many claim rows whose evidence is "converged" carry a discretization uncertainty
/// (issue 44's count): `some` for at least one of their numbers, `every` for all of them.
/// Our own checks (role check) are left out, as they are from the papers' counts.
struct UncertaintyCoverage {
  int converged = 0, some = 0, every = 0;
};
UncertaintyCoverage uncertainty_coverage(const std::vector<LedgerEntry>& entries);
/// The verdict and evidence counts per paper and per section (index.md's ledger; the rows are
/// ledger.md's).
std::string ledger_counts_markdown(const std::vector<LedgerEntry>& entries);
/// ledger.csv (RFC 4180 quoting): a row per claim, with its evidence, the reading its verdict
/// comes from, and every reading and check tried with its values.
std::string ledger_csv(const std::vector<LedgerEntry>& entries);
/// The sources judged under one reading (ledger.md's section, verify/ledger_sources.cpp): per
/// source the reading and the text it rests on, then every reading its rows tried with each
/// row's value, ratio and verdict under it, how many rows it reproduces, the readings that
/// pass some rows and fail others (reported, not counted), and the pairs' ratios. "" when the
/// ledger has no [[source]].
std::string ledger_sources_markdown(const Ledger& ledger, const std::vector<LedgerEntry>& entries);

/// Our value of a published quantity in one case: "error u" is the relative L2 error on the
/// common rule, "error du/dx" the relative H1 seminorm, anything else a headline (NaN if absent).
double our_published_value(const CaseResult& r, const std::string& quantity);

}  // namespace mfv
