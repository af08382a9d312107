/// `mfv diff A B`: what changed between two verification runs, read from their results.json
/// (docs/schemas/results.schema.json): numbers that moved beyond a tolerance, regression and
/// ledger verdicts that flipped, cases added or removed. A is the earlier run, B the later.
///
/// Numbers compared, per case: the relative L2, H1-seminorm and energy errors at each
/// resolution both ran (smaller is better), the least-squares rates (larger is better), and
/// every headline value at each resolution (direction unknown: "moved"). A number measured in
/// A and not in B (null) is worse; CPU seconds and throughput headlines are left out (they
/// measure the machine as much as the code; results.json's provenance says which machine).
#pragma once
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace mfv {

/// One verification run as diff and the history see it: per case, quantity → value (NaN: not
/// measured) with its sense, and the regression and ledger verdicts.
struct RunRecord {
  struct Number {
    double value = NAN;
    int sense = 0;  ///< +1 larger is better, −1 smaller is better, 0 unknown
  };
  std::string label;  ///< time and commit of the run (or what is known of them)
  std::string suite;  ///< the manifest's suite name ("" when not recorded)
  std::map<std::string, std::map<std::string, Number>> numbers;  ///< case → quantity → value
  std::map<std::string, std::string> case_verdicts, ledger_verdicts;
  std::vector<std::string> order;  ///< case ids in the run's order
  /// CPU seconds per case over its resolutions: kept by the history as kCpuQuantity, never
  /// compared by diff (it measures the machine as much as the code).
  std::map<std::string, double> cpu_seconds;
};

/// The history's name for a case's CPU seconds.
inline constexpr const char* kCpuQuantity = "CPU seconds (all resolutions)";

/// The record of a verify results.json (InputError when its layout is not the schema's).
RunRecord run_record(const nlohmann::json& results);

struct DiffOptions {
  double tolerance = 0.05;  ///< relative change that counts, |b − a| / max(|a|, floor)
  double floor = 1e-12;     ///< values both below this (round-off) never differ
};

struct DiffEntry {
  enum class Direction { worse, better, moved };
  Direction direction = Direction::moved;
  std::string case_id;   ///< "" for suite-level entries
  std::string quantity;  ///< "L2 relative error at 241 nodes", "ledger 001-T3-sph", …
  std::string before, after;  ///< as printed
  double relative = 0;        ///< signed relative change of a number; 0 for verdicts
};

struct RunDiff {
  std::string before_label, after_label;  ///< path, commit and time of each run
  std::vector<DiffEntry> numbers;         ///< values beyond the tolerance
  std::vector<DiffEntry> verdicts;        ///< regression and ledger verdicts that flipped
  std::vector<std::string> added, removed;  ///< case ids
  /// Ledger rows whose case ran in one run only ("not run" in the other): not a flip.
  std::vector<std::string> ledger_not_compared;
  int worse() const;
  int better() const;
};

/// results.json of a run: the file itself, or a report directory holding one. InputError
/// naming the path and the fix when it is missing, not JSON, or not a verify run's.
nlohmann::json load_run_results(const std::filesystem::path& path);

RunDiff diff_runs(const RunRecord& before, const RunRecord& after,
                  const DiffOptions& options = {});
RunDiff diff_runs(const nlohmann::json& before, const nlohmann::json& after,
                  const DiffOptions& options = {});

/// The diff as text for people: a summary line, then worse, flipped, better, moved, added
/// and removed, each a table. `markdown` writes the report's "Changes since the last run".
std::string diff_text(const RunDiff& d, bool markdown = false);

}  // namespace mfv
