#include "verify/ledger.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "methods/core/errors.hpp"
#include "analyses/report_section.hpp"
#include "analyses/analysis.hpp"
#include "verify/manifest.hpp"

namespace mfv {

namespace {

constexpr const char* kFormatHint = "see the format at the top of verify/ledger.hpp";

int line_of(const toml::node& n) { return static_cast<int>(n.source().begin.line); }

/// "<file>:<line>: <what>; <fix>" as an InputError (exit 2).
class Reporter {
 public:
  explicit Reporter(std::string file) : file_(std::move(file)) {}
  [[noreturn]] void fail(int line, const std::string& what, const std::string& fix) const {
    throw InputError(fmt::format("{}:{}: {}; {}", file_, line, what, fix));
  }

 private:
  std::string file_;
};

std::string get_string(const Reporter& r, const toml::table& t, const std::string& key,
                       bool required, int row_line) {
  const toml::node* n = t.get(key);
  if (!n) {
    if (required)
      r.fail(row_line, fmt::format("the row has no '{}'", key),
             fmt::format("add {} = \"...\" ({})", key, kFormatHint));
    return {};
  }
  const auto* s = n->as_string();
  if (!s || s->get().empty())
    r.fail(line_of(*n), fmt::format("'{}' must be a non-empty string", key),
           fmt::format("write {} = \"...\"", key));
  return s->get();
}

std::optional<double> number_of(const toml::node& n) {
  if (auto i = n.as_integer()) return static_cast<double>(i->get());
  if (auto f = n.as_floating_point()) return f->get();
  return std::nullopt;
}

Params get_params(const Reporter& r, const toml::table& t, const std::string& key) {
  const toml::node* n = t.get(key);
  if (!n) return {};
  const auto* tt = n->as_table();
  if (!tt)
    r.fail(line_of(*n), fmt::format("'{}' must be a table", key),
           fmt::format("write {} = {{ name = value, ... }}", key));
  Params p;
  for (const auto& [k, v] : *tt) {
    const std::string name(k.str());
    if (auto d = number_of(v)) p.set(name, *d);
    else if (auto s = v.as_string()) p.set(name, ParamValue{s->get()});
    else if (auto b = v.as_boolean()) p.set(name, b->get() ? "true" : "false");
    else r.fail(line_of(v), fmt::format("parameter '{}' in '{}' is not a number, string or boolean", name, key),
                "write numbers, strings or booleans");
  }
  return p;
}

std::vector<std::string> get_strings(const Reporter& r, const toml::node& n,
                                     const std::string& key) {
  std::vector<std::string> out;
  const auto* a = n.as_array();
  if (!a || a->empty())
    r.fail(line_of(n), fmt::format("'{}' must be a non-empty array of strings", key),
           fmt::format("write {} = [\"...\"]", key));
  for (const auto& e : *a) {
    const auto* s = e.as_string();
    if (!s) r.fail(line_of(n), fmt::format("'{}' must hold strings", key), "quote each entry");
    out.push_back(s->get());
  }
  return out;
}

std::vector<double> get_numbers(const Reporter& r, const toml::node& n, const std::string& key) {
  std::vector<double> out;
  const auto* a = n.as_array();
  if (!a || a->empty())
    r.fail(line_of(n), fmt::format("'{}' must be a non-empty array of numbers", key),
           fmt::format("write {} = [1.0, 2.0]", key));
  for (const auto& e : *a) {
    const auto v = number_of(e);
    if (!v || !std::isfinite(*v))
      r.fail(line_of(n), fmt::format("'{}' must hold finite numbers", key),
             "write the paper's printed values");
    out.push_back(*v);
  }
  return out;
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

/// The published values a row names: at least one per node count with the row's value (two
/// sources may print the same number), and the row's tolerance (throws otherwise).
void check_published(const Reporter& r, const LedgerRow& row, const Registries& catalogue) {
  const auto problem = create_problem(catalogue, row.problem, row.problem_params);
  const Params resolved = catalogue.methods.resolve(row.method, row.method_params);
  // Resolved, so that a case leaving dim at its default 1 does not match dim = 2's values.
  const Params problem_resolved = resolved_case_params(catalogue, row.problem, row.problem_params);
  const auto all = problem->published();
  for (std::size_t i = 0; i < row.nodes.size(); ++i) {
    std::vector<const PublishedValue*> found;
    for (const auto& pv : all)
      if (pv.source == row.published_source && pv.quantity == row.quantity &&
          pv.method == row.method && pv.nodes == row.nodes[i] &&
          params_match(resolved, pv.method_params) &&
          problem_params_match(problem_resolved, pv.problem_params))
        found.push_back(&pv);
    std::erase_if(found, [&](const PublishedValue* pv) { return pv->value != row.paper[i]; });
    if (found.empty())
      r.fail(row.line,
             fmt::format("row '{}': {} publishes no '{}' from '{}' for {} at {} nodes with the "
                         "value {}",
                         row.id, row.problem, row.quantity, row.published_source, row.method,
                         row.nodes[i], row.paper[i]),
             "restate the problem's PublishedValue exactly (source, quantity, nodes, value), or "
             "fix the problem's published()");
    if (found.front()->tolerance != row.tolerance)
      r.fail(row.line,
             fmt::format("row '{}': tolerance {} differs from the problem's {} for {} at {} nodes",
                         row.id, row.tolerance, found.front()->tolerance, row.quantity,
                         row.nodes[i]),
             "state the PublishedValue's tolerance");
  }
}

std::string fmt_value(double v) {
  if (!std::isfinite(v)) return "–";
  const double a = std::abs(v);
  if (a != 0 && (a < 1e-2 || a >= 1e5)) return fmt::format("{:.4g}", v);
  return fmt::format("{:.5g}", v);
}

/// Values for people (5 digits), or for machines (`exact`: round-trip precision, empty for
/// a missing value).
std::string join_values(const std::vector<double>& v, bool exact = false) {
  std::vector<std::string> s;
  for (double x : v)
    s.push_back(!exact ? fmt_value(x) : std::isfinite(x) ? fmt::format("{}", x) : "");
  return fmt::format("{}", fmt::join(s, exact ? ";" : ", "));
}

/// One row's value of a measure in a study: a least-squares rate or a headline at the finest.
double measure_value(const StudyResult& s, const std::string& measure) {
  if (measure == "l2_rate") return s.rates.rate("L2");
  if (measure == "h1_rate") return s.rates.rate("H1-semi");
  if (measure == "energy_rate") return s.rates.rate("energy");
  if (measure.rfind("headline:", 0) == 0 && !s.cases.empty()) {
    const auto it = s.cases.back().headline.find(measure.substr(9));
    return it == s.cases.back().headline.end() ? NAN : it->second;
  }
  return NAN;
}

/// compare_value, with one-sided rows judged only on the side the claim excludes.
Comparison compare_row(double ours, double paper, const LedgerRow& row) {
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

}  // namespace

const std::vector<std::string>& ledger_verdicts() {
  static const std::vector<std::string> v = {kReproduced, kReproducedReading, kPartly,
                                             kNotReproduced, kNotReached, kNotRun, kNotYetBuilt};
  return v;
}

double our_published_value(const CaseResult& r, const std::string& quantity) {
  if (quantity == "error u") return r.errors.l2_rel;
  if (quantity == "error du/dx") return r.errors.h1_semi_rel;
  const auto it = r.headline.find(quantity);
  return it == r.headline.end() ? NAN : it->second;
}

Ledger load_ledger(const std::filesystem::path& path, const Manifest& manifest,
                   const Registries& catalogue) {
  const Reporter r(path.string());
  const std::string text = detail::read_text_file(path, "ledger", "check the manifest's "
                                                  "[suite] ledger = \"...\" path");
  toml::table doc;
  try {
    doc = toml::parse(text, path.string());
  } catch (const toml::parse_error& e) {
    r.fail(static_cast<int>(e.source().begin.line), std::string(e.description()),
           "fix the TOML syntax (" + std::string(kFormatHint) + ")");
  }
  static const std::vector<std::string> kKeys = {
      "id", "source", "claim", "reading", "reason", "case", "cases", "problem", "problem_params",
      "method", "method_params", "published", "quantity", "nodes", "paper", "tolerance",
      "compare", "measure", "finding"};
  for (const auto& [k, v] : doc)
    if (k.str() != "row")
      r.fail(line_of(v), fmt::format("unknown top-level key '{}'", k.str()),
             "the ledger holds only [[row]] tables");
  const toml::array* rows = doc["row"].as_array();
  if (!rows || rows->empty())
    r.fail(1, "the ledger has no [[row]]", "add one [[row]] per claim of the papers");

  Ledger ledger;
  ledger.path = path;
  std::set<std::string> ids;
  for (const auto& node : *rows) {
    const auto* t = node.as_table();
    if (!t) r.fail(line_of(node), "a row is not a table", "write each row under [[row]]");
    LedgerRow row;
    row.line = line_of(node);
    for (const auto& [k, v] : *t)
      if (std::find(kKeys.begin(), kKeys.end(), std::string(k.str())) == kKeys.end())
        r.fail(line_of(v), fmt::format("unknown key '{}' in a row", k.str()),
               fmt::format("valid keys: {}", fmt::join(kKeys, ", ")));
    row.id = get_string(r, *t, "id", true, row.line);
    if (!ids.insert(row.id).second)
      r.fail(row.line, fmt::format("duplicate row id '{}'", row.id), "give each row its own id");
    row.source = get_string(r, *t, "source", true, row.line);
    row.claim = get_string(r, *t, "claim", true, row.line);
    row.reading = get_string(r, *t, "reading", false, row.line);
    row.reason = get_string(r, *t, "reason", false, row.line);
    row.problem_params = get_params(r, *t, "problem_params");
    row.method_params = get_params(r, *t, "method_params");
    row.problem = get_string(r, *t, "problem", false, row.line);
    row.method = get_string(r, *t, "method", false, row.line);
    row.published_source = get_string(r, *t, "published", false, row.line);
    row.quantity = get_string(r, *t, "quantity", false, row.line);
    row.measure = get_string(r, *t, "measure", false, row.line);
    const std::string finding = get_string(r, *t, "finding", false, row.line);
    if (t->get("case")) row.cases = {get_string(r, *t, "case", true, row.line)};
    if (const auto* c = t->get("cases")) {
      if (!row.cases.empty())
        r.fail(line_of(*c), "a row has both 'case' and 'cases'", "keep one of them");
      row.cases = get_strings(r, *c, "cases");
    }
    if (const auto* p = t->get("paper")) row.paper = get_numbers(r, *p, "paper");
    if (const auto* n = t->get("nodes")) {
      for (double v : get_numbers(r, *n, "nodes")) {
        if (v != std::floor(v) || v < 1)
          r.fail(line_of(*n), "'nodes' must hold positive integers", "write nodes = [21, 41]");
        row.nodes.push_back(static_cast<int>(v));
      }
    }
    if (const auto* tol = t->get("tolerance")) {
      const auto v = number_of(*tol);
      if (!v || !(*v > 0) || !std::isfinite(*v))
        r.fail(line_of(*tol), "'tolerance' must be a positive finite number",
               "state the row's tolerance, e.g. tolerance = 0.05");
      row.tolerance = *v;
    }
    const std::string compare = get_string(r, *t, "compare", false, row.line);
    if (compare == "difference") row.compare = CompareBy::difference;
    else if (compare == "at_least") row.bound = LedgerRow::Bound::at_least;
    else if (compare == "at_most") row.bound = LedgerRow::Bound::at_most;
    else if (!compare.empty() && compare != "ratio")
      r.fail(row.line, fmt::format("compare = \"{}\" is not ratio, difference, at_least or at_most",
                                   compare),
             "write compare = \"ratio\", \"difference\", \"at_least\" or \"at_most\"");

    // The kind, and what it needs.
    const int kinds = !row.published_source.empty() + !row.measure.empty() + !finding.empty();
    if (kinds > 1)
      r.fail(row.line, fmt::format("row '{}' mixes published, measure and finding", row.id),
             "give one kind per row");
    auto need_numbers = [&](std::size_t n) {
      if (row.paper.size() != n)
        r.fail(row.line, fmt::format("row '{}' has {} paper value(s) for {}", row.id,
                                     row.paper.size(), n),
               "give one paper value per node count (measure rows: exactly one)");
      if (!(row.tolerance > 0))
        r.fail(row.line, fmt::format("row '{}' states no tolerance", row.id),
               "add tolerance = <relative or absolute tolerance>");
    };
    for (const auto& id : row.cases)
      if (!find_case(manifest, id))
        r.fail(row.line, fmt::format("row '{}' names the case '{}', not in {}", row.id, id,
                                     manifest.path.string()),
               "name a case id of the manifest (mfv verify --case lists them)");
    if (!row.published_source.empty()) {
      row.kind = LedgerRow::Kind::published;
      if (row.cases.size() > 1)
        r.fail(row.line, "a published row names one case", "write case = \"...\"");
      if (row.cases.size() == 1) {
        const ManifestCase& mc = *find_case(manifest, row.cases[0]);
        if (!row.problem.empty() || !row.method.empty())
          r.fail(row.line, "a row with a case takes problem and method from it",
                 "drop problem/method/problem_params/method_params");
        row.problem = mc.problem;
        row.problem_params = mc.problem_params;
        row.method = mc.method;
        row.method_params = mc.method_params;
      } else if (row.problem.empty() || row.method.empty()) {
        r.fail(row.line, fmt::format("published row '{}' names neither a case nor a problem "
                                     "and method", row.id),
               "add case = \"<suite case>\", or problem and method when no case measures it");
      }
      if (row.quantity.empty() || row.nodes.empty())
        r.fail(row.line, fmt::format("published row '{}' needs quantity and nodes", row.id),
               "add quantity = \"...\" and nodes = [...]");
      need_numbers(row.nodes.size());
      try {
        check_published(r, row, catalogue);
      } catch (const InputError& e) {
        const std::string what = e.what();
        if (what.rfind(path.string(), 0) == 0) throw;
        r.fail(row.line, what, "fix the row's problem, method or parameters");
      }
    } else if (!row.measure.empty()) {
      row.kind = LedgerRow::Kind::measure;
      if (row.cases.empty())
        r.fail(row.line, fmt::format("measure row '{}' names no case", row.id),
               "add cases = [\"<suite case>\", ...]");
      const bool known = row.measure == "l2_rate" || row.measure == "h1_rate" ||
                         row.measure == "energy_rate" || row.measure.rfind("headline:", 0) == 0;
      if (!known)
        r.fail(row.line, fmt::format("unknown measure '{}'", row.measure),
               "use l2_rate, h1_rate, energy_rate or headline:<name>");
      need_numbers(1);
    } else if (!finding.empty()) {
      row.kind = LedgerRow::Kind::finding;
      const auto colon = finding.find(':');
      if (colon == std::string::npos || colon == 0 || colon + 1 == finding.size())
        r.fail(row.line, fmt::format("finding '{}' is not <problem>:<id>", finding),
               "write finding = \"cantilever:kbm-si-rate\"");
      row.problem = finding.substr(0, colon);
      row.finding = finding.substr(colon + 1);
      if (catalogue.problems.contains(row.problem)) {
        try {
          create_problem(catalogue, row.problem, row.problem_params);
        } catch (const InputError& e) {
          r.fail(row.line, e.what(), "fix the row's problem_params");
        }
      }
    } else {
      row.kind = LedgerRow::Kind::open;
      if (row.problem.empty())
        r.fail(row.line, fmt::format("row '{}' measures nothing", row.id),
               "give it a published value (case, published, quantity, nodes, paper), a "
               "measure, a finding, or the problem that will measure it");
      if (catalogue.problems.contains(row.problem))
        r.fail(row.line, fmt::format("row '{}' is open but the problem '{}' now exists",
                                     row.id, row.problem),
               "name the case or finding that measures the claim");
    }
    ledger.rows.push_back(std::move(row));
  }
  return ledger;
}

std::vector<LedgerEntry> evaluate_ledger(const Ledger& ledger, const Registries& catalogue,
                                         const Manifest& manifest,
                                         const std::map<std::string, CaseOutcome>& ran) {
  std::vector<LedgerEntry> out;
  for (const auto& row : ledger.rows) {
    LedgerEntry e;
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
          if (it->second.study)
            for (const auto& r : it->second.study->cases) {
              computed = computed || row.quantity == "error u" ||
                         row.quantity == "error du/dx" || r.headline.count(row.quantity) > 0;
              if (r.spec.nodes == row.nodes[i]) ours = our_published_value(r, row.quantity);
            }
          if (!std::isfinite(ours)) missing.push_back(std::to_string(row.nodes[i]));
          e.ours.push_back(ours);
          e.compared.push_back(compare_row(ours, row.paper[i], row));
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
        std::vector<std::string> not_run, failed;
        for (const auto& id : row.cases) {
          const auto it = ran.find(id);
          if (it == ran.end()) { not_run.push_back(id); continue; }
          if (!it->second.study) { failed.push_back(id); continue; }
          const double v = measure_value(*it->second.study, row.measure);
          if (std::isfinite(v) && !(v <= best)) best = v;
        }
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
        for (const auto& mc : manifest.cases) {
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
        e.verdict = v.status == "not run" ? std::string(kNotRun) : v.status;
        if (std::find(ledger_verdicts().begin(), ledger_verdicts().end(), e.verdict) ==
            ledger_verdicts().end())
          throw std::logic_error(fmt::format("finding {}:{} returned the verdict '{}'",
                                             row.problem, row.finding, v.status));
        break;
      }
    }
    if (e.verdict == kReproduced && !row.reading.empty()) e.verdict = kReproducedReading;
    if (e.verdict != kReproduced && e.verdict != kReproducedReading &&
        e.verdict != kNotYetBuilt && e.verdict != kNotRun) {
      std::vector<std::string> parts;
      if (const std::string gap = gap_text(e); !gap.empty()) parts.push_back("gap " + gap);
      if (!e.why.empty()) parts.push_back(e.why);
      if (!row.reason.empty()) parts.push_back(row.reason);
      e.why = fmt::format("{}", fmt::join(parts, "; "));
    } else if (e.verdict == kReproducedReading) {
      e.why = "reading: " + row.reading;
    }
    out.push_back(std::move(e));
  }
  return out;
}

std::map<std::string, int> count_verdicts(const std::vector<LedgerEntry>& entries) {
  std::map<std::string, int> n;
  for (const auto& v : ledger_verdicts()) n[v] = 0;
  for (const auto& e : entries) ++n[e.verdict];
  return n;
}

std::string verdict_counts_line(const std::vector<LedgerEntry>& entries) {
  const auto n = count_verdicts(entries);
  std::vector<std::string> parts;
  for (const auto& v : ledger_verdicts())
    if (n.at(v) > 0) parts.push_back(fmt::format("{} {}", n.at(v), v));
  return fmt::format("{} of {} claims", fmt::join(parts, ", "), entries.size());
}

namespace {
std::string tolerance_text(const LedgerEntry& e) {
  const LedgerRow& row = *e.row;
  if (row.kind == LedgerRow::Kind::finding) return e.criterion;
  if (!(row.tolerance > 0)) return "–";
  if (row.bound == LedgerRow::Bound::at_least)
    return fmt::format("≥ paper − {:g}%", 100 * row.tolerance);
  if (row.bound == LedgerRow::Bound::at_most)
    return fmt::format("≤ paper + {:g}%", 100 * row.tolerance);
  return row.compare == CompareBy::ratio ? fmt::format("±{:g}%", 100 * row.tolerance)
                                         : fmt::format("±{:g}", row.tolerance);
}

std::string comparison_text(const LedgerEntry& e) {
  // Several values: the range of ratios (or differences), which is what the verdict reads.
  if (e.compared.size() > 2) {
    double lo = INFINITY, hi = -INFINITY;
    int finite = 0;
    for (const auto& c : e.compared) {
      const double v = e.row->compare == CompareBy::ratio ? c.ratio : c.difference;
      if (!std::isfinite(v)) continue;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
      ++finite;
    }
    if (finite == 0) return "–";
    const std::string range = e.row->compare == CompareBy::ratio
                                  ? fmt::format("{:.3g} to {:.3g}", lo, hi)
                                  : fmt::format("{:+.3g} to {:+.3g}", lo, hi);
    return finite < static_cast<int>(e.compared.size())
               ? fmt::format("{} ({} of {} values)", range, finite, e.compared.size())
               : range;
  }
  std::vector<std::string> parts;
  for (const auto& c : e.compared) {
    if (e.row->compare == CompareBy::ratio && std::isfinite(c.ratio))
      parts.push_back(fmt::format("{:.3g}", c.ratio));
    else if (std::isfinite(c.difference))
      parts.push_back(fmt::format("{:+.3g}", c.difference));
    else
      parts.push_back("–");
  }
  return fmt::format("{}", fmt::join(parts, ", "));
}

std::string paper_text(const LedgerEntry& e) {
  if (e.row->paper.empty()) return "–";
  std::string s = join_values(e.row->paper);
  if (e.row->kind == LedgerRow::Kind::published && e.row->nodes.size() > 1)
    s += fmt::format(" (n = {})", fmt::join(e.row->nodes, ", "));
  else if (e.row->kind == LedgerRow::Kind::published)
    s += fmt::format(" (n = {})", e.row->nodes[0]);
  return s;
}

std::string ours_text(const LedgerEntry& e) {
  if (e.row->kind == LedgerRow::Kind::finding) return e.ours_text.empty() ? "–" : e.ours_text;
  if (e.ours.empty()) return "–";
  return join_values(e.ours);
}

std::string case_text(const LedgerRow& row) {
  if (row.kind == LedgerRow::Kind::finding) return row.problem + ":" + row.finding;
  if (row.kind == LedgerRow::Kind::open) return row.problem;
  if (row.cases.empty()) return row.problem + " " + row.method;
  return fmt::format("{}", fmt::join(row.cases, ", "));
}

/// A Markdown table cell: pipes escaped, one line, "–" when empty.
std::string cell(const std::string& text) {
  std::string out;
  for (char ch : text) {
    if (ch == '|') out += "\\|";
    else if (ch == '\n') out += ' ';
    else out += ch;
  }
  return out.empty() ? std::string("–") : out;
}
}  // namespace

std::string ledger_markdown(const std::vector<LedgerEntry>& entries) {
  // Unpadded rows: the ledger is the report's longest table and padding would triple it.
  std::string md =
      "| id | source | claim | measured by | paper | ours | ours/paper (or −) | tolerance | "
      "verdict | reason, reading |\n|:--|:--|:--|:--|--:|--:|--:|:--|:--|:--|\n";
  for (const auto& e : entries) {
    const LedgerRow& row = *e.row;
    std::string by = case_text(row);
    if (row.cases.size() > 2) by = fmt::format("{} and {} more", row.cases.front(), row.cases.size() - 1);
    std::string why = e.why;
    if (e.verdict != kReproduced && e.verdict != kReproducedReading &&
        e.verdict != kNotRun && e.verdict != kNotYetBuilt) {
      // The gap is in the ratio column; the reason here.
      std::vector<std::string> parts;
      if (!row.reason.empty()) parts.push_back(row.reason);
      if (!row.reading.empty()) parts.push_back("reading: " + row.reading);
      why = fmt::format("{}", fmt::join(parts, "; "));
    }
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | **{}** | {} |\n", cell(row.id),
                      cell(row.source), cell(row.claim), cell(by), cell(paper_text(e)),
                      cell(ours_text(e)), cell(comparison_text(e)), cell(tolerance_text(e)),
                      e.verdict, cell(why));
  }
  return md;
}

std::string ledger_summary_markdown(const std::vector<LedgerEntry>& entries) {
  std::string md = "| id | source | claim | ours/paper (or −) | verdict |\n|:--|:--|:--|--:|:--|\n";
  for (const auto& e : entries) {
    const LedgerRow& row = *e.row;
    const bool compared = row.kind == LedgerRow::Kind::published ||
                          row.kind == LedgerRow::Kind::measure;
    md += fmt::format("| {} | {} | {} | {} | **{}** |\n", cell(row.id), cell(row.source),
                      cell(row.claim), compared ? cell(comparison_text(e)) : "–", e.verdict);
  }
  return md;
}

std::string ledger_csv(const std::vector<LedgerEntry>& entries) {
  std::string out =
      "id,source,claim,measured_by,paper,ours,comparison,tolerance,compare,verdict,gap_reason\n";
  for (const auto& e : entries) {
    const LedgerRow& row = *e.row;
    const std::vector<std::string> fields = {
        row.id, row.source, row.claim, case_text(row), join_values(row.paper, true),
        row.kind == LedgerRow::Kind::finding ? ours_text(e) : join_values(e.ours, true),
        comparison_text(e),
        row.kind == LedgerRow::Kind::finding ? e.criterion
        : row.tolerance > 0                  ? fmt::format("{:g}", row.tolerance)
                                             : "",
        row.kind == LedgerRow::Kind::finding ? "finding"
        : row.bound == LedgerRow::Bound::at_least ? "at_least"
        : row.bound == LedgerRow::Bound::at_most  ? "at_most"
        : row.compare == CompareBy::ratio    ? "ratio"
                                             : "difference",
        e.verdict, e.why};
    std::vector<std::string> quoted;
    for (const auto& f : fields) quoted.push_back(csv_field(f));
    out += fmt::format("{}\n", fmt::join(quoted, ","));
  }
  return out;
}

}  // namespace mfv
