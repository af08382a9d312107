#include "verify/ledger.hpp"
#include "verify/ledger_internal.hpp"
#include "reports/uncertainty.hpp"
#include "verify/reference_studies.hpp"

#include <algorithm>
#include <fnmatch.h>

#include <cmath>
#include <map>
#include <set>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "methods/core/errors.hpp"
#include "analyses/report_section.hpp"
#include "analyses/analysis.hpp"
#include "verify/manifest.hpp"

/// The ledger on a run: each reading's values and verdict, its checks and evidence, the
/// reading a row (or its source) is judged under, and the counts.
namespace mfv {

using namespace ledger_internal;

namespace ledger_internal {

std::string fmt_value(double v) {
  if (!std::isfinite(v)) return "–";
  const double a = std::abs(v);
  if (a != 0 && (a < 1e-2 || a >= 1e5)) return fmt::format("{:.4g}", v);
  return fmt::format("{:.5g}", v);
}

/// Values for people (5 digits), or for machines (`exact`: round-trip precision, empty for
/// a missing value).
std::string join_values(const std::vector<double>& v, bool exact) {
  std::vector<std::string> s;
  for (double x : v)
    s.push_back(!exact ? fmt_value(x) : std::isfinite(x) ? fmt::format("{}", x) : "");
  return fmt::format("{}", fmt::join(s, exact ? ";" : ", "));
}

/// A rate of a study under a statistic: the least-squares slope, or a slope between
/// successive resolutions (the finest pair, or the largest of them; NaN pairs are skipped by
/// best_pair and make finest_pair NaN).
double rate_value(const Rates& rates, const std::string& column, RateStatistic statistic) {
  if (statistic == RateStatistic::least_squares) return rates.rate(column);
  const auto& pairs = rates.pairwise_of(column);
  if (pairs.empty()) return NAN;
  if (statistic == RateStatistic::finest_pair) return pairs.back();
  double best = NAN;
  for (double p : pairs)
    if (std::isfinite(p) && !(p <= best)) best = p;
  return best;
}

/// One row's value of a measure in a study: a rate under the row's statistic, or a headline
/// at the finest resolution.
double measure_value(const StudyResult& s, const std::string& measure, RateStatistic statistic) {
  if (measure == "l2_rate") return rate_value(s.rates, kRateL2, statistic);
  if (measure == "h1_rate") return rate_value(s.rates, kRateH1Semi, statistic);
  if (measure == "energy_rate") return rate_value(s.rates, kRateEnergy, statistic);
  if (measure.rfind("headline:", 0) == 0 && !s.cases.empty()) {
    const auto it = s.cases.back().headline.find(measure.substr(9));
    return it == s.cases.back().headline.end() ? NAN : it->second;
  }
  return NAN;
}

/// compare_value, with one-sided rows judged only on the side the claim excludes.
Comparison compare_row(double ours, double paper, const LedgerRow& row) {
  if (row.bound == LedgerRow::Bound::range) {
    // paper is ignored: the interval is the row's [low, high]; ratio and difference are
    // against the nearer end (1 and 0 inside).
    const double lo = row.paper[0], hi = row.paper[1];
    Comparison c = compare_value(ours, ours < lo ? lo : ours > hi ? hi : ours, row.tolerance,
                                 CompareBy::ratio);
    if (c.verdict == kNotReached) return c;
    const double excess = ours < lo ? (lo - ours) / std::abs(lo)
                          : ours > hi ? (ours - hi) / std::abs(hi)
                                      : 0.0;
    c.verdict = excess <= row.tolerance ? kReproduced
                : excess <= 3 * row.tolerance ? kPartly
                                              : kNotReproduced;
    return c;
  }
  Comparison c = compare_value(ours, paper, row.tolerance, row.compare);
  if (row.bound == LedgerRow::Bound::none || c.verdict == kNotReached) return c;
  const double tol = row.tolerance * std::abs(paper);
  const double excess = row.bound == LedgerRow::Bound::at_least ? paper - ours : ours - paper;
  c.verdict = excess <= tol ? kReproduced : excess <= 3 * tol ? kPartly : kNotReproduced;
  return c;
}

/// Combines per-value verdicts: all reproduced → reproduced, none even partly → not
/// reproduced, anything missing → not reached, otherwise partly.
std::string combine(const std::vector<Comparison>& cs) {
  int ok = 0, part = 0, missing = 0;
  for (const auto& c : cs) {
    if (c.verdict == kReproduced) ++ok;
    else if (c.verdict == kPartly) ++part;
    else if (c.verdict == kNotReached) ++missing;
  }
  const int n = static_cast<int>(cs.size());
  if (missing > 0) return kNotReached;
  if (ok == n) return kReproduced;
  if (ok == 0 && part == 0) return kNotReproduced;
  return kPartly;
}

std::string gap_text(const LedgerEntry& e) {
  const auto& row = *e.row;
  std::vector<std::string> parts;
  for (const auto& c : e.compared) {
    if (!std::isfinite(c.difference)) continue;
    parts.push_back(row.compare == CompareBy::ratio && std::isfinite(c.ratio)
                        ? fmt::format("×{:.3g}", c.ratio)
                        : fmt::format("{:+.3g}", c.difference));
  }
  return fmt::format("{}", fmt::join(parts, ", "));
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

/// Whether resolved parameters contain every wanted one (as the problem pages match them).
bool params_match(const Params& resolved, const Params& wanted) {
  for (const auto& [k, v] : wanted.values())
    if (!resolved.has(k) || format_value(resolved.values().at(k)) != format_value(v)) return false;
  return true;
}

/// A published value belongs to a case's problem parameters when each of its own problem
/// parameters is the case's value or the case left it at its default.
bool problem_params_match(const Params& case_params, const Params& wanted) {
  for (const auto& [k, v] : wanted.values())
    if (case_params.has(k) && format_value(case_params.values().at(k)) != format_value(v))
      return false;
  return true;
}

const ManifestCase* find_case(const Manifest& m, const std::string& id) {
  for (const auto& c : m.cases)
    if (c.id == id) return &c;
  return nullptr;
}

}  // namespace ledger_internal

namespace {

/// Rank of a verdict for choosing the closest reading (lower is closer).
int verdict_rank(const std::string& v) {
  static const std::vector<std::string> order = {kReproduced,    kReproducedReading, kPartly,
                                                 kNotReproduced, kNotReached,        kNotRun,
                                                 kNotYetBuilt};
  const auto it = std::find(order.begin(), order.end(), v);
  return static_cast<int>(it - order.begin());
}

}  // namespace

/// A finding may return "reproduced under a stated reading" itself: a compared verdict too,
/// whose checks count as evidence.
bool ledger_internal::compared_verdict(const std::string& v) {
  return v == kReproduced || v == kReproducedReading || v == kPartly || v == kNotReproduced;
}

namespace {

/// The largest distance of ours from the paper over a reading's values (see
/// LedgerReadingOutcome::distance).
double distance_of(const LedgerReadingOutcome& o) {
  const LedgerRow& row = *o.row;
  if (row.kind == LedgerRow::Kind::finding || row.kind == LedgerRow::Kind::open)
    return compared_verdict(o.verdict) ? 0 : INFINITY;
  if (o.compared.empty()) return INFINITY;
  double d = 0;
  for (std::size_t i = 0; i < o.compared.size(); ++i) {
    const Comparison& c = o.compared[i];
    if (!std::isfinite(c.difference)) return INFINITY;
    const double paper = row.paper[i];
    if (row.bound == LedgerRow::Bound::range) {
      const double end = c.ratio > 0 && std::isfinite(c.ratio) ? std::abs(c.difference) /
                                                                     std::max(std::abs(row.paper[0]), 1e-300)
                                                               : INFINITY;
      d = std::max(d, end / row.tolerance);
      continue;
    }
    if (row.bound != LedgerRow::Bound::none) {
      const double excess = row.bound == LedgerRow::Bound::at_least ? -c.difference : c.difference;
      d = std::max(d, std::max(0.0, excess) / (row.tolerance * std::max(std::abs(paper), 1e-300)));
    } else if (row.compare == CompareBy::ratio && std::isfinite(c.ratio) && c.ratio > 0) {
      d = std::max(d, std::abs(std::log(c.ratio)));
    } else {
      d = std::max(d, std::abs(c.difference) / row.tolerance);
    }
  }
  return d;
}

/// The uncertainty of a measure of a study: a rate's from its pairwise rates (each at the
/// geometric mean spacing of its pair: the sequence the asymptotic order is the limit of), a
/// headline's from its values over the resolutions.
Uncertainty measure_uncertainty(const StudyResult& s, const std::string& measure) {
  std::vector<double> hs, vs;
  const char* column = measure == "l2_rate"       ? kRateL2
                       : measure == "h1_rate"     ? kRateH1Semi
                       : measure == "energy_rate" ? kRateEnergy
                                                  : nullptr;
  if (column) {
    const auto& pairs = s.rates.pairwise_of(column);
    for (std::size_t k = 0; k < pairs.size() && k + 1 < s.cases.size(); ++k) {
      hs.push_back(std::sqrt(s.cases[k].h * s.cases[k + 1].h));
      vs.push_back(pairs[k]);
    }
  } else if (measure.rfind("headline:", 0) == 0) {
    for (const auto& c : s.cases) {
      const auto it = c.headline.find(measure.substr(9));
      hs.push_back(c.h);
      vs.push_back(it == c.headline.end() ? NAN : it->second);
    }
  }
  return grid_uncertainty(hs, vs);
}

/// One reading's values and verdict against the paper, before a stated reading is named.
LedgerReadingOutcome measure_reading(const LedgerRow& row, const Registries& catalogue,
                                     const Manifest& manifest,
                                     const std::map<std::string, CaseOutcome>& ran,
                                     const std::string& only_case = "") {
  LedgerReadingOutcome e;
  e.row = &row;
  switch (row.kind) {
    case LedgerRow::Kind::open:
      e.verdict = kNotYetBuilt;
      e.why = fmt::format("the catalogue has no problem '{}' yet", row.problem);
      break;
    case LedgerRow::Kind::published: {
      if (row.cases.empty()) {
        e.verdict = kNotRun;
        e.why = "no case of the suite measures it";
        e.ours.assign(row.paper.size(), NAN);
        break;
      }
      const auto it = ran.find(row.cases[0]);
      if (it == ran.end()) {
        e.verdict = kNotRun;
        e.why = fmt::format("case {} did not run in this invocation", row.cases[0]);
        e.ours.assign(row.paper.size(), NAN);
        break;
      }
      std::vector<std::string> missing;
      bool computed = false;  // whether any case of the study has the quantity at all
      for (std::size_t i = 0; i < row.nodes.size(); ++i) {
        double ours = NAN;
        const double paper = row.bound == LedgerRow::Bound::range ? NAN : row.paper[i];
        if (it->second.study)
          for (const auto& r : it->second.study->cases) {
            computed = computed || row.quantity == "error u" ||
                       row.quantity == "error du/dx" || r.headline.count(row.quantity) > 0;
            if (r.spec.nodes == row.nodes[i]) ours = our_published_value(r, row.quantity);
          }
        if (!std::isfinite(ours)) missing.push_back(std::to_string(row.nodes[i]));
        e.ours.push_back(ours);
        e.compared.push_back(compare_row(ours, paper, row));
        // A value at the paper's own resolution is compared as computed there: its
        // uncertainty is that of the quadrature, step or solver, from a converged check
        // (evaluate_checks), not the particle refinement's distance to the continuum.
        Uncertainty none;
        none.why_none = "a value at the paper's resolution and no converged check of it";
        e.uncertainty.push_back(none);
      }
      e.verdict = combine(e.compared);
      if (!it->second.study)
        e.why = fmt::format("case {} could not run: {}", row.cases[0], it->second.error);
      else if (!computed)
        e.why = fmt::format("case {} computes no '{}'", row.cases[0], row.quantity);
      else if (!missing.empty())
        e.why = fmt::format("no finite value at {} nodes", fmt::join(missing, ", "));
      break;
    }
    case LedgerRow::Kind::measure: {
      double best = NAN;
      const StudyResult* from = nullptr;
      std::vector<std::string> not_run, failed;
      for (const auto& id : row.cases) {
        const auto it = ran.find(id);
        if (it == ran.end()) { not_run.push_back(id); continue; }
        if (!only_case.empty() && id != only_case) continue;
        if (!it->second.study) { failed.push_back(id); continue; }
        const double v = measure_value(*it->second.study, row.measure, row.statistic);
        if (std::isfinite(v) && !(v <= best)) {
          best = v;
          from = &*it->second.study;
          e.from_case = id;
        }
      }
      if (from) e.uncertainty = {measure_uncertainty(*from, row.measure)};
      if (!not_run.empty()) {
        e.verdict = kNotRun;
        e.why = not_run.size() == 1 ? fmt::format("case {} did not run in this invocation", not_run[0])
                                    : fmt::format("{} of its cases did not run in this invocation", not_run.size());
        e.ours = {NAN};
        break;
      }
      e.ours = {best};
      e.compared = {compare_row(best, row.paper[0], row)};
      e.verdict = e.compared[0].verdict;
      if (!failed.empty()) e.why = fmt::format("could not run: {}", fmt::join(failed, ", "));
      break;
    }
    case LedgerRow::Kind::finding: {
      if (!catalogue.problems.contains(row.problem)) {
        e.verdict = kNotYetBuilt;
        e.why = fmt::format("the catalogue has no problem '{}' yet", row.problem);
        break;
      }
      const auto problem = create_problem(catalogue, row.problem, row.problem_params);
      const auto findings = problem->findings();
      const auto f = std::find_if(findings.begin(), findings.end(),
                                  [&](const Finding& x) { return x.id == row.finding; });
      if (f == findings.end()) {
        e.verdict = kNotYetBuilt;
        e.why = fmt::format("{} has no finding '{}' yet", row.problem, row.finding);
        break;
      }
      e.criterion = f->criterion;
      std::vector<StudyResult> studies;
      // An independent implementation's studies (checked readable when the ledger loaded).
      if (!row.reference.empty()) {
        const Verdict v = f->check(
            summarize(catalogue, load_reference_studies(row.reference, row.reference_studies)));
        e.ours_text = fmt::format("independent ({}): {}", row.reference.filename().string(), v.ours);
        e.verdict = v.status == "not run" ? std::string(kNotRun) : v.status;
        if (e.verdict == kNotRun && e.why.empty()) e.why = v.ours;
        break;
      }
      // Named cases: the finding is judged on those studies only (a paper's own method or
      // particle counts); each must have run.
      if (!row.cases.empty()) {
        std::vector<std::string> not_run;
        for (const auto& id : row.cases) {
          const auto it = ran.find(id);
          if (it == ran.end()) not_run.push_back(id);
          else if (it->second.study) studies.push_back(*it->second.study);
        }
        if (!not_run.empty()) {
          e.verdict = kNotRun;
          e.why = fmt::format("case{} {} did not run in this invocation",
                              not_run.size() == 1 ? "" : "s", fmt::join(not_run, ", "));
          break;
        }
      }
      for (const auto& mc : manifest.cases) {
        if (!row.cases.empty()) break;
        if (mc.problem != row.problem) continue;
        if (!params_match(resolved_case_params(catalogue, mc.problem, mc.problem_params),
                          row.problem_params))
          continue;
        const auto it = ran.find(mc.id);
        if (it != ran.end() && it->second.study) studies.push_back(*it->second.study);
      }
      if (studies.empty()) {
        e.verdict = kNotRun;
        e.why = fmt::format("no study of {} ran in this invocation", row.problem);
        break;
      }
      const Verdict v = f->check(summarize(catalogue, studies));
      e.ours_text = v.ours;
      e.numbers = v.numbers;
      e.verdict = v.status == "not run" ? std::string(kNotRun) : v.status;
      if (std::find(ledger_verdicts().begin(), ledger_verdicts().end(), e.verdict) ==
          ledger_verdicts().end())
        throw std::logic_error(fmt::format("finding {}:{} returned the verdict '{}'",
                                           row.problem, row.finding, v.status));
      if (e.verdict == kNotRun && e.why.empty()) e.why = v.ours;
      break;
    }
  }
  e.distance = distance_of(e);
  return e;
}

/// Whether a check's second computation agrees with the reading it checks.
bool check_agrees(const LedgerCheckOutcome& c, const LedgerReadingOutcome& o) {
  const LedgerRow& row = *o.row;
  if (row.kind == LedgerRow::Kind::finding)
    return compared_verdict(o.verdict) && c.verdict == o.verdict;
  if (c.values.size() != o.ours.size() || o.ours.empty()) return false;
  for (std::size_t i = 0; i < o.ours.size(); ++i) {
    const double a = o.ours[i], b = c.values[i];
    if (!std::isfinite(a) || !std::isfinite(b)) return false;
    const bool relative = row.compare == CompareBy::ratio || row.bound != LedgerRow::Bound::none;
    const double gap = relative ? (a != 0 ? std::abs(b / a - 1) : std::abs(b)) : std::abs(b - a);
    if (!(gap <= row.tolerance)) return false;
  }
  return true;
}

}  // namespace

namespace ledger_internal {

/// "dam-break/sph-eulerian (eulerian): front speed" as its study label, its frame part and
/// what it is ("dam-break/sph-eulerian", " (eulerian)", "front speed").
struct NumberName {
  std::string label, frame, what;
};
static NumberName split_number_name(const std::string& name) {
  const auto colon = name.find(": ");
  if (colon == std::string::npos) return {name, "", ""};
  std::string left = name.substr(0, colon), frame;
  if (const auto paren = left.rfind(" ("); paren != std::string::npos && left.back() == ')') {
    frame = left.substr(paren);
    left.resize(paren);
  }
  return {left, frame, name.substr(colon + 2)};
}

/// The same number of the refined study in a converged check's numbers: the same quantity
/// and frame, of a case whose label is ours with a suffix ("dam-break/sph-eulerian-dt" for
/// "dam-break/sph-eulerian"), the shortest such label when several (the check of
/// "…-wall-particles" is "…-wall-particles-dt", not ours); an exact name first.
static const FindingNumber* refined_counterpart(const FindingNumber& n,
                                         const std::vector<FindingNumber>& theirs) {
  for (const auto& x : theirs)
    if (x.name == n.name) return &x;
  const NumberName ours = split_number_name(n.name);
  if (ours.what.empty()) return nullptr;
  const FindingNumber* best = nullptr;
  std::size_t best_len = std::string::npos;
  for (const auto& x : theirs) {
    const NumberName t = split_number_name(x.name);
    if (t.what != ours.what || t.frame != ours.frame) continue;
    if (t.label.rfind(ours.label + "-", 0) != 0) continue;
    if (t.label.size() < best_len) best = &x, best_len = t.label.size();
  }
  return best;
}

/// A finding's uncertainty per number its verdict rests on: from the number's own levels
/// (three or more: the GCI; two: with its formal order, F_s = 3), or, a number read at one
/// resolution, from the same number in the first converged check that has it: two levels,
/// F_s = 3, the check's refinement and order, U = 3 |ours − check| r^p / (r^p − 1).
void finding_uncertainty(LedgerReadingOutcome& o) {
  o.uncertainty.clear();
  o.uncertainty_of.clear();
  for (const FindingNumber& n : o.numbers) {
    int finite = 0;
    for (std::size_t i = 0; i < n.values.size() && i < n.h.size(); ++i)
      finite += std::isfinite(n.values[i]) && std::isfinite(n.h[i]);
    Uncertainty u;
    if (finite >= 2) {
      u = grid_uncertainty(n.h, n.values, n.order);
      if (!u.known() && u.why_none.empty())
        u.why_none = finite == 2 ? "two levels and no formal order" : "no estimate";
    } else {
      const double ours = n.values.empty() ? NAN : n.values.back();
      for (const auto& c : o.checks) {
        if (c.check->kind != LedgerCheck::Kind::converged) continue;
        const FindingNumber* m = refined_counterpart(n, c.numbers);
        if (!m || m->values.empty() || !std::isfinite(m->values.back()) || !std::isfinite(ours))
          continue;
        const double rp = std::pow(c.check->refinement, c.check->order);
        u.levels = 2;
        u.value = ours;
        u.order = c.check->order;
        u.assumed_order = true;
        u.absolute = 3 * std::abs(ours - m->values.back()) * rp / (rp - 1);
        u.gci = ours != 0 ? u.absolute / std::abs(ours) : NAN;
        u.cls = ConvergenceClass::two_levels;
        u.method = fmt::format("GCI, 2 levels, F_s = 3 (against {})", c.check->route);
        break;
      }
      if (!u.known())
        u.why_none = std::isfinite(ours) ? "one resolution and no converged check of this number"
                                         : "not measured";
    }
    o.uncertainty.push_back(u);
    o.uncertainty_of.push_back(n.name);
  }
}

}  // namespace ledger_internal

namespace {

void evaluate_checks(LedgerReadingOutcome& o, const std::vector<LedgerCheck>& checks,
                     const Registries& catalogue, const Manifest& manifest,
                     const std::map<std::string, CaseOutcome>& ran) {
  // A kind of evidence holds when a check of that kind agrees and none that ran disagrees:
  // "converged" means the finer runs moved ours less than the tolerance, every one of them
  // (issue 43), not that one of several did.
  bool independent = false, converged = false, independent_veto = false, converged_veto = false;
  for (const auto& check : checks) {
    const LedgerReadingOutcome m = measure_reading(*check.row, catalogue, manifest, ran);
    LedgerCheckOutcome c;
    c.check = &check;
    c.values = m.ours;
    c.ours_text = m.ours_text.empty() ? m.why : m.ours_text;
    c.numbers = m.numbers;
    c.verdict = m.verdict;
    c.agrees = check_agrees(c, o);
    const bool ran_check = compared_verdict(m.verdict) || m.verdict == kNotReached;
    const bool is_independent = check.kind == LedgerCheck::Kind::independent;
    if (c.agrees) (is_independent ? independent : converged) = true;
    else if (ran_check) (is_independent ? independent_veto : converged_veto) = true;
    o.checks.push_back(std::move(c));
  }
  independent = independent && !independent_veto;
  converged = converged && !converged_veto;
  // A value of one resolution: its uncertainty from the first converged check that ran, two
  // levels (F_s = 3): U = 3 |ours − check| r^p / (r^p − 1), the coarse level's GCI.
  const LedgerRow& row = *o.row;
  if (row.kind == LedgerRow::Kind::published || row.kind == LedgerRow::Kind::measure) {
    o.uncertainty.resize(o.ours.size());
    for (std::size_t i = 0; i < o.ours.size(); ++i) {
      if (o.uncertainty[i].levels >= 2 || !std::isfinite(o.ours[i])) continue;
      if (row.kind == LedgerRow::Kind::published) o.uncertainty[i] = Uncertainty{};
      for (const auto& c : o.checks) {
        if (c.check->kind != LedgerCheck::Kind::converged || c.values.size() != o.ours.size() ||
            !std::isfinite(c.values[i]))
          continue;
        const double rp = std::pow(c.check->refinement, c.check->order);
        Uncertainty u = grid_uncertainty({c.check->refinement, 1.0}, {o.ours[i], c.values[i]},
                                         c.check->order);
        // grid_uncertainty estimates the finer level's; ours is the coarser one.
        u.value = o.ours[i];
        u.absolute = 3 * std::abs(o.ours[i] - c.values[i]) * rp / (rp - 1);
        u.gci = o.ours[i] != 0 ? u.absolute / std::abs(o.ours[i]) : NAN;
        o.uncertainty[i] = u;
        break;
      }
      // No converged check: the difference from an independent route that agrees (a closed
      // form, a second solver) is how far ours is known.
      if (!o.uncertainty[i].known())
        for (const auto& c : o.checks)
          if (c.check->kind == LedgerCheck::Kind::independent && c.agrees &&
              c.values.size() == o.ours.size() && std::isfinite(c.values[i])) {
            Uncertainty u;
            u.levels = 2;
            u.value = o.ours[i];
            u.absolute = std::abs(o.ours[i] - c.values[i]);
            u.gci = o.ours[i] != 0 ? u.absolute / std::abs(o.ours[i]) : NAN;
            u.cls = ConvergenceClass::two_levels;
            u.method = "difference from an independent route";
            o.uncertainty[i] = u;
            break;
          }
      if (o.uncertainty[i].levels < 2 && o.uncertainty[i].why_none.empty())
        o.uncertainty[i].why_none = row.kind == LedgerRow::Kind::published
                                        ? "a value at the paper's resolution and no converged "
                                          "check of it"
                                        : "one resolution and no converged check of this value";
    }
    o.paper_inside.assign(o.ours.size(), false);
    if (row.bound == LedgerRow::Bound::range) {
      // The interval, widened by U and the tolerance, contains ours.
      if (!o.ours.empty() && o.uncertainty[0].known()) {
        const double u = o.uncertainty[0].absolute, x = o.ours[0];
        o.paper_inside[0] = x + u >= row.paper[0] * (1 - row.tolerance) &&
                            x - u <= row.paper[1] * (1 + row.tolerance);
      }
    } else
    for (std::size_t i = 0; i < o.ours.size() && i < row.paper.size(); ++i)
      o.paper_inside[i] = within_uncertainty(o.ours[i], o.uncertainty[i], row.paper[i],
                                             row.tolerance, row.compare == CompareBy::ratio ||
                                                                row.bound != LedgerRow::Bound::none);
  } else if (row.kind == LedgerRow::Kind::finding && !o.numbers.empty()) {
    finding_uncertainty(o);
  } else {
    Uncertainty none;
    none.why_none = row.kind == LedgerRow::Kind::finding
                        ? "a finding whose check names no number (its numbers are in ours)"
                        : "an open row";
    o.uncertainty = {none};
  }
  // A reproduction that a finer run does not confirm is not counted as one: the value has not
  // converged (issue 43). It stays "partly", the disagreeing check named.
  if (converged_veto && (o.verdict == kReproduced || o.verdict == kReproducedReading)) {
    std::vector<std::string> routes;
    for (const auto& c : o.checks)
      if (c.check->kind == LedgerCheck::Kind::converged && !c.agrees &&
          (compared_verdict(c.verdict) || c.verdict == kNotReached))
        routes.push_back(fmt::format("{} gives {}", c.check->route, c.verdict));
    o.verdict = kPartly;
    o.why = fmt::format("reproduced here, not under refinement: {}", fmt::join(routes, "; "));
  }
  const bool ran_at_all = compared_verdict(o.verdict) || o.verdict == kNotReached;
  o.evidence = !ran_at_all  ? "–"
               : independent ? kEvidenceIndependent
               : converged   ? kEvidenceConverged
                             : kEvidenceSingle;
}

}  // namespace

std::string LedgerReadingOutcome::name() const {
  if (reading) return reading->name;
  return row->reading.empty() ? std::string("as printed") : row->reading;
}

std::vector<LedgerEntry> evaluate_ledger(const Ledger& ledger, const Registries& catalogue,
                                         const Manifest& manifest,
                                         const std::map<std::string, CaseOutcome>& ran) {
  std::vector<LedgerEntry> out;
  std::map<std::string, const LedgerSource*> source_of;
  for (const auto& src : ledger.sources)
    for (const auto& id : src.rows) source_of[id] = &src;
  // Per measure row and reading name ("" its own), the case its value came from: what a row
  // that follows it reads its measure on.
  std::map<std::string, std::map<std::string, std::string>> case_of;
  for (const auto& row : ledger.rows) {
    LedgerEntry e;
    e.row = &row;
    if (const auto s = source_of.find(row.id); s != source_of.end()) e.source = s->second;
    auto followed = [&](const std::string& reading) -> std::string {
      if (row.follow.empty()) return "";
      const auto& m = case_of[row.follow];
      const auto it = m.find(reading);
      // A reading the followed row does not try: its own reading's case.
      const std::string c = it != m.end() ? it->second : m.count("") ? m.at("") : "";
      return c.empty() ? std::string("\x01none") : c;  // nothing to follow: nothing read
    };
    e.readings.push_back(measure_reading(row, catalogue, manifest, ran, followed("")));
    case_of[row.id][""] = e.readings.back().from_case;
    evaluate_checks(e.readings.back(), row.checks, catalogue, manifest, ran);
    for (const auto& t : row.tries) {
      e.readings.push_back(measure_reading(*t.row, catalogue, manifest, ran, followed(t.name)));
      case_of[row.id][t.name] = e.readings.back().from_case;
      e.readings.back().reading = &t;
      evaluate_checks(e.readings.back(), t.checks, catalogue, manifest, ran);
    }
    // In a source: the source's one reading, chosen from the text before comparing.
    // Otherwise the closest counted reading: best verdict, then smallest distance; the row's
    // own reading wins a tie (it comes first).
    if (e.source && !e.source->reading.empty())
      for (std::size_t i = 1; i < e.readings.size(); ++i)
        if (e.readings[i].reading->name == e.source->reading) e.chosen = i;
    for (std::size_t i = 1; i < e.readings.size() && !e.source; ++i) {
      const auto& a = e.readings[i];
      const auto& b = e.readings[e.chosen];
      if (a.reading->fitted) continue;
      const int ra = verdict_rank(a.verdict), rb = verdict_rank(b.verdict);
      if (ra < rb || (ra == rb && compared_verdict(a.verdict) && a.distance < b.distance))
        e.chosen = i;
    }
    const LedgerReadingOutcome& c = e.readings[e.chosen];
    e.read = c.row;
    e.ours = c.ours;
    e.compared = c.compared;
    e.ours_text = c.ours_text;
    e.criterion = c.criterion;
    e.verdict = c.verdict;
    e.why = c.why;
    e.evidence = c.evidence;
    e.reading = c.name();
    const bool stated = c.reading != nullptr || !row.reading.empty();
    if (e.verdict == kReproduced && stated) e.verdict = kReproducedReading;
    if (e.verdict != kReproduced && e.verdict != kReproducedReading &&
        e.verdict != kNotYetBuilt && e.verdict != kNotRun) {
      std::vector<std::string> parts;
      if (const std::string gap = gap_text(e); !gap.empty()) parts.push_back("gap " + gap);
      if (e.source)
        parts.push_back(fmt::format("one reading for {}: {}", e.source->name, e.reading));
      else if (c.reading)
        parts.push_back("closest reading: " + c.reading->name);
      if (!e.why.empty()) parts.push_back(e.why);
      if (!row.reason.empty()) parts.push_back(row.reason);
      e.why = fmt::format("{}", fmt::join(parts, "; "));
    } else if (e.verdict == kReproducedReading) {
      e.why = e.source ? fmt::format("one reading for {}: {}", e.source->name, e.reading)
                       : "reading: " + e.reading;
    }
    out.push_back(std::move(e));
  }
  return out;
}

std::map<std::string, int> count_verdicts(const std::vector<LedgerEntry>& entries,
                                          LedgerRow::Role role) {
  std::map<std::string, int> n;
  for (const auto& v : ledger_verdicts()) n[v] = 0;
  for (const auto& e : entries)
    if (e.row->role == role) ++n[e.verdict];
  return n;
}

std::string verdict_counts_line(const std::vector<LedgerEntry>& entries) {
  auto line = [&](LedgerRow::Role role, int& total) {
    const auto n = count_verdicts(entries, role);
    std::vector<std::string> parts;
    total = 0;
    for (const auto& v : ledger_verdicts()) {
      total += n.at(v);
      if (n.at(v) > 0) parts.push_back(fmt::format("{} {}", n.at(v), v));
    }
    return fmt::format("{}", fmt::join(parts, ", "));
  };
  int claims = 0, costs = 0, checks = 0;
  const std::string c = line(LedgerRow::Role::claim, claims);
  const std::string t = line(LedgerRow::Role::cost, costs);
  const std::string k = line(LedgerRow::Role::check, checks);
  return fmt::format("{} of {} claims{}{}", c, claims,
                     costs > 0 ? fmt::format("; claims about CPU time (this machine's, apart): "
                                             "{} of {}",
                                             t, costs)
                               : "",
                     checks > 0 ? fmt::format("; our own checks: {} of {}", k, checks) : "");
}

}  // namespace mfv
