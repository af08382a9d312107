/// `mfv verify`: runs a manifest's studies, judges each case against its bands and the
/// baseline (accuracy and headlines), its stability, and its CPU against the baseline scaled
/// by the run's machine factor (verify/timing.hpp), then writes the verdicts, results.json,
/// the history, JUnit, the baseline (on request) and the report.
///
/// A case's failure has a kind, so that the first screen says what broke: accuracy (an error
/// or rate outside its band or worse than the baseline), headline (a headline outside its band
/// or moved from the baseline), stability (blew up, or stayed stable against expect =
/// "unstable"), baseline (resolutions changed, a measurement lost, or no record under
/// --require-baseline), could not run, and timing (only under a timing gate).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <set>

#include <fmt/format.h>

#include "analyses/report_section.hpp"
#include "apps/command_support.hpp"
#include "apps/commands.hpp"
#include "dynamics/external_solver.hpp"
#include "methods/core/clock.hpp"
#include "methods/core/errors.hpp"
#include "methods/core/measurement_error.hpp"
#include "methods/core/petsc_session.hpp"
#include "reports/atomic.hpp"
#include "reports/markdown.hpp"
#include "verify/baseline.hpp"
#include "verify/diff.hpp"
#include "verify/history.hpp"
#include "verify/junit.hpp"
#include "verify/ledger.hpp"
#include "verify/manifest.hpp"
#include "verify/provenance.hpp"
#include "verify/results_json.hpp"
#include "verify/runner.hpp"
#include "verify/timing.hpp"

namespace mfv {

using namespace cli;

namespace {

/// The kinds a case can fail by, in the order the summary lists them.
const std::vector<std::string>& failure_kinds() {
  static const std::vector<std::string> k = {"accuracy", "headline",      "stability",
                                             "baseline", "could not run", "timing"};
  return k;
}

/// The cases `o` selects, in manifest order (ids and globs; full-only cases with --full).
std::vector<const ManifestCase*> select_cases(const Manifest& manifest, const VerifyOptions& o,
                                              std::ostream& progress) {
  std::vector<const ManifestCase*> selected;
  if (o.cases.empty()) {
    for (const auto& mc : manifest.cases)
      if (o.full || !mc.full_only) selected.push_back(&mc);
    return selected;
  }
  // Ids and globs, each case once, in manifest order. A full-only case named by its id
  // without --full is a mistake; one a pattern sweeps up is left out, and said so.
  std::set<const ManifestCase*> chosen;
  int full_only_skipped = 0;
  for (const auto& pattern : o.cases) {
    const auto matched = manifest.select(pattern);
    const bool by_id = matched.size() == 1 && matched.front()->id == pattern;
    for (const ManifestCase* mc : matched) {
      if (mc->full_only && !o.full) {
        if (by_id)
          throw InputError(fmt::format("{}:{}: case '{}' runs only with --full (full_only = "
                                       "true); add --full",
                                       manifest.path.string(), mc->line, mc->id));
        if (!chosen.count(mc)) ++full_only_skipped;
        continue;
      }
      chosen.insert(mc);
    }
  }
  for (const auto& mc : manifest.cases)
    if (chosen.count(&mc)) selected.push_back(&mc);
  if (full_only_skipped > 0)
    progress << fmt::format("{} full-only case(s) the pattern(s) matched are left out; add "
                            "--full to run them\n",
                            full_only_skipped);
  if (selected.empty())
    throw InputError(fmt::format("--case {} selects only full-only cases; add --full",
                                 fmt::join(o.cases, " --case ")));
  return selected;
}

/// What one case's run left: its study or the error, and what the checks found.
struct Outcome {
  const ManifestCase* mc;
  std::optional<StudyResult> study;
  std::string error;
  std::vector<BandViolation> bands;
  std::vector<Drift> drifts;
  std::vector<std::string> stability;  ///< blown up, or stable against expect = "unstable"
  bool new_case = false;               ///< not in the baseline yet
  double seconds = 0;                  ///< wall time of the case
  double cpu_seconds = NAN;            ///< CPU of the whole study (NaN: did not run)
};

/// The verdict of one case, with the kinds it failed by.
struct Judged {
  std::set<std::string> kinds;  ///< failure_kinds() it failed by; empty: PASS
  std::string baseline;         ///< what the baseline column says
  std::string bands;            ///< what the bands column says
  const TimingVerdict* timing = nullptr;
  bool ok() const { return kinds.empty(); }
};

bool is_headline_metric(const std::string& metric) { return metric.rfind("headline", 0) == 0; }

/// "l2 at 81 nodes, h1_rate": the metrics of `drifts` that `pick` selects, at most three.
template <class Pick>
std::string drift_names(const std::vector<Drift>& drifts, Pick pick) {
  std::vector<std::string> names;
  int n = 0;
  for (const auto& d : drifts) {
    if (!pick(d)) continue;
    if (++n <= 3)
      names.push_back(d.nodes > 0 ? fmt::format("{} at {}", d.metric, d.nodes) : d.metric);
  }
  if (n > 3) names.push_back(fmt::format("{} more", n - 3));
  return fmt::format("{}", fmt::join(names, ", "));
}

Judged judge(const Outcome& oc, const VerifyOptions& o, const Manifest& manifest,
             const TimingVerdict* timing, bool timing_gated) {
  Judged j;
  j.timing = timing;
  if (!oc.error.empty()) j.kinds.insert("could not run");
  if (!oc.stability.empty()) j.kinds.insert("stability");
  for (const auto& b : oc.bands) j.kinds.insert(is_headline_metric(b.metric) ? "headline" : "accuracy");
  int worse = 0, better = 0, changed = 0;
  for (const auto& d : oc.drifts) {
    if (d.metric == "resolution") {
      ++changed;
      j.kinds.insert("baseline");
    } else if (d.worse) {
      ++worse;
      j.kinds.insert(d.lost && o.update_baseline ? "baseline"
                     : is_headline_metric(d.metric) ? "headline"
                                                    : "accuracy");
    } else {
      ++better;
    }
  }
  if (oc.new_case && o.require_baseline) j.kinds.insert("baseline");
  if (timing && timing->slower && timing_gated) j.kinds.insert("timing");

  if (manifest.baseline.empty()) {
    j.baseline = "none";
  } else if (oc.mc->full_only) {
    j.baseline = "none (--full only)";
  } else if (o.update_baseline) {
    j.baseline = worse > 0 ? "kept (a measurement was lost)" : "updated";
  } else if (!oc.error.empty()) {
    j.baseline = "not compared (did not run)";
  } else if (oc.new_case) {
    j.baseline = o.require_baseline ? "missing (--require-baseline)"
                                    : "new: record it with --update-baseline";
  } else {
    std::vector<std::string> parts;
    if (changed > 0) parts.push_back("resolutions changed");
    if (worse > 0)
      parts.push_back(fmt::format("{} worse: {}", worse, drift_names(oc.drifts, [](const Drift& d) {
                                    return d.worse && d.metric != "resolution";
                                  })));
    if (better > 0)
      parts.push_back(fmt::format("{} better: {}", better, drift_names(oc.drifts, [](const Drift& d) {
                                    return !d.worse && d.metric != "resolution";
                                  })));
    j.baseline = parts.empty() ? "unchanged" : fmt::format("{}", fmt::join(parts, "; "));
  }
  if (timing && timing->slower)
    j.baseline += fmt::format("; CPU {} the machine factor", fmt_ratio(timing->relative));
  else if (timing && timing->faster)
    j.baseline += fmt::format("; CPU {} faster", fmt_ratio(1 / timing->relative));

  j.bands = !oc.error.empty()       ? "not run"
            : !oc.stability.empty() ? (oc.bands.empty() ? "inside; stability wrong"
                                                        : fmt::format("{} violated; stability wrong",
                                                                      oc.bands.size()))
            : oc.bands.empty()      ? "inside"
                                    : fmt::format("{} violated", oc.bands.size());
  return j;
}

/// "3 accuracy, 1 could not run": how many cases failed by each kind.
std::string kind_counts(const std::map<std::string, int>& counts) {
  std::vector<std::string> parts;
  for (const auto& k : failure_kinds())
    if (const auto it = counts.find(k); it != counts.end() && it->second > 0)
      parts.push_back(fmt::format("{} {}", it->second, k));
  return fmt::format("{}", fmt::join(parts, ", "));
}

}  // namespace

int command_verify(const Catalogue& c, const VerifyOptions& o, std::ostream& out,
                   std::ostream& progress) {
  const Manifest manifest = load_manifest(o.manifest);
  const std::vector<const ManifestCase*> selected = select_cases(manifest, o, progress);
  if (o.list) {
    for (const auto* mc : selected)
      out << fmt::format("{:<48} {:<22} {}{}\n", mc->id, mc->problem, mc->method,
                         mc->full_only ? "  (--full only)" : "");
    out << fmt::format("{} case(s) of {}\n", selected.size(), manifest.path.string());
    return 0;
  }
  if (o.update_baseline && o.require_baseline)
    throw InputError("--update-baseline records the baseline that --require-baseline asks for; "
                     "give one of them");
  if (!o.junit.empty()) check_output_file(o.junit, "JUnit file", is_mfv_junit);

  // Names and parameters are checked up front: a typo fails in a second, not after an hour.
  for (const auto* mc : selected) {
    try {
      CaseSpec spec;
      spec.problem = mc->problem;
      spec.problem_params = mc->problem_params;
      spec.method = mc->method;
      spec.method_params = mc->method_params;
      spec.analysis = mc->analysis;
      resolve_case(c, spec);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}:{}: case '{}': {}", manifest.path.string(), mc->line,
                                   mc->id, e.what()));
    }
  }
  const Baseline baseline =
      manifest.baseline.empty() ? Baseline{} : load_baseline(manifest.baseline);
  if (!baseline.suite.empty() && baseline.suite != manifest.name)
    throw InputError(fmt::format("baseline {} records suite '{}', not this manifest's '{}'; point "
                                 "[suite] baseline at '{}''s own baseline, or record one with "
                                 "--update-baseline into a new file",
                                 manifest.baseline.string(), baseline.suite, manifest.name,
                                 manifest.name));
  if (o.update_baseline && !manifest.baseline.empty())
    check_output_file(manifest.baseline, "baseline", written_by_mfv_verify);
  const std::filesystem::path report_dir =
      o.report.empty() ? std::filesystem::path("runs") / manifest.name
                       : std::filesystem::path(o.report);
  std::unique_ptr<StagedDirectory> staged;
  if (!o.no_report) staged = stage_report(report_dir, o.force, manifest.name);
  // A history or JUnit file inside the report directory would be replaced with it by the
  // next run (and taken by --force): refused before any case.
  const auto inside_report = [&](const std::filesystem::path& f) {
    if (!staged) return false;
    std::error_code ec;
    const auto dir = std::filesystem::weakly_canonical(report_dir, ec);
    const auto p = std::filesystem::weakly_canonical(std::filesystem::absolute(f), ec);
    const auto rel = p.lexically_relative(dir);
    return !ec && !rel.empty() && *rel.begin() != "..";
  };
  if (!o.junit.empty() && inside_report(o.junit))
    throw InputError(fmt::format("--junit '{}' is inside the report directory '{}', which every "
                                 "run replaces; write it beside the report",
                                 o.junit, report_dir.string()));
  // The history file is opened (created, migrated, checked) before the first case runs.
  std::optional<HistoryStore> history;
  if (!o.no_history) {
    std::filesystem::path file = o.history;
    if (file.empty() && staged) {
      // Beside the report, never inside it: "-r runs/x/" names the directory x too.
      const std::filesystem::path target =
          report_dir.has_filename() ? report_dir : report_dir.parent_path();
      file = target.parent_path() / (target.filename().string() + ".history.sqlite");
    }
    if (!file.empty()) {
      if (inside_report(file))
        throw InputError(fmt::format("--history '{}' is inside the report directory '{}', "
                                     "which every run replaces; keep it beside the report (the "
                                     "default is {}.history.sqlite)",
                                     file.string(), report_dir.string(), report_dir.string()));
      history.emplace(file);
      history->check_writable();
    }
  }
  // The run this report replaces, if it was a verification run: the report leads with what
  // changed since it (an unreadable or foreign one is simply not compared).
  std::optional<nlohmann::json> previous;
  if (staged) {
    try {
      if (std::filesystem::exists(report_dir / "results.json"))
        previous = load_run_results(report_dir / "results.json");
    } catch (const InputError&) {
    }
  }
  // The ledger is checked before the first case runs too (its rows name cases and values).
  std::optional<Ledger> ledger;
  if (!manifest.ledger.empty()) ledger = load_ledger(manifest.ledger, manifest, c);
  petsc::checks_done();

  // How fast this machine is: the reference workload after the last case, and before the
  // first in a run long enough for the median rule (the faster of the two, the less
  // disturbed, where both ran: a few hundredths of a second each), and the load around it.
  const bool timing_wanted = !manifest.baseline.empty();
  const MachineLoad load_start = read_machine_load();
  double reference_now =
      timing_wanted && static_cast<int>(selected.size()) >= kMinFactorCases
          ? reference_workload_seconds()
          : INFINITY;

  const double w0 = wall_seconds(), c0 = cpu_seconds();
  std::vector<Outcome> outcomes;
  std::vector<ReportSection> sections;
  Baseline updated = baseline;
  updated.suite = manifest.name;
  const Provenance here = provenance();
  const std::string machine = machine_note(here.cpu, here.cores, here.threads);
  // CPU seconds compare at the same thread counts, scaled by the machine factor; an update
  // records this machine and its reference workload.
  const bool cpu_comparable_here = cpu_comparable(baseline.machine, machine);
  if (o.update_baseline && !o.full) updated.machine = machine;
  const std::string manifest_file = manifest.path.filename().string();

  for (std::size_t k = 0; k < selected.size(); ++k) {
    const ManifestCase& mc = *selected[k];
    Outcome oc{&mc, std::nullopt, "", {}, {}, {}, false, 0, NAN};
    const double case_start = wall_seconds();
    CaseSpec spec;
    spec.problem = mc.problem;
    spec.problem_params = mc.problem_params;
    spec.analysis = mc.analysis;
    spec.method = mc.method;
    spec.method_params = mc.method_params;
    spec.perturbation = mc.perturbation;
    const auto nodes = resolutions(mc, o.full);
    const std::string tag = fmt::format("[{}/{}] {}:", k + 1, selected.size(), mc.id);
    try {
      StudyResult s = run_study(c, spec, nodes, progress_printer(progress, tag));
      s.label = mc.id;
      oc.bands = check_bands(mc, s, manifest_file);
      oc.stability = check_stability(mc, s);
      BaselineCase current = baseline_from_study(s);
      oc.cpu_seconds = current.cpu_seconds;
      const auto it = baseline.cases.find(mc.id);
      if (mc.full_only) {
        // Runs only with --full: the baseline records the nightly, its bands guard it.
      } else if (o.update_baseline) {
        // A number the baseline held that this run did not measure (NaN) is a lost
        // measurement, never a new record: the case fails and keeps its old entry.
        // A headline the run measured as NaN is a value ("not unstable", "not reached"), not
        // a loss; a headline it no longer measures at all is one.
        std::vector<Drift> lost;
        if (it != baseline.cases.end())
          for (const Drift& d : check_drift(mc.id, it->second, current, INFINITY, 0))
            if (d.lost) lost.push_back(d);
        for (Drift& d : lost)
          d.message = fmt::format("{}: {}{}: the baseline holds {:.6g}, this run measured "
                                  "nothing; its baseline entry is kept (fix the run, or remove "
                                  "the entry from {} by hand if the measurement went on purpose)",
                                  mc.id, d.metric, d.nodes > 0 ? fmt::format(" at {} nodes", d.nodes) : "",
                                  d.baseline, manifest.baseline.string());
        if (lost.empty()) {
          if (!o.full) updated.cases[mc.id] = current;
        } else {
          oc.drifts = std::move(lost);
        }
      } else if (!manifest.baseline.empty()) {
        if (it == baseline.cases.end()) {
          oc.new_case = true;
        } else {
          BaselineCase base = it->second;
          if (o.full) {
            // --full runs other resolutions: compare those in both, not the rates.
            std::erase_if(current.resolutions, [&](const BaselineEntry& e) {
              return std::none_of(base.resolutions.begin(), base.resolutions.end(),
                                  [&](const BaselineEntry& b) { return b.nodes == e.nodes; });
            });
            std::erase_if(base.resolutions, [&](const BaselineEntry& e) {
              return std::none_of(current.resolutions.begin(), current.resolutions.end(),
                                  [&](const BaselineEntry& b) { return b.nodes == e.nodes; });
            });
            base.l2_rate = base.h1_rate = current.l2_rate = current.h1_rate = std::nan("");
          }
          oc.drifts = check_drift(mc.id, base, current,
                                  mc.drift_tolerance.value_or(manifest.drift_tolerance),
                                  manifest.drift_floor);
        }
      }
      oc.study = s;
      add_to_sections(c, sections, std::move(s));
    } catch (const std::bad_alloc&) {
      // The case fails with its size named; the other cases still run.
      oc.error = fmt::format("out of memory at resolutions {} (nodes); lower them in the manifest",
                             fmt::join(nodes, ", "));
      progress << fmt::format("{} could not run: {}\n", tag, oc.error);
    } catch (const SingularError& e) {
      oc.error = e.what();
      progress << fmt::format("{} could not run: {}\n", tag, e.what());
    } catch (const MeasurementError& e) {
      oc.error = e.what();
      progress << fmt::format("{} could not measure: {}\n", tag, e.what());
    } catch (const ExternalSolverError& e) {
      oc.error = e.what();
      progress << fmt::format("{} could not run: {}\n", tag, e.what());
    } catch (const ExternalSolverMissing& e) {
      // Not installed here: the case did not run, which a regression run must not pass.
      oc.error = fmt::format("not run: {}", e.what());
      progress << fmt::format("{} not run: {}\n", tag, e.what());
    }
    oc.seconds = wall_seconds() - case_start;
    outcomes.push_back(std::move(oc));
  }
  const double wall = wall_seconds() - w0, cpu = cpu_seconds() - c0;
  reference_now = timing_wanted ? std::min(reference_now, reference_workload_seconds()) : NAN;
  const MachineLoad load_end = read_machine_load();
  const double steal = steal_fraction(load_start, load_end);
  if (o.update_baseline && !o.full) updated.reference_seconds = reference_now;

  // Timing: every case that ran with a baseline CPU time, judged against the baseline scaled
  // by the run's machine factor; apart from accuracy, failing only under a timing gate.
  const bool timing_gated = o.timing_gate || manifest.timing_gate;
  std::vector<CaseTiming> timings;
  if (timing_wanted && !o.full && !o.update_baseline && cpu_comparable_here)
    for (const auto& oc : outcomes)
      if (oc.study && !oc.mc->full_only)
        if (const auto it = baseline.cases.find(oc.mc->id); it != baseline.cases.end())
          timings.push_back({oc.mc->id, it->second.cpu_seconds, oc.cpu_seconds});
  MachineFactor factor;
  if (!timing_wanted) factor.why_unknown = "the manifest names no baseline";
  else if (o.update_baseline) factor.why_unknown = "--update-baseline records the CPU instead";
  else if (o.full) factor.why_unknown = "--full runs other resolutions than the baseline's";
  else if (baseline.machine.empty())
    factor.why_unknown = "the baseline records no CPU times yet (--update-baseline records them)";
  else if (!cpu_comparable_here)
    factor.why_unknown = fmt::format("the baseline was recorded at other thread counts ({}; "
                                     "this run: {})",
                                     baseline.machine, machine);
  else
    factor = machine_factor(timings, reference_now, baseline.reference_seconds);
  const std::vector<TimingVerdict> timing =
      judge_timing(timings, factor, manifest.timing_floor_seconds);
  const std::string timing_line = timing_status(timing, factor, timing_gated);
  auto timing_of = [&](const std::string& id) -> const TimingVerdict* {
    for (const auto& t : timing)
      if (t.id == id) return &t;
    return nullptr;
  };

  // Verdicts.
  int failed = 0, new_cases = 0;
  std::map<std::string, int> failed_by;
  MarkdownTable verdicts({"case", "problem", "method", "nodes", "L2 rate", "H1-seminorm rate",
                          "energy rate", "bands", "baseline", "verdict"},
                         {'l', 'l', 'l', 'l', 'r', 'r', 'r', 'l', 'l', 'l'});
  // The report's copy, unpadded and without the problem and method the case id already names.
  std::string verdicts_md =
      "| case | nodes | L2 rate | H1-seminorm rate | energy rate | bands | baseline | verdict |\n"
      "|:--|:--|--:|--:|--:|:--|:--|:--|\n";
  std::vector<std::string> messages;
  std::vector<std::pair<std::string, std::string>> failures;  ///< case id → its kinds
  std::vector<VerifyCaseJson> case_json;
  JUnitSuite junit;
  for (const auto& oc : outcomes) {
    const Judged jd = judge(oc, o, manifest, timing_of(oc.mc->id), timing_gated);
    const bool ok = jd.ok();
    if (!ok) {
      ++failed;
      for (const auto& k : jd.kinds) ++failed_by[k];
      failures.emplace_back(oc.mc->id, fmt::format("{}", fmt::join(jd.kinds, ", ")));
    }
    if (oc.new_case) ++new_cases;
    std::vector<std::string> nodes;
    for (int n : resolutions(*oc.mc, o.full)) nodes.push_back(std::to_string(n));
    const bool vector_field = oc.study && !oc.study->cases.empty() &&
                              oc.study->cases.front().components > 1;
    const std::string verdict =
        ok ? "PASS" : fmt::format("FAIL ({})", fmt::join(jd.kinds, ", "));
    const std::string l2 = oc.study ? fmt_rate(oc.study->rates.rate("L2")) : "–";
    const std::string h1 = oc.study ? fmt_rate(oc.study->rates.rate("H1-semi")) : "–";
    const std::string en = vector_field ? fmt_rate(oc.study->rates.rate("energy")) : "–";
    verdicts.add_row({oc.mc->id, oc.mc->problem, oc.mc->method,
                      fmt::format("{}", fmt::join(nodes, ",")), l2, h1, en, jd.bands,
                      jd.baseline, verdict});
    verdicts_md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} |\n", oc.mc->id,
                               fmt::join(nodes, ","), l2, h1, en, jd.bands, jd.baseline,
                               ok ? "PASS" : "**" + verdict + "**");
    VerifyCaseJson cj{oc.mc->id, oc.mc->problem, oc.mc->method, resolutions(*oc.mc, o.full),
                      jd.bands, jd.baseline, ok ? "PASS" : "FAIL", {},
                      oc.study ? &*oc.study : nullptr, oc.error};
    cj.failed_kinds.assign(jd.kinds.begin(), jd.kinds.end());
    if (jd.timing) {
      cj.cpu_ratio = jd.timing->ratio;
      cj.cpu_relative = jd.timing->relative;
    }
    auto note = [&](const std::string& m) {
      messages.push_back(m);
      cj.messages.push_back(m);
    };
    if (!oc.error.empty()) {
      messages.push_back(fmt::format("{}: could not run: {}", oc.mc->id, oc.error));
    }
    for (const auto& m : oc.stability) note(m);
    for (const auto& b : oc.bands) note(b.message);
    for (const auto& d : oc.drifts) note(d.message);
    if (oc.new_case)
      note(fmt::format("{}: not in the baseline {}{}; record it with `mfv verify {} "
                       "--update-baseline`",
                       oc.mc->id, manifest.baseline.string(),
                       o.require_baseline ? " (--require-baseline: a failure)" : " (new: not a failure)",
                       o.manifest));
    if (jd.timing && !jd.timing->message.empty()) note(jd.timing->message);

    JUnitCase jc{"mfv." + oc.mc->problem, oc.mc->id, oc.seconds, {},
                 fmt::format("{} with {} at nodes {}: L2 rate {}, bands {}, baseline {}: {}",
                             oc.mc->problem, oc.mc->method, fmt::join(nodes, ","), l2, jd.bands,
                             jd.baseline, verdict)};
    if (!oc.error.empty())
      jc.problems.push_back({JUnitProblem::Kind::error, "could-not-run", oc.error, oc.error});
    for (const auto& m : oc.stability)
      jc.problems.push_back({JUnitProblem::Kind::failure, "stability", m, m});
    for (const auto& b : oc.bands)
      jc.problems.push_back({JUnitProblem::Kind::failure, "band", b.message,
                             fmt::format("{} = {:.6g}, band [{:.6g}, {:.6g}]", b.metric, b.value,
                                         b.band.low, b.band.high)});
    for (const auto& d : oc.drifts) {
      if (d.worse || d.metric == "resolution")
        jc.problems.push_back({JUnitProblem::Kind::failure, "baseline", d.message,
                               d.metric == "resolution"
                                   ? d.message
                                   : fmt::format("{}{}: baseline {:.6g}, now {:.6g} ({:+.1f} %)",
                                                 d.metric,
                                                 d.nodes > 0 ? fmt::format(" at {} nodes", d.nodes)
                                                             : "",
                                                 d.baseline, d.current,
                                                 100 * (d.current - d.baseline) /
                                                     std::max(std::abs(d.baseline), 1e-300))});
      else
        jc.system_out += "\n" + d.message;  // better than the baseline: a note, not a failure
    }
    if (oc.new_case) {
      const std::string m =
          fmt::format("{}: not in the baseline; record it with --update-baseline", oc.mc->id);
      if (o.require_baseline)
        jc.problems.push_back({JUnitProblem::Kind::failure, "baseline", m, m});
      else
        jc.system_out += "\n" + m;
    }
    if (jd.timing && !jd.timing->message.empty()) {
      if (jd.timing->slower && timing_gated)
        jc.problems.push_back({JUnitProblem::Kind::failure, "timing", jd.timing->message,
                               jd.timing->message});
      else
        jc.system_out += "\ntiming: " + jd.timing->message;
    }
    junit.cases.push_back(std::move(jc));
    case_json.push_back(std::move(cj));
  }

  // The summary line: PASS or FAIL, and for a FAIL by which kinds.
  const std::string what =
      manifest.baseline.empty() ? "inside their bands" : "inside their bands and the baseline";
  const std::string summary =
      failed == 0
          ? fmt::format("PASS: all {} case(s) of suite '{}' {}{}", outcomes.size(), manifest.name,
                        what,
                        new_cases > 0 ? fmt::format(" ({} new, not yet in the baseline)", new_cases)
                                      : "")
          : fmt::format("FAIL: {} of {} case(s) of suite '{}' failed: {}", failed,
                        outcomes.size(), manifest.name, kind_counts(failed_by));
  out << verdicts.str();
  for (const auto& m : messages) out << m << "\n";
  out << summary << "\n" << timing_line << "\n";

  // Reproduction, computed from the same run and shown apart from the regression verdict.
  std::vector<LedgerEntry> entries;
  if (ledger) {
    std::map<std::string, CaseOutcome> ran;
    for (const auto& oc : outcomes)
      ran[oc.mc->id] = CaseOutcome{oc.study ? &*oc.study : nullptr, oc.error};
    entries = evaluate_ledger(*ledger, c, manifest, ran);
    out << fmt::format("Ledger ({}): {}\n", ledger->path.string(), verdict_counts_line(entries));
  }
  VerifyTimingJson timing_json{factor.known() ? factor.factor : NAN,
                               factor.rule,
                               factor.median_cases >= kMinFactorCases ? factor.median : NAN,
                               factor.median_cases,
                               factor.reference > 0 ? factor.reference : NAN,
                               reference_now,
                               baseline.reference_seconds,
                               load_start.load_average,
                               load_end.load_average,
                               steal,
                               timing_gated,
                               {},
                               timing_line,
                               factor.why_unknown};
  for (const auto& t : timing)
    if (t.slower) timing_json.slower.push_back(t.id);
  std::map<std::string, int> kinds_json(failed_by.begin(), failed_by.end());
  const std::string results_text = verify_results_json(
      c, run_info(c, "verify", wall, cpu), manifest.name, o.manifest, o.full, case_json,
      ledger ? &*ledger : nullptr, entries, &timing_json, kinds_json);

  // The history: this run appended, then the slow drifts over the last runs (each step
  // inside the tolerance, the whole window not) reported; they do not change the exit code.
  // Parsed once, for the history and the report's diff, and only when one of them reads it.
  const nlohmann::json results_doc =
      history || previous ? nlohmann::json::parse(results_text) : nlohmann::json();
  std::vector<HistoryDrift> creeping;
  long run_id = 0;
  // An append that still fails (checked writable before the first case, so a disk that
  // filled or a writer that held the lock past the timeout) costs the history, never the
  // run: the JUnit file and the report are written first and the failure is named after them.
  std::vector<std::string> late_failures;  // outputs refused at write time, named at the end
  if (history) {
    try {
      run_id = history->append(results_doc);
      creeping = history->drifts(run_id, kHistoryWindow,
                                 manifest.drift_tolerance > 0 ? manifest.drift_tolerance : 0.05);
      out << fmt::format("history: run {} appended to {}{}\n", run_id,
                         history->path().string(),
                         creeping.empty() ? ""
                                          : fmt::format("; {} quantity(ies) crept over the last "
                                                        "{} runs:",
                                                        creeping.size(), kHistoryWindow));
      for (const auto& d : creeping) out << "  " << d.message << "\n";
    } catch (const std::exception& e) {
      late_failures.push_back(fmt::format("not appended to the history: {}", e.what()));
      run_id = 0;
      history.reset();
    }
  }

  if (!o.junit.empty()) {
    // The regression verdicts are the test cases; provenance and the ledger's verdicts (a
    // paper not reproduced is not a failed test) are the suite's properties.
    for (const auto& d : creeping)
      for (auto& jc : junit.cases)
        if (jc.name == d.case_id) jc.system_out += "\nhistory: " + d.message;
    junit.name = manifest.name;
    junit.timestamp = utc_now("%Y-%m-%dT%H:%M:%S");
    junit.seconds = wall;
    const Provenance& prov = here;
    junit.hostname = prov.hostname;
    junit.properties = {
        {"manifest", o.manifest},
        {"full", o.full ? "true" : "false"},
        {"mfv.version", prov.version},
        {"mfv.commit", prov.commit + (prov.dirty ? " (with uncommitted changes)" : "")},
        {"mfv.build", prov.build_type + ", " + prov.compiler},
        {"machine", fmt::format("{} cores, {}", prov.cores, prov.cpu)},
        {"threads", fmt::format("{} (OMP_WAIT_POLICY {})", prov.threads,
                                prov.omp_wait_policy.empty() ? "unset" : prov.omp_wait_policy)},
        {"summary", summary},
        {"timing", timing_line},
    };
    if (ledger) {
      junit.properties.emplace_back("ledger", verdict_counts_line(entries));
      for (const auto& e : entries) {
        const LedgerRow& read = e.read ? *e.read : *e.row;
        junit.properties.emplace_back(
            "ledger:" + e.row->id,
            fmt::format("{}{}{}", e.verdict,
                        e.evidence.empty() || e.evidence == "–" ? "" : "; evidence " + e.evidence,
                        read.cases.empty()
                            ? std::string()
                            : fmt::format("; cases {}", fmt::join(read.cases, ", "))));
      }
    }
    // Checked again now: a file someone created there while the cases ran is theirs, and is
    // kept (the run is not lost: the failure is named after the report).
    try {
      check_output_file(o.junit, "JUnit file", is_mfv_junit);
      write_file_atomic(o.junit, junit_xml(junit));
      out << fmt::format("JUnit: {}\n", o.junit);
    } catch (const InputError& e) {
      late_failures.push_back(fmt::format("JUnit not written: {}", e.what()));
    }
  }

  if (o.update_baseline && !manifest.baseline.empty()) {
    if (o.full) {
      out << "baseline not updated: it records the default resolutions; run without --full\n";
    } else {
      // A baseline beside a manifest in the working directory has no parent to create.
      if (const auto parent = manifest.baseline.parent_path(); !parent.empty())
        std::filesystem::create_directories(parent);
      try {
        check_output_file(manifest.baseline, "baseline", written_by_mfv_verify);
        write_file_atomic(manifest.baseline, baseline_to_toml(updated));
        out << fmt::format("baseline written: {}\n", manifest.baseline.string());
      } catch (const InputError& e) {
        late_failures.push_back(fmt::format("baseline not written: {}", e.what()));
      }
    }
  }

  if (staged) {
    const std::filesystem::path& dir = report_dir;
    std::string head = fmt::format("# mfv verification report: {}\n\n", manifest.name);
    if (!manifest.description.empty()) head += manifest.description + "\n\n";
    // 1. Summary: reproduction and regression apart, so that "no regression" is never read
    // as "the papers are reproduced"; then what built and ran it.
    MarkdownTable summary_table({"", ""}, {'l', 'l'});
    summary_table.add_row({"**reproduction** of the papers (ledger)",
                           ledger ? verdict_counts_line(entries)
                                  : "no ledger: the manifest names none ([suite] ledger)"});
    summary_table.add_row({"**regression** against bands and baseline",
                           failed == 0 ? summary
                                       : summary + " ([what failed](#regression))"});
    summary_table.add_row({"**timing** against the machine factor",
                           timing_line.substr(timing_line.find(": ") + 2)});
    // What changed since the run this report replaces: the first thing a nightly reader needs.
    std::string changes_md;
    if (previous) {
      try {
        const RunDiff d = diff_runs(*previous, results_doc);
        summary_table.add_row(
            {"**changes** since the last run here",
             fmt::format("{} worse, {} better ([Changes](#changes-since-the-last-run))", d.worse(),
                         d.better())});
        changes_md = "## Changes since the last run\n\n" + diff_text(d, true) + "\n";
      } catch (const InputError& e) {
        changes_md = fmt::format("## Changes since the last run\n\nNot compared: {}\n\n", e.what());
      }
    } else {
      summary_table.add_row({"**changes** since the last run here",
                             "no earlier verification run at this report path"});
    }
    if (history) {
      std::string h = fmt::format(
          "\nHistory: `{}` (`mfv history CASE --history {}` prints a quantity over the runs). ",
          history->path().string(), history->path().string());
      if (creeping.empty()) {
        h += fmt::format("No quantity crept the wrong way by more than the drift tolerance over "
                         "the last {} runs.\n\n",
                         kHistoryWindow);
      } else {
        h += fmt::format("Crept the wrong way over the last {} runs, each step inside the "
                         "tolerance:\n\n",
                         kHistoryWindow);
        for (const auto& d : creeping) h += fmt::format("- {}\n", d.message);
        h += "\n";
      }
      if (changes_md.empty()) changes_md = "## Changes since the last run\n\n";
      changes_md += h;
    }
    summary_table.add_row(
        {"build", fmt::format("mfv {}, commit `{}`{}, {} build, {}", here.version,
                              here.commit.substr(0, 12),
                              here.dirty ? " with uncommitted changes" : "", here.build_type,
                              here.compiler)});
    summary_table.add_row(
        {"machine",
         fmt::format("{}; load average {} at the start, {} at the end; steal {}", machine,
                     load_start.load_average >= 0 ? fmt::format("{:.2f}", load_start.load_average)
                                                  : "unknown",
                     load_end.load_average >= 0 ? fmt::format("{:.2f}", load_end.load_average)
                                                : "unknown",
                     std::isfinite(steal) ? fmt::format("{:.1f} %", 100 * steal) : "unknown")});
    if (!c.plugins.empty())
      summary_table.add_row({"plugins", fmt::format("`{}`", fmt::join(c.plugins, "`, `"))});
    summary_table.add_row({"time", fmt::format("wall {}, CPU {} (finished {})", fmt_seconds(wall),
                                               fmt_seconds(cpu), utc_now(kReportTime))});
    summary_table.add_row({"manifest", fmt::format("`{}`{}", o.manifest,
                                                   o.full ? " (`--full` resolutions)" : "")});
    head += "## Summary\n\n" + summary_table.str() +
            "\nRegression PASS means our numbers stayed inside the manifest's bands and the "
            "recorded baseline; it says nothing about the papers. Whether a paper's claim is "
            "reproduced is the ledger's verdict, computed from this run against the tolerance "
            "each row states. Timing is judged apart and fails the run only under a timing "
            "gate.\n\n";
    // What failed, by case, with the kinds and since when (the history's streak of FAILs).
    if (!failures.empty()) {
      head += "### What failed\n\n";
      MarkdownTable ft({"case", "failed by", "first failed"}, {'l', 'l', 'l'});
      for (const auto& [id, kinds] : failures) {
        std::string since = "–";
        if (history)
          if (const auto first = history->failing_since(id, run_id))
            since = first->id == run_id
                        ? "this run"
                        : fmt::format("run {} ({}, commit `{}`)", first->id, first->generated_utc,
                                      first->commit.substr(0, 12));
        ft.add_row({id, kinds, since});
      }
      head += ft.str() + "\n";
    }
    head += changes_md;
    // 2. Contents.
    head += "## Contents\n\n";
    head += "- [Regression](#regression) (every case: [regression.md](regression.md))\n";
    if (ledger) head += "- [Reproduction ledger](#reproduction-ledger) (in full: [ledger.md](ledger.md))\n";
    head += fmt::format("- Problems\n{}\n", kProblemsToc);
    head += o.vtk ? (o.vtk_finest_only ? "VTK fields: each study's finest resolution "
                                         "(`--vtk=all` writes every resolution).\n\n"
                                       : "VTK fields: every resolution.\n\n")
                  : "VTK fields: none written (`mfv verify … --vtk=finest` writes each study's "
                    "finest resolution, `--vtk=all` every resolution, for ParaView).\n\n";
    head += "Machine-readable: [results.json](results.json) (every case, the regression "
            "verdicts and the ledger; schema in docs/results-schema.md)";
    if (ledger) head += ", [ledger.csv](ledger.csv), [ledger.json](ledger.json)";
    head += ".\n\n";
    const std::string legend =
        "Verdicts: **reproduced** (within the row's tolerance), **reproduced under a stated "
        "reading** (the row states the reading), **partly** (within three times the tolerance, "
        "or some of the row's values), **not reproduced** (the gap and the best reason), **not "
        "reached** (the run gave no finite value), **not run** (its case was not selected), "
        "**not yet built** (the problem or check does not exist yet). Ratio = ours / paper. "
        "Each row may try several readings of the paper's text (each quoted); the verdict is "
        "the closest reading's that is not a fitted constant, and names it. Evidence says how "
        "sure ours is: **independent** (a second route agrees), **converged** (refinement "
        "moves it less than the tolerance), **single run**.";
    // 3. The ledger: short rows here, every column (paper, ours, tolerance, reason, reading)
    // on ledger.md.
    std::vector<std::pair<std::string, std::string>> files;
    std::string ledger_md;
    if (ledger) {
      ledger_md = fmt::format(
          "## Reproduction ledger\n\nOne row per claim of the papers (`{}`). {} Every row — "
          "the paper's and our values, the tolerance, the case that measures ours, the reason "
          "for each gap, every reading tried and its checks — is in [ledger.md](ledger.md), by "
          "paper; [ledger.csv](ledger.csv) has them for a spreadsheet.\n\n{}\n",
          ledger->path.filename().string(), legend, ledger_counts_markdown(entries));
      files.emplace_back(
          "ledger.md",
          fmt::format("# Reproduction ledger: {}\n\n[Back to the report](index.md)\n\n{}\n\n"
                      "**{}**\n\n{}\n",
                      manifest.name, legend, verdict_counts_line(entries),
                      ledger_markdown(entries) + ledger_sources_markdown(*ledger, entries)));
    }
    // 4. Regression: the status and what failed here, every case on regression.md.
    const std::string regression_note =
        "Rates are least-squares slopes on the common rule, by norm: L2, H1 seminorm, and the "
        "energy norm (2D problems only). The baseline column says how the case's numbers "
        "compare with the recorded baseline: unchanged, which moved worse or better, new (not "
        "yet recorded) or resolutions changed, and its CPU against the machine factor where "
        "that is far off.";
    head += fmt::format("## Regression\n\n**{}**\n\n**{}**\n\nEvery case with its rates, bands "
                        "and baseline: [regression.md](regression.md).\n\n",
                        summary, timing_line);
    // What the baseline watches, and how this run's CPU was judged against it.
    if (!manifest.baseline.empty() && !o.update_baseline)
      head += fmt::format(
          "The baseline holds every case's errors, rates and headline values (relative drift "
          "tolerance {:g}, a headline move fails until the baseline is updated) and its CPU "
          "seconds. The CPU is judged against the baseline scaled by this run's machine "
          "factor (the median ratio of this run's CPU to the baseline's over its cases, or a "
          "reference workload's ratio for a run of few cases): more than {:g}× the scaled "
          "baseline (and {:g} s beyond it) is a timing regression, which fails the run only under a "
          "timing gate. Baseline recorded on {}; this run on {}{}. Machine factor: {}{}.\n\n",
          manifest.drift_tolerance, kCpuRatio, manifest.timing_floor_seconds,
          baseline.machine.empty() ? std::string("an unnamed machine") : baseline.machine,
          machine,
          same_machine(baseline.machine, machine)
              ? " (the same CPU name and thread counts, which does not make it the same host)"
              : "",
          factor.known() ? fmt::format("{} ({})", fmt_ratio(factor.factor), factor.rule)
                         : "not measured: " + factor.why_unknown,
          factor.known() && factor.reference > 0 && factor.rule != "reference workload"
              ? fmt::format("; the reference workload's ratio {} agrees within {:.0f} %",
                            fmt_ratio(factor.reference),
                            100 * std::abs(factor.reference / factor.factor - 1))
              : "");
    std::string messages_md;
    if (!messages.empty()) {
      messages_md += "Messages:\n\n";
      for (const auto& m : messages) messages_md += fmt::format("- {}\n", m);
      messages_md += "\n";
    }
    head += messages_md;
    head += ledger_md;
    files.emplace_back("regression.md",
                       fmt::format("# Regression verdict per case: {}\n\n[Back to the "
                                   "report](index.md)\n\n**{}**\n\n**{}**\n\n{}\n\n{}\n{}",
                                   manifest.name, summary, timing_line, regression_note,
                                   verdicts_md,
                                   messages_md.empty() ? "" : "Every message, case by case: " + messages_md));
    for (auto& s : sections)
      for (const auto& oc : outcomes)
        if (!oc.error.empty() && oc.mc->problem == s.problem)
          s.failures.push_back(fmt::format("{}: {}", oc.mc->id, oc.error));
    files.emplace_back("results.json", results_text);
    if (ledger) {
      files.emplace_back("ledger.csv", ledger_csv(entries));
      files.emplace_back("ledger.json", ledger_json_text(*ledger, entries));
    }
    write_report(c, *staged, head, std::move(sections), o.vtk, o.vtk_finest_only, files);
    out << fmt::format("report: {}\n", (dir / "index.md").string());
  }
  if (!late_failures.empty())
    throw std::runtime_error(fmt::format("the run finished{} but {}",
                                         staged ? " and its report is written" : "",
                                         fmt::join(late_failures, "; ")));
  return failed == 0 ? 0 : 1;
}

}  // namespace mfv
