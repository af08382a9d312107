/// `mfv diff`, `mfv history` and `mfv manifest-ctest`: what the nightly's records answer.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <optional>

#include <fmt/format.h>

#include "apps/command_support.hpp"
#include "apps/commands.hpp"
#include "methods/core/errors.hpp"
#include "methods/core/names.hpp"
#include "reports/markdown.hpp"
#include "verify/diff.hpp"
#include "verify/history.hpp"
#include "verify/manifest.hpp"

namespace mfv {

using namespace cli;

int command_diff(const DiffCommandOptions& o, std::ostream& out) {
  if (!(o.tolerance > 0) || !std::isfinite(o.tolerance))
    throw InputError(fmt::format("--tolerance {} must be a positive finite relative change, "
                                 "e.g. 0.05",
                                 o.tolerance));
  DiffOptions d;
  d.tolerance = o.tolerance;
  // A path (a report directory or a results.json), or a run id of the history.
  std::optional<HistoryStore> history;
  auto record_of = [&](const std::string& what) {
    std::error_code ec;
    const bool digits = !what.empty() && std::all_of(what.begin(), what.end(), [](char ch) {
      return std::isdigit(static_cast<unsigned char>(ch));
    });
    if (!digits || std::filesystem::exists(what, ec)) {
      const nlohmann::json doc = load_run_results(what);
      try {
        return run_record(doc);
      } catch (const InputError& e) {
        // Which of the two runs has the wrong layout (issue 45's fuzz_diff: it was not said).
        throw InputError(fmt::format("'{}': {}", what, e.what()));
      }
    }
    if (o.history.empty())
      throw InputError(fmt::format("mfv diff: '{}' is a run id; name the history it is in with "
                                   "--history FILE",
                                   what));
    if (!std::filesystem::exists(o.history, ec))
      throw InputError(fmt::format("mfv diff: no history at '{}'; `mfv verify` writes one "
                                   "beside its report (<report>.history.sqlite)",
                                   o.history));
    if (!history) history.emplace(o.history);
    // A run id past what a long holds is no run of any history.
    if (what.size() > 15)
      throw InputError(fmt::format("mfv diff: run id '{}' is out of range; `mfv history "
                                   "--history {}` lists the runs",
                                   what, o.history));
    return history->record(std::stol(what));
  };
  const RunRecord before = record_of(o.before), after = record_of(o.after);
  if (!before.suite.empty() && !after.suite.empty() && before.suite != after.suite)
    throw InputError(fmt::format("mfv diff: the runs are of different suites ('{}' is of "
                                 "'{}', '{}' of '{}'); diff compares two runs of one suite",
                                 o.before, before.suite, o.after, after.suite));
  const RunDiff diff = diff_runs(before, after, d);
  out << diff_text(diff);
  // A case that ran before and not now is named (a manifest that dropped it); a later run
  // that lost every case compared nothing, and fails as a number that got worse does.
  const bool all_gone = !before.order.empty() && diff.removed.size() == before.order.size();
  // An earlier run without a case or a ledger row the later one has (a results.json whose
  // cases were all removed) gives nothing to compare against: that is no pass either.
  const bool common_row = std::any_of(
      before.ledger_verdicts.begin(), before.ledger_verdicts.end(),
      [&](const auto& r) { return after.ledger_verdicts.count(r.first) > 0; });
  if (before.order.empty() && !common_row) {
    out << fmt::format("the earlier run '{}' has no case and no ledger row of the later run: "
                       "nothing was compared\n",
                       o.before);
    return 1;
  }
  if (!diff.removed.empty())
    out << fmt::format("{} of the earlier run's {} case(s) are missing from the later run{}\n",
                       diff.removed.size(), before.order.size(),
                       all_gone ? " (every one: nothing was compared)" : "");
  return diff.worse() > 0 || all_gone ? 1 : 0;
}

int command_history(const HistoryCommandOptions& o, std::ostream& out) {
  if (o.last < 1)
    throw InputError(fmt::format("--last {} must be at least 1", o.last));
  if (!std::filesystem::exists(o.history))
    throw InputError(fmt::format("no history at '{}'; `mfv verify` writes one beside its report "
                                 "(<report>.history.sqlite) or where --history says",
                                 o.history));
  const HistoryStore h(o.history);
  if (o.subject.empty()) {
    MarkdownTable t({"run", "time", "suite", "commit", "status", "failed"},
                    {'r', 'l', 'l', 'l', 'l', 'r'});
    for (const auto& r : h.runs(o.last))
      t.add_row({std::to_string(r.id), r.generated_utc, r.suite + (r.full ? " (--full)" : ""),
                 r.commit.substr(0, 12) + (r.dirty ? "+changes" : ""), r.status,
                 fmt::format("{} of {}", r.failed, r.cases)});
    out << t.str();
    return 0;
  }
  // CASE/QUANTITY: the longest recorded case id that the subject starts with.
  const std::vector<std::string> cases = h.cases();
  std::string case_id, quantity = o.quantity;
  for (const auto& c : cases)
    if ((o.subject == c || o.subject.starts_with(c + "/")) && c.size() > case_id.size()) case_id = c;
  if (case_id.empty())
    throw InputError(fmt::format("history {} has no case '{}'; {}{} cases are recorded",
                                 o.history, o.subject, did_you_mean(o.subject, cases),
                                 cases.size()));
  if (o.subject.size() > case_id.size()) quantity = o.subject.substr(case_id.size() + 1);
  if (quantity.empty()) {
    // Every quantity of the case with its last value and trend.
    MarkdownTable t({"quantity", "last", "trend (oldest → newest)"}, {'l', 'r', 'l'});
    for (const auto& q : h.quantities(case_id)) {
      const auto pts = h.series(case_id, q, o.last);
      std::vector<double> v;
      for (const auto& p : pts) v.push_back(p.value);
      t.add_row({q, pts.empty() || !std::isfinite(pts.back().value)
                        ? "–"
                        : fmt::format("{:.4g}", pts.back().value),
                 sparkline(v)});
    }
    out << t.str();
    return 0;
  }
  const auto known = h.quantities(case_id);
  if (std::find(known.begin(), known.end(), quantity) == known.end())
    throw InputError(fmt::format("history {}: case '{}' has no quantity '{}'; {}`mfv history {}` "
                                 "lists its {}",
                                 o.history, case_id, quantity, did_you_mean(quantity, known),
                                 case_id, known.size()));
  MarkdownTable t({"run", "time", "commit", quantity}, {'r', 'l', 'l', 'r'});
  std::vector<double> v;
  for (const auto& p : h.series(case_id, quantity, o.last)) {
    t.add_row({std::to_string(p.run), p.generated_utc, p.commit.substr(0, 12),
               std::isfinite(p.value) ? fmt::format("{:.6g}", p.value) : "not measured"});
    v.push_back(p.value);
  }
  out << t.str() << fmt::format("trend: {}\n", sparkline(v));
  return 0;
}

namespace {
/// A CMake bracket argument that survives any text: as many '=' as it takes for the closing
/// bracket not to occur in it (a case id holding "]==]" would otherwise end the argument).
std::string bracket(const std::string& s) {
  std::string eq = "==";
  while (s.find("]" + eq + "]") != std::string::npos) eq += '=';
  return "[" + eq + "[" + s + "]" + eq + "]";
}
}  // namespace

void command_manifest_ctest(const std::string& manifest_path, const std::string& mfv_executable,
                            const std::string& output) {
  const Manifest m = load_manifest(manifest_path);
  check_output_file(output, "CTest script", written_by_manifest_ctest);
  const std::string manifest_abs = std::filesystem::absolute(manifest_path).string();
  std::string text = fmt::format("# generated by mfv manifest-ctest from {}\n", manifest_abs);
  for (const auto& c : m.cases) {
    if (c.full_only) continue;  // the nightly's tests; --full runs these
    std::vector<std::string> labels = {"regression", c.problem, c.method};
    for (const auto& l : c.labels) labels.push_back(l);
    text += fmt::format("add_test({} {} verify {} --case {} --no-report)\n", bracket(c.id),
                        bracket(mfv_executable), bracket(manifest_abs), bracket(c.id));
    // Idle OpenMP threads sleep: two tests share the 2 cores under ctest -j2, and spinning
    // threads would inflate the CPU seconds the baseline's ratio judges (scripts/main.sh).
    text += fmt::format("set_tests_properties({} PROPERTIES LABELS {} TIMEOUT 900 "
                        "ENVIRONMENT OMP_WAIT_POLICY=passive)\n",
                        bracket(c.id), bracket(fmt::format("{}", fmt::join(labels, ";"))));
  }
  write_file_atomic(output, text);
}

}  // namespace mfv
