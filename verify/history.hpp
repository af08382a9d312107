/// Run history (issue 28): every `mfv verify` run appends its provenance, every number diff
/// compares (verify/diff.hpp: errors per resolution, rates, headlines) and every regression
/// and ledger verdict to one SQLite file, so "did this error creep up over the last month?"
/// has an answer (`mfv history`), `mfv diff` takes run ids, and drift is judged over the
/// last runs, not only against the checked-in baseline.
///
/// Schema (PRAGMA user_version = kHistorySchema; an older file is migrated on open, a newer
/// one refused):
///   runs(id, generated_utc, suite, manifest, full, commit, dirty, status, failed, cases,
///        wall_seconds, cpu_seconds, provenance JSON)
///   quantities(id, case_id, quantity, sense)          -- sense +1/−1/0 as RunRecord
///   vals(run → runs, quantity → quantities, value)    -- NULL: not measured
///   verdicts(run → runs, kind 'regression'|'ledger', subject, verdict)
/// Writers take an immediate transaction and wait up to 10 s for another (two nightly
/// jobs on one file serialize); a file that is not SQLite, is damaged, is a SQLite database
/// of someone else's (any user_version but mfv's, or none on an existing file) or is shorter
/// than a history can be is refused with the path and the fix and is never rewritten: a
/// history is created only where no file exists.
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "verify/diff.hpp"

struct sqlite3;

namespace mfv {

inline constexpr int kHistorySchema = 1;

struct HistoryRun {
  long id = 0;
  std::string generated_utc, suite, commit, status;
  bool dirty = false, full = false;
  int failed = 0, cases = 0;
};

struct HistoryPoint {
  long run = 0;
  std::string generated_utc, commit;
  double value = NAN;  ///< NaN: not measured in that run
};

/// Drift over the history: a number that moved the wrong way by more than the tolerance from
/// the first to the last of the last `window` runs where each step stayed under it (a creep
/// no night-to-night comparison sees).
struct HistoryDrift {
  std::string case_id, quantity;
  double first = 0, last = 0;
  int runs = 0;  ///< how many runs the window held
  std::string message;
};

class HistoryStore {
 public:
  /// Opens (creating it when absent) and migrates the history file. InputError naming the
  /// file and the fix for a directory, a special file, a file that is not SQLite or damaged,
  /// or a schema newer than this mfv's.
  explicit HistoryStore(const std::filesystem::path& file);
  ~HistoryStore();
  HistoryStore(const HistoryStore&) = delete;
  HistoryStore& operator=(const HistoryStore&) = delete;

  /// Takes and releases the write lock append takes (InputError naming the file when it is
  /// locked past the busy timeout, read-only or on a read-only file system): verify calls it
  /// before the first case, so a history never costs a finished run.
  void check_writable();
  /// Appends a verify run (its results.json), in one transaction; returns the run's id.
  long append(const nlohmann::json& results);

  /// The last `last` runs, newest first.
  std::vector<HistoryRun> runs(int last = 20) const;
  /// A case's quantity over the last `last` runs that had the case, oldest first.
  std::vector<HistoryPoint> series(const std::string& case_id, const std::string& quantity,
                                   int last = 20) const;
  /// The quantities recorded for a case (empty: the case was never recorded).
  std::vector<std::string> quantities(const std::string& case_id) const;
  /// Every case id recorded.
  std::vector<std::string> cases() const;
  /// A recorded run as diff reads it; InputError when there is no such id.
  RunRecord record(long run) const;
  /// "Since when": the first run of the streak of regression FAILs of `case_id` that ends at
  /// `run` (the runs of `run`'s suite, newest first, while the case's verdict is FAIL); none
  /// when the case did not fail in `run`. A run without the case ends the streak.
  std::optional<HistoryRun> failing_since(const std::string& case_id, long run) const;
  /// Slow drifts over the last `window` runs of `suite` ending at `run`.
  std::vector<HistoryDrift> drifts(long run, int window, double tolerance) const;

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  sqlite3* db_ = nullptr;
};

/// "▁▂▅█" of the values (NaN as a space): the trend at a glance.
std::string sparkline(const std::vector<double>& values);

}  // namespace mfv
