#include "verify/ledger.hpp"
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
  /// A path the ledger names, relative to the ledger's directory.
  std::filesystem::path resolve(const std::string& p) const {
    const std::filesystem::path path(p);
    return path.is_absolute() ? path : std::filesystem::path(file_).parent_path() / path;
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

namespace {

const std::vector<std::string> kRowKeys = {
    "id", "source", "claim", "reading", "reason", "quote", "case", "cases", "problem",
    "problem_params", "method", "method_params", "published", "quantity", "nodes", "paper",
    "tolerance", "compare", "measure", "statistic", "finding", "try", "check"};

bool is_rate_measure(const std::string& m) {
  return m == "l2_rate" || m == "h1_rate" || m == "energy_rate";
}

RateStatistic parse_statistic(const Reporter& r, const toml::table& t, int line) {
  const std::string s = get_string(r, t, "statistic", false, line);
  if (s.empty() || s == "least_squares") return RateStatistic::least_squares;
  if (s == "finest_pair") return RateStatistic::finest_pair;
  if (s == "best_pair") return RateStatistic::best_pair;
  r.fail(line_of(*t.get("statistic")), fmt::format("statistic = \"{}\" is not known", s),
         "write least_squares, finest_pair or best_pair");
}

std::vector<int> get_nodes(const Reporter& r, const toml::node& n) {
  std::vector<int> out;
  for (double v : get_numbers(r, n, "nodes")) {
    if (v != std::floor(v) || v < 1)
      r.fail(line_of(n), "'nodes' must hold positive integers", "write nodes = [21, 41]");
    out.push_back(static_cast<int>(v));
  }
  return out;
}

/// "<problem>:<id>" into the row (finding rows).
void set_finding(const Reporter& r, LedgerRow& row, const std::string& finding,
                 const Registries& catalogue) {
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
}

/// Takes problem and method from the manifest case a published row names.
void take_case(const Reporter& r, LedgerRow& row, const Manifest& manifest) {
  const ManifestCase* mc = find_case(manifest, row.cases[0]);
  if (!mc)
    r.fail(row.line, fmt::format("row '{}' names the case '{}', not in {}", row.id,
                                 row.cases[0], manifest.path.string()),
           "name a case id of the manifest (mfv verify --case lists them)");
  row.problem = mc->problem;
  row.problem_params = mc->problem_params;
  row.method = mc->method;
  row.method_params = mc->method_params;
}

void check_cases_exist(const Reporter& r, const LedgerRow& row, const Manifest& manifest) {
  for (const auto& id : row.cases)
    if (!find_case(manifest, id))
      r.fail(row.line, fmt::format("row '{}' names the case '{}', not in {}", row.id, id,
                                   manifest.path.string()),
             "name a case id of the manifest (mfv verify --case lists them)");
}

/// A finding row's cases, when it names them, are studies of its problem.
void check_finding_cases(const Reporter& r, const LedgerRow& row, const Manifest& manifest) {
  for (const auto& id : row.cases)
    if (const ManifestCase* mc = find_case(manifest, id); mc && mc->problem != row.problem)
      r.fail(row.line, fmt::format("row '{}' judges {}:{} on the case '{}' of problem '{}'",
                                   row.id, row.problem, row.finding, id, mc->problem),
             fmt::format("name cases of {} only", row.problem));
}

/// What a try or a check may replace in a row of each kind (the rest it inherits).
std::vector<std::string> replaceable(LedgerRow::Kind kind) {
  switch (kind) {
    case LedgerRow::Kind::published: return {"case", "nodes", "quantity"};
    case LedgerRow::Kind::measure: return {"cases", "measure", "statistic"};
    case LedgerRow::Kind::finding: return {"finding", "problem_params", "cases"};
    case LedgerRow::Kind::open: return {};
  }
  return {};
}

/// The row `base` with the replacements of a [[row.try]] or [[row.check]] table.
std::shared_ptr<const LedgerRow> variant_of(const Reporter& r, const LedgerRow& base,
                                            const toml::table& t, const std::string& what,
                                            const std::vector<std::string>& own_keys,
                                            const Manifest& manifest,
                                            const Registries& catalogue) {
  auto v = std::make_shared<LedgerRow>(base);
  v->tries.clear();
  v->checks.clear();
  v->line = line_of(t);
  if (base.kind == LedgerRow::Kind::open)
    r.fail(v->line, fmt::format("row '{}' is open: it has no reading to vary", base.id),
           fmt::format("drop the {}", what));
  const auto can = replaceable(base.kind);
  std::vector<std::string> valid = own_keys;
  valid.insert(valid.end(), can.begin(), can.end());
  for (const auto& [k, node] : t)
    if (std::find(valid.begin(), valid.end(), std::string(k.str())) == valid.end())
      r.fail(line_of(node), fmt::format("'{}' cannot be set in a {} of row '{}'", k.str(), what,
                                        base.id),
             fmt::format("valid keys here: {}", fmt::join(valid, ", ")));
  if (const auto* c = t.get("case")) {
    v->cases = {get_string(r, t, "case", true, v->line)};
    (void)c;
    take_case(r, *v, manifest);
  }
  if (const auto* c = t.get("cases")) {
    v->cases = get_strings(r, *c, "cases");
    check_cases_exist(r, *v, manifest);
  }
  if (t.get("finding") || t.get("cases")) {
    if (base.kind == LedgerRow::Kind::finding) {
      if (t.get("finding"))
        set_finding(r, *v, get_string(r, t, "finding", true, v->line), catalogue);
      check_finding_cases(r, *v, manifest);
    }
  }
  if (t.get("reference")) {
    v->reference = r.resolve(get_string(r, t, "reference", true, v->line));
    if (const auto* st = t.get("studies")) v->reference_studies = get_strings(r, *st, "studies");
    v->cases.clear();
    try {
      (void)load_reference_studies(v->reference, v->reference_studies);
    } catch (const InputError& e) {
      r.fail(v->line, e.what(), "fix the reference file or the check's studies");
    }
  } else if (t.get("studies")) {
    r.fail(v->line, "'studies' names studies of a reference file, and the check names none",
           "add reference = \"<file>\" or drop studies");
  }
  if (const auto* n = t.get("nodes")) {
    v->nodes = get_nodes(r, *n);
    if (v->nodes.size() != v->paper.size())
      r.fail(line_of(*n), fmt::format("{} of row '{}' reads {} resolution(s) for {} paper "
                                      "value(s)", what, base.id, v->nodes.size(), v->paper.size()),
             "give one resolution per paper value");
  }
  if (t.get("quantity")) v->quantity = get_string(r, t, "quantity", true, v->line);
  if (t.get("measure")) {
    v->measure = get_string(r, t, "measure", true, v->line);
    if (!is_rate_measure(v->measure) && v->measure.rfind("headline:", 0) != 0)
      r.fail(v->line, fmt::format("unknown measure '{}'", v->measure),
             "use l2_rate, h1_rate, energy_rate or headline:<name>");
  }
  if (t.get("statistic")) v->statistic = parse_statistic(r, t, v->line);
  if (t.get("problem_params")) v->problem_params = get_params(r, t, "problem_params");
  if (t.get("problem_params") && !t.get("finding"))
    set_finding(r, *v, v->problem + ":" + v->finding, catalogue);
  return v;
}

std::vector<LedgerCheck> parse_checks(const Reporter& r, const LedgerRow& base,
                                      const toml::node* node, const Manifest& manifest,
                                      const Registries& catalogue) {
  std::vector<LedgerCheck> out;
  if (!node) return out;
  const auto* a = node->as_array();
  if (!a || !a->is_array_of_tables())
    r.fail(line_of(*node), fmt::format("'check' of row '{}' must be [[row.check]] tables", base.id),
           "write each check as [[row.check]] (or [[row.try.check]])");
  for (const auto& n : *a) {
    const auto& t = *n.as_table();
    LedgerCheck c;
    c.line = line_of(n);
    c.route = get_string(r, t, "route", true, c.line);
    const std::string kind = get_string(r, t, "kind", true, c.line);
    if (kind == "independent") c.kind = LedgerCheck::Kind::independent;
    else if (kind == "converged") c.kind = LedgerCheck::Kind::converged;
    else
      r.fail(c.line, fmt::format("check kind = \"{}\" is not known", kind),
             "write kind = \"independent\" (a second route) or \"converged\" (refinement)");
    std::vector<std::string> own = {"kind", "route"};
    // A finding judged on an independent implementation's recorded studies
    // (verify/reference_studies.hpp): the second route that shares no code with ours.
    if (base.kind == LedgerRow::Kind::finding) own.insert(own.end(), {"reference", "studies"});
    c.row = variant_of(r, base, t, "check", own, manifest, catalogue);
    if (t.size() == 2)
      r.fail(c.line, fmt::format("a check of row '{}' replaces nothing: it would repeat the "
                                 "reading", base.id),
             "name the case, cases, nodes or finding the second computation uses");
    out.push_back(std::move(c));
  }
  return out;
}

std::vector<LedgerReading> parse_tries(const Reporter& r, const LedgerRow& base,
                                       const toml::node* node, const Manifest& manifest,
                                       const Registries& catalogue) {
  std::vector<LedgerReading> out;
  if (!node) return out;
  const auto* a = node->as_array();
  if (!a || !a->is_array_of_tables())
    r.fail(line_of(*node), fmt::format("'try' of row '{}' must be [[row.try]] tables", base.id),
           "write each reading tried as [[row.try]]");
  std::set<std::string> names;
  for (const auto& n : *a) {
    const auto& t = *n.as_table();
    LedgerReading rd;
    rd.line = line_of(n);
    rd.name = get_string(r, t, "name", true, rd.line);
    if (!names.insert(rd.name).second)
      r.fail(rd.line, fmt::format("row '{}' tries the reading '{}' twice", base.id, rd.name),
             "give each reading its own name");
    rd.quote = get_string(r, t, "quote", true, rd.line);
    if (const auto* f = t.get("fitted")) {
      const auto* b = f->as_boolean();
      if (!b)
        r.fail(line_of(*f), "'fitted' must be true or false",
               "write fitted = true for a constant fitted to the paper's numbers");
      rd.fitted = b->get();
    }
    rd.row = variant_of(r, base, t, "try", {"name", "quote", "fitted", "check"}, manifest,
                        catalogue);
    rd.checks = parse_checks(r, *rd.row, t.get("check"), manifest, catalogue);
    out.push_back(std::move(rd));
  }
  return out;
}

/// The [[source]] tables (LedgerSource): names unique, row globs resolved in ledger order,
/// each row in one source at most, a named reading tried by every row of its source.
std::vector<LedgerSource> parse_sources(const Reporter& r, const toml::node* node,
                                        const std::vector<LedgerRow>& rows) {
  std::vector<LedgerSource> out;
  if (!node) return out;
  const auto* a = node->as_array();
  if (!a || !a->is_array_of_tables())
    r.fail(line_of(*node), "'source' must be [[source]] tables",
           "write each source judged under one reading as [[source]]");
  static const std::vector<std::string> keys = {"name", "rows", "reading", "quote", "pairs"};
  std::set<std::string> names;
  std::map<std::string, std::string> owner;  // row id → source
  for (const auto& n : *a) {
    const auto& t = *n.as_table();
    LedgerSource src;
    src.line = line_of(n);
    for (const auto& [k, v] : t)
      if (std::find(keys.begin(), keys.end(), std::string(k.str())) == keys.end())
        r.fail(line_of(v), fmt::format("unknown key '{}' in a [[source]]", k.str()),
               fmt::format("valid keys: {}", fmt::join(keys, ", ")));
    src.name = get_string(r, t, "name", true, src.line);
    if (!names.insert(src.name).second)
      r.fail(src.line, fmt::format("two [[source]] tables are named '{}'", src.name),
             "give each source one table");
    src.reading = get_string(r, t, "reading", false, src.line);
    src.quote = get_string(r, t, "quote", true, src.line);
    const toml::node* rn = t.get("rows");
    if (!rn)
      r.fail(src.line, fmt::format("source '{}' names no rows", src.name),
             "add rows = [\"<id or glob>\", ...]");
    const std::vector<std::string> patterns = get_strings(r, *rn, "rows");
    for (const auto& pattern : patterns) {
      int matched = 0;
      for (const auto& row : rows) {
        if (fnmatch(pattern.c_str(), row.id.c_str(), 0) != 0) continue;
        ++matched;
        if (std::find(src.rows.begin(), src.rows.end(), row.id) != src.rows.end()) continue;
        if (const auto o = owner.find(row.id); o != owner.end())
          r.fail(src.line, fmt::format("row '{}' is in source '{}' and '{}'", row.id, o->second,
                                       src.name),
                 "a row is judged under one source's reading: name it in one [[source]]");
        if (row.kind == LedgerRow::Kind::open)
          r.fail(src.line, fmt::format("source '{}' names the open row '{}'", src.name, row.id),
                 "an open row has no reading to judge");
        if (!src.reading.empty() &&
            std::none_of(row.tries.begin(), row.tries.end(), [&](const LedgerReading& t) {
              return t.name == src.reading && !t.fitted;
            }))
          r.fail(src.line, fmt::format("source '{}' reads every row as '{}', which row '{}' "
                                       "does not try (or tries as fitted)",
                                       src.name, src.reading, row.id),
                 "add the [[row.try]] to every row of the source, or leave reading empty");
        owner[row.id] = src.name;
        src.rows.push_back(row.id);
      }
      if (matched == 0)
        r.fail(src.line, fmt::format("source '{}': '{}' matches no row", src.name, pattern),
               "name row ids of this ledger");
    }
    // Ledger order, whatever the order of the patterns.
    std::vector<std::string> ordered;
    for (const auto& row : rows)
      if (std::find(src.rows.begin(), src.rows.end(), row.id) != src.rows.end())
        ordered.push_back(row.id);
    src.rows = std::move(ordered);
    if (const toml::node* pn = t.get("pairs")) {
      const auto* pa = pn->as_array();
      if (!pa) r.fail(line_of(*pn), "'pairs' must be an array of [first, second] row ids",
                      "write pairs = [[\"a\", \"b\"]]");
      for (const auto& e : *pa) {
        const std::vector<std::string> p = get_strings(r, e, "pairs entry");
        if (p.size() != 2 || std::find(src.rows.begin(), src.rows.end(), p[0]) == src.rows.end() ||
            std::find(src.rows.begin(), src.rows.end(), p[1]) == src.rows.end())
          r.fail(line_of(e), fmt::format("a pair of source '{}' must name two of its rows",
                                         src.name),
                 "write [\"<first row id>\", \"<second row id>\"]");
        src.pairs.emplace_back(p[0], p[1]);
      }
    }
    out.push_back(std::move(src));
  }
  return out;
}

}  // namespace

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
  for (const auto& [k, v] : doc)
    if (k.str() != "row" && k.str() != "source")
      r.fail(line_of(v), fmt::format("unknown top-level key '{}'", k.str()),
             "the ledger holds [[row]] and [[source]] tables");
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
      if (std::find(kRowKeys.begin(), kRowKeys.end(), std::string(k.str())) == kRowKeys.end())
        r.fail(line_of(v), fmt::format("unknown key '{}' in a row", k.str()),
               fmt::format("valid keys: {}", fmt::join(kRowKeys, ", ")));
    row.id = get_string(r, *t, "id", true, row.line);
    if (!ids.insert(row.id).second)
      r.fail(row.line, fmt::format("duplicate row id '{}'", row.id), "give each row its own id");
    row.source = get_string(r, *t, "source", true, row.line);
    row.claim = get_string(r, *t, "claim", true, row.line);
    row.reading = get_string(r, *t, "reading", false, row.line);
    row.reason = get_string(r, *t, "reason", false, row.line);
    row.quote = get_string(r, *t, "quote", false, row.line);
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
    if (const auto* n = t->get("nodes")) row.nodes = get_nodes(r, *n);
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
    check_cases_exist(r, row, manifest);
    if (!row.published_source.empty()) {
      row.kind = LedgerRow::Kind::published;
      if (row.cases.size() > 1)
        r.fail(row.line, "a published row names one case", "write case = \"...\"");
      if (row.cases.size() == 1) {
        if (!row.problem.empty() || !row.method.empty())
          r.fail(row.line, "a row with a case takes problem and method from it",
                 "drop problem/method/problem_params/method_params");
        take_case(r, row, manifest);
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
      const bool known = is_rate_measure(row.measure) || row.measure.rfind("headline:", 0) == 0;
      if (!known)
        r.fail(row.line, fmt::format("unknown measure '{}'", row.measure),
               "use l2_rate, h1_rate, energy_rate or headline:<name>");
      need_numbers(1);
    } else if (!finding.empty()) {
      row.kind = LedgerRow::Kind::finding;
      set_finding(r, row, finding, catalogue);
      check_finding_cases(r, row, manifest);
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
    if (t->get("statistic")) {
      if (row.kind != LedgerRow::Kind::measure)
        r.fail(row.line, fmt::format("row '{}' sets a statistic but measures no rate", row.id),
               "drop 'statistic' (it chooses how a measure row reads a rate)");
      row.statistic = parse_statistic(r, *t, row.line);
    }
    row.tries = parse_tries(r, row, t->get("try"), manifest, catalogue);
    row.checks = parse_checks(r, row, t->get("check"), manifest, catalogue);
    if (!row.tries.empty() && row.quote.empty() && row.reading.empty())
      r.fail(row.line, fmt::format("row '{}' tries other readings but does not say what its "
                                   "own rests on", row.id),
             "add quote = \"<the paper's words>\" (or reading = \"…\") to the row");
    ledger.rows.push_back(std::move(row));
  }
  ledger.sources = parse_sources(r, doc.get("source"), ledger.rows);
  return ledger;
}

namespace {

/// Rank of a verdict for choosing the closest reading (lower is closer).
int verdict_rank(const std::string& v) {
  static const std::vector<std::string> order = {kReproduced,    kReproducedReading, kPartly,
                                                 kNotReproduced, kNotReached,        kNotRun,
                                                 kNotYetBuilt};
  const auto it = std::find(order.begin(), order.end(), v);
  return static_cast<int>(it - order.begin());
}

/// A verdict from a comparison with the paper (a finding may return "reproduced under a
/// stated reading" itself: a compared verdict too, whose checks count as evidence).
bool compared_verdict(const std::string& v) {
  return v == kReproduced || v == kReproducedReading || v == kPartly || v == kNotReproduced;
}

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

/// One reading's values and verdict against the paper, before a stated reading is named.
LedgerReadingOutcome measure_reading(const LedgerRow& row, const Registries& catalogue,
                                     const Manifest& manifest,
                                     const std::map<std::string, CaseOutcome>& ran) {
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
        const double v = measure_value(*it->second.study, row.measure, row.statistic);
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
  for (const auto& row : ledger.rows) {
    LedgerEntry e;
    e.row = &row;
    if (const auto s = source_of.find(row.id); s != source_of.end()) e.source = s->second;
    e.readings.push_back(measure_reading(row, catalogue, manifest, ran));
    evaluate_checks(e.readings.back(), row.checks, catalogue, manifest, ran);
    for (const auto& t : row.tries) {
      e.readings.push_back(measure_reading(*t.row, catalogue, manifest, ran));
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

std::string comparison_text(const LedgerRow& row, const std::vector<Comparison>& compared) {
  // Several values: the range of ratios (or differences), which is what the verdict reads.
  if (compared.size() > 2) {
    double lo = INFINITY, hi = -INFINITY;
    int finite = 0;
    for (const auto& c : compared) {
      const double v = row.compare == CompareBy::ratio ? c.ratio : c.difference;
      if (!std::isfinite(v)) continue;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
      ++finite;
    }
    if (finite == 0) return "–";
    const std::string range = row.compare == CompareBy::ratio
                                  ? fmt::format("{:.3g} to {:.3g}", lo, hi)
                                  : fmt::format("{:+.3g} to {:+.3g}", lo, hi);
    return finite < static_cast<int>(compared.size())
               ? fmt::format("{} ({} of {} values)", range, finite, compared.size())
               : range;
  }
  std::vector<std::string> parts;
  for (const auto& c : compared) {
    if (row.compare == CompareBy::ratio && std::isfinite(c.ratio))
      parts.push_back(fmt::format("{:.3g}", c.ratio));
    else if (std::isfinite(c.difference))
      parts.push_back(fmt::format("{:+.3g}", c.difference));
    else
      parts.push_back("–");
  }
  return fmt::format("{}", fmt::join(parts, ", "));
}

std::string comparison_text(const LedgerEntry& e) { return comparison_text(*e.row, e.compared); }

/// The paper's values with the resolutions `read` takes ours at.
std::string paper_text(const LedgerRow& row, const LedgerRow& read) {
  if (row.paper.empty()) return "–";
  std::string s = join_values(row.paper);
  if (read.kind == LedgerRow::Kind::published)
    s += fmt::format(" (n = {})", fmt::join(read.nodes, ", "));
  return s;
}

std::string paper_text(const LedgerEntry& e) { return paper_text(*e.row, *e.read); }

std::string values_text(const LedgerRow& row, const std::vector<double>& ours,
                        const std::string& text) {
  if (row.kind == LedgerRow::Kind::finding) return text.empty() ? "–" : text;
  if (ours.empty()) return "–";
  return join_values(ours);
}

std::string ours_text(const LedgerEntry& e) { return values_text(*e.row, e.ours, e.ours_text); }

std::string case_text(const LedgerRow& row) {
  if (row.kind == LedgerRow::Kind::finding) {
    const std::string pp = row.problem_params.to_string();
    return row.problem + ":" + row.finding + (pp.empty() ? "" : " (" + pp + ")");
  }
  if (row.kind == LedgerRow::Kind::open) return row.problem;
  if (row.cases.empty()) return row.problem + " " + row.method;
  std::string s = row.cases.size() > 2
                      ? fmt::format("{} and {} more", row.cases.front(), row.cases.size() - 1)
                      : fmt::format("{}", fmt::join(row.cases, ", "));
  if (row.kind == LedgerRow::Kind::measure) {
    s += ", " + row.measure;
    if (is_rate_measure(row.measure))
      s += row.statistic == RateStatistic::finest_pair ? " (finest pair)"
           : row.statistic == RateStatistic::best_pair ? " (best pair)"
                                                       : " (least squares)";
  }
  if (row.kind == LedgerRow::Kind::published) s += " · " + row.quantity;
  return s;
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

/// The HTML anchor of a row's readings on the ledger page.
std::string anchor(const LedgerRow& row) {
  std::string a = "row-";
  for (char ch : row.id) a += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '-';
  return a;
}

const std::map<std::string, std::string>& paper_titles() {
  static const std::map<std::string, std::string> t = {
      {"000", "000 — Belytschko & Xiao, stability of particle methods with corrected derivatives"},
      {"001", "001 — Rabczuk, Belytschko & Xiao, stable particle methods based on Lagrangian kernels"},
      {"003", "003 — Samaniego et al., stability of explicit enriched meshfree methods"},
      {"004", "004 — Liu et al., reproducing kernel and wavelet particle methods (I–III)"},
      {"other", "Other sources (closed forms, hydrostatics, experiments): our checks"}};
  return t;
}

std::vector<std::string> paper_order() { return {"000", "001", "003", "004", "other"}; }

/// Verdict columns of the counts table; the rest (not reached, not run, not yet built) is
/// "other".
struct Counts {
  int claims = 0, reproduced = 0, reading = 0, partly = 0, not_reproduced = 0, other = 0;
  int independent = 0, converged = 0, single = 0;
  void add(const LedgerEntry& e) {
    ++claims;
    if (e.verdict == kReproduced) ++reproduced;
    else if (e.verdict == kReproducedReading) ++reading;
    else if (e.verdict == kPartly) ++partly;
    else if (e.verdict == kNotReproduced) ++not_reproduced;
    else ++other;
    if (e.evidence == kEvidenceIndependent) ++independent;
    else if (e.evidence == kEvidenceConverged) ++converged;
    else if (e.evidence == kEvidenceSingle) ++single;
  }
  std::vector<std::string> cells() const {
    auto n = [](int v) { return v == 0 ? std::string("·") : std::to_string(v); };
    return {std::to_string(claims), n(reproduced), n(reading), n(partly), n(not_reproduced),
            n(other), n(independent), n(converged), n(single)};
  }
};

std::string counts_header(const std::string& first) {
  return fmt::format(
      "| {} | claims | reproduced | stated reading | partly | not reproduced | not run or "
      "reached | independent | converged | single run |\n|:--|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n",
      first);
}

std::string md_row(const std::vector<std::string>& cells) {
  std::string s = "|";
  for (const auto& c : cells) s += " " + cell(c) + " |";
  return s + "\n";
}

/// "§3.1.2" before "§3.10", "I §6" before "II §7": digit runs compare as numbers.
bool natural_less(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    const bool da = std::isdigit(static_cast<unsigned char>(a[i])),
               db = std::isdigit(static_cast<unsigned char>(b[j]));
    if (da && db) {
      std::size_t ie = i, je = j;
      while (ie < a.size() && std::isdigit(static_cast<unsigned char>(a[ie]))) ++ie;
      while (je < b.size() && std::isdigit(static_cast<unsigned char>(b[je]))) ++je;
      const long x = std::stol(a.substr(i, std::min<std::size_t>(ie - i, 9)));
      const long y = std::stol(b.substr(j, std::min<std::size_t>(je - j, 9)));
      if (x != y) return x < y;
      i = ie;
      j = je;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i;
      ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

/// Counts per paper (and, with `sections`, per section of each paper).
std::string counts_markdown(const std::vector<LedgerEntry>& entries, bool sections) {
  std::map<std::string, Counts> per_paper;
  std::map<std::string, std::map<std::string, Counts>> per_section;
  std::map<std::string, std::vector<std::string>> section_order;
  Counts all;
  for (const auto& e : entries) {
    const std::string p = ledger_paper(*e.row), s = ledger_section(*e.row);
    per_paper[p].add(e);
    auto& order = section_order[p];
    if (std::find(order.begin(), order.end(), s) == order.end()) order.push_back(s);
    per_section[p][s].add(e);
    all.add(e);
  }
  for (auto& [p, order] : section_order) std::sort(order.begin(), order.end(), natural_less);
  std::string md = counts_header(sections ? "paper / section" : "paper");
  for (const auto& p : paper_order()) {
    if (!per_paper.count(p)) continue;
    auto cells = per_paper[p].cells();
    cells.insert(cells.begin(), sections ? "**" + paper_titles().at(p) + "**"
                                         : paper_titles().at(p));
    md += md_row(cells);
    if (!sections) continue;
    for (const auto& s : section_order[p]) {
      auto sc = per_section[p][s].cells();
      sc.insert(sc.begin(), "  " + s);
      md += md_row(sc);
    }
  }
  auto cells = all.cells();
  cells.insert(cells.begin(), "**all**");
  return md + md_row(cells);
}

std::string check_kind(const LedgerCheck& c) {
  return c.kind == LedgerCheck::Kind::independent ? kEvidenceIndependent : kEvidenceConverged;
}

/// Every reading tried for a row and every check, as the ledger page shows them.
std::string readings_markdown(const LedgerEntry& e) {
  const LedgerRow& row = *e.row;
  std::string md = fmt::format("<a id=\"{}\"></a>\n#### {}\n\n{} — {}  \n", anchor(row),
                               row.id, row.source, row.claim);
  md += fmt::format("Verdict **{}**, evidence **{}**, from the reading *{}*.", e.verdict,
                    e.evidence, e.reading);
  if (!row.reason.empty() && e.verdict != kReproduced && e.verdict != kReproducedReading)
    md += " Best explanation of the gap: " + row.reason;
  md += "\n\n| reading | the paper's words | measured by | ours | ours/paper (or −) | "
        "verdict | evidence |\n|:--|:--|:--|--:|--:|:--|:--|\n";
  for (std::size_t i = 0; i < e.readings.size(); ++i) {
    const LedgerReadingOutcome& o = e.readings[i];
    std::string name = o.name();
    if (!o.reading) name += " (the row's own)";
    if (o.reading && o.reading->fitted) name += " — fitted: shown for scale, not counted";
    if (i == e.chosen) name = "**" + name + "** ← verdict";
    const std::string quote = o.reading ? o.reading->quote : row.quote;
    md += md_row({name, quote, case_text(*o.row),
                  values_text(*o.row, o.ours, o.ours_text) +
                      (o.row->kind == LedgerRow::Kind::published
                           ? fmt::format(" (n = {})", fmt::join(o.row->nodes, ", "))
                           : ""),
                  comparison_text(*o.row, o.compared),
                  o.verdict + (o.why.empty() || compared_verdict(o.verdict) ? "" : ": " + o.why),
                  o.evidence});
  }
  bool any_check = false;
  for (const auto& o : e.readings) any_check = any_check || !o.checks.empty();
  if (any_check) {
    md += "\nChecks (a second computation of a reading's value):\n\n| reading | kind | route | "
          "measured by | value | agrees |\n|:--|:--|:--|:--|--:|:--|\n";
    for (const auto& o : e.readings)
      for (const auto& c : o.checks)
        md += md_row({o.name(), check_kind(*c.check), c.check->route, case_text(*c.check->row),
                      values_text(*c.check->row, c.values, c.ours_text),
                      c.agrees                   ? std::string("yes")
                      : c.verdict == kNotRun       ? std::string("not run (a --full case?)")
                                                   : fmt::format("no ({})", c.verdict)});
  }
  return md + "\n";
}

}  // namespace

std::string ledger_paper(const LedgerRow& row) {
  // The id's prefix, else the source's first word ("004 II Table 1").
  for (const char* p : {"000", "001", "003", "004"})
    if (row.id.rfind(std::string(p) + "-", 0) == 0 || row.source.rfind(std::string(p) + " ", 0) == 0)
      return p;
  return "other";
}

std::string ledger_section(const LedgerRow& row) {
  const std::string& s = row.source;
  std::string part;
  // 004 has three papers: "004 I", "004 II", "004 III".
  for (const char* p : {"III", "II", "I"})
    if (s.rfind(std::string("004 ") + p + " ", 0) == 0 ||
        s.rfind(std::string("004 ") + p + ",", 0) == 0) {
      part = std::string(p) + " ";
      break;
    }
  const auto at = s.find("§");
  if (at == std::string::npos) {
    for (const char* w : {"Table", "Fig."}) {
      const auto t = s.find(w);
      if (t != std::string::npos) {
        auto end = s.find_first_of(",;(", t);
        return part + s.substr(t, end == std::string::npos ? std::string::npos : end - t);
      }
    }
    return part.empty() ? s : part + "–";
  }
  std::size_t end = at + std::string("§").size();
  while (end < s.size() && (std::isdigit(static_cast<unsigned char>(s[end])) || s[end] == '.'))
    ++end;
  while (end > at && s[end - 1] == '.') --end;
  return part + s.substr(at, end - at);
}

std::string ledger_markdown(const std::vector<LedgerEntry>& entries) {
  std::string md = "## Counts by paper and section\n\n" + counts_markdown(entries, true) +
                   "\nEvidence: **independent** (a second computation by another route agrees "
                   "within the row's tolerance), **converged** (a finer resolution, quadrature or "
                   "time step moves ours by less than the tolerance), **single run** (no check "
                   "agrees, or none exists).\n\n";
  for (const auto& p : paper_order()) {
    std::vector<const LedgerEntry*> mine;
    for (const auto& e : entries)
      if (ledger_paper(*e.row) == p) mine.push_back(&e);
    if (mine.empty()) continue;
    md += fmt::format("## {}\n\n", paper_titles().at(p));
    md += "| id | source | claim | paper | ours | ours/paper (or −) | tolerance | verdict | "
          "evidence | reading (of those tried) |\n|:--|:--|:--|--:|--:|--:|:--|:--|:--|:--|\n";
    for (const LedgerEntry* e : mine) {
      const LedgerRow& row = *e->row;
      const std::string tried = e->readings.size() > 1
                                    ? fmt::format("{} ([{} tried](#{}))", e->reading,
                                                  e->readings.size(), anchor(row))
                                    : fmt::format("{} ([details](#{}))", e->reading, anchor(row));
      md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | **{}** | {} | {} |\n",
                        cell(row.id), cell(row.source), cell(row.claim), cell(paper_text(*e)),
                        cell(ours_text(*e)), cell(comparison_text(*e)), cell(tolerance_text(*e)),
                        e->verdict, cell(e->evidence), cell(tried));
    }
    md += "\n";
  }
  md += "## Readings tried and checks, per row\n\nThe verdict is that of the closest reading "
        "that is not fitted (best verdict, then nearest the paper); the row's own reading wins "
        "a tie.\n\n";
  for (const auto& e : entries) {
    md += readings_markdown(e);
    if (!e.why.empty() && e.verdict != kReproduced) md += "Gap and reason: " + e.why + "\n\n";
  }
  return md;
}

std::string ledger_counts_markdown(const std::vector<LedgerEntry>& entries) {
  return counts_markdown(entries, true);
}

std::string ledger_csv(const std::vector<LedgerEntry>& entries) {
  std::string out =
      "id,paper_id,section,source,claim,measured_by,paper,ours,comparison,tolerance,compare,"
      "verdict,evidence,reading,readings_tried,checks,gap_reason\n";
  for (const auto& e : entries) {
    const LedgerRow& row = *e.row;
    std::vector<std::string> tried, checks;
    for (std::size_t i = 0; i < e.readings.size(); ++i) {
      const auto& o = e.readings[i];
      tried.push_back(fmt::format(
          "{}{}{}: {} [{}] {} → {}", i == e.chosen ? "* " : "", o.name(),
          o.reading && o.reading->fitted ? " (fitted, not counted)" : "", case_text(*o.row),
          o.row->kind == LedgerRow::Kind::finding ? values_text(*o.row, o.ours, o.ours_text)
                                                   : join_values(o.ours, true),
          comparison_text(*o.row, o.compared), o.verdict));
      for (const auto& c : o.checks)
        checks.push_back(fmt::format(
            "{} check of {}: {}: {} = {} → {}", check_kind(*c.check), o.name(), c.check->route,
            case_text(*c.check->row),
            c.check->row->kind == LedgerRow::Kind::finding ? c.ours_text
                                                            : join_values(c.values, true),
            c.agrees                ? std::string("agrees")
            : c.verdict == kNotRun ? std::string("not run in this invocation")
                                   : "differs (" + c.verdict + ")"));
    }
    const std::vector<std::string> fields = {
        row.id, ledger_paper(row), ledger_section(row), row.source, row.claim,
        case_text(*e.read), join_values(row.paper, true),
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
        e.verdict, e.evidence, e.reading, fmt::format("{}", fmt::join(tried, " | ")),
        fmt::format("{}", fmt::join(checks, " | ")), e.why};
    std::vector<std::string> quoted;
    for (const auto& f : fields) quoted.push_back(csv_field(f));
    out += fmt::format("{}\n", fmt::join(quoted, ","));
  }
  return out;
}

}  // namespace mfv
