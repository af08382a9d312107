/// Machine-readable results: results.json of a study, a comparison or a verification run, and
/// ledger.json (schemas in docs/schemas/, described in docs/results-schema.md).
#pragma once
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "analyses/case.hpp"
#include "verify/ledger.hpp"

namespace mfv {

struct Registries;

inline constexpr const char* kResultsSchema = "mfv-results-1";
inline constexpr const char* kLedgerSchema = "mfv-ledger-1";

/// Builds JSON in which a non-finite number is written as null and its JSON pointer recorded
/// with the reason in "nulls" (a NaN is never written as 0, an inf never as a big number).
class JsonNumbers {
 public:
  /// x, or null with `pointer` → "<NaN|+inf|-inf>: <why>" recorded.
  nlohmann::json number(double x, const std::string& pointer, const std::string& why);
  /// null with `pointer` → `why` recorded: a quantity this kind of run does not measure.
  nlohmann::json absent(const std::string& pointer, const std::string& why);
  /// The recorded pointers and reasons (an object; empty when every number was finite).
  const nlohmann::json& nulls() const { return nulls_; }

 private:
  nlohmann::json nulls_ = nlohmann::json::object();
};

/// The run around the results: what ran it and how long it took.
struct RunInfo {
  std::string kind;  ///< "study", "compare", "analysis" or "verify"
  std::string generated_utc;
  unsigned cores = 1;
  double wall_seconds = 0, cpu_seconds = 0;
  std::vector<std::string> plugins;  ///< plugin libraries loaded (apps/plugins.hpp)
};

/// A headline's stable identifier: its name in lower-case ASCII words joined by '_' (Greek
/// letters spelled out, '+' "plus", '−' "minus", '/' "per", other signs dropped), so that
/// "σθθ vs 1D at 0.1 ms (of p)" is "sigma_theta_theta_vs_1d_at_0_1_ms_of_p". Stable as long as
/// the name is; never empty ("headline" for a name with no letter or digit).
std::string headline_id(const std::string& name);

/// The unit a headline's name states in its last parentheses ("half-drain time (s)" → "s",
/// "σθθ (Pa), row mean" → "Pa", "unstable at (ms)" → "ms"), or "" where the name states none
/// (ratios, counts, verdict flags and relative errors mostly). Only recognised units count:
/// "(of p)" or "(particle sum)" are qualifiers, not units.
std::string headline_unit(const std::string& name);

struct Uncertainty;
/// A discretization uncertainty (reports/uncertainty.hpp) as JSON: levels, class, and each
/// estimated number (absent when not estimated, why_none saying why).
nlohmann::json uncertainty_json(const Uncertainty& u);

/// One study: parameters, per-resolution errors by norm name (common and paper rules), rates
/// by norm name (least squares and pairwise), CPU seconds, headline values and the analysis
/// verdicts. `pointer` is where it sits in the document (for "nulls").
nlohmann::json study_json(const Registries& catalogue, const StudyResult& study,
                          const std::string& pointer, JsonNumbers& numbers);

/// results.json of `mfv study` / `compare` / `analyse`: the studies and the failures
/// ("label: message").
std::string results_json(const Registries& catalogue, const RunInfo& run,
                         const std::vector<StudyResult>& studies,
                         const std::vector<std::string>& failures);

/// The evaluated ledger as JSON (ledger.json, and the "ledger" member of a verify results.json).
nlohmann::json ledger_json(const Ledger& ledger, const std::vector<LedgerEntry>& entries,
                           const std::string& pointer, JsonNumbers& numbers);
/// ledger.json as text.
std::string ledger_json_text(const Ledger& ledger, const std::vector<LedgerEntry>& entries);

/// One case of a verification run as `mfv verify` judged it.
struct VerifyCaseJson {
  std::string id, problem, method;
  std::vector<int> nodes;
  std::string bands, baseline, verdict;  ///< "inside"/"2 violated"/"not run", …, PASS/FAIL
  std::vector<std::string> messages;
  const StudyResult* study = nullptr;  ///< null when the case could not run
  std::string error;
  /// The kinds a FAIL failed by (accuracy, headline, stability, baseline, could not run,
  /// timing); empty for a PASS.
  std::vector<std::string> failed_kinds = {};
  /// CPU now over the baseline's, and that over the machine factor (NaN: not judged).
  double cpu_ratio = NAN, cpu_relative = NAN;
};

/// How a verify run judged CPU time (verify/timing.hpp): "regression.timing" of results.json.
struct VerifyTimingJson {
  double factor = NAN;             ///< the machine factor used (NaN: none measured)
  std::string rule;                ///< how it was measured ("" : none)
  double median = NAN;             ///< the run's median CPU ratio (NaN: too few cases)
  int median_cases = 0;
  double reference_ratio = NAN;    ///< the reference workload's ratio (NaN: not on both sides)
  double reference_seconds = NAN, baseline_reference_seconds = NAN;
  double load_start = -1, load_end = -1;  ///< 1-minute load averages (-1: unknown)
  double steal = NAN;              ///< steal fraction over the run
  bool gated = false;              ///< a timing regression fails the run
  std::vector<std::string> slower; ///< the cases far slower than the factor predicts
  std::string status;              ///< the one-line status
  std::string why_unknown;         ///< why no factor, when none
};

/// results.json of `mfv verify`: suite, regression summary, every case with its study, and the
/// ledger (when the suite has one; `ledger` null otherwise).
std::string verify_results_json(const Registries& catalogue, const RunInfo& run,
                                const std::string& suite, const std::string& manifest,
                                bool full, const std::vector<VerifyCaseJson>& cases,
                                const Ledger* ledger, const std::vector<LedgerEntry>& entries,
                                const VerifyTimingJson* timing = nullptr,
                                const std::map<std::string, int>& failed_by = {});

}  // namespace mfv
