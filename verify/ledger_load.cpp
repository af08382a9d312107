#include "verify/ledger.hpp"
#include "verify/ledger_internal.hpp"
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

/// Reading and checking suites/ledger.toml (verify/ledger.hpp's format): rows, their tries and
/// checks, the reference studies they name, and the [[source]] tables.
namespace mfv {

using namespace ledger_internal;

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

/// The published values a row names: at least one per node count with the row's value (two
/// sources may print the same number), and the row's tolerance (throws otherwise).
void check_published(const Reporter& r, const LedgerRow& row, const Registries& catalogue) {
  const auto problem = create_problem(catalogue, row.problem, row.problem_params);
  const Params resolved = catalogue.methods.resolve(row.method, row.method_params);
  // Resolved, so that a case leaving dim at its default 1 does not match dim = 2's values.
  const Params problem_resolved = resolved_case_params(catalogue, row.problem, row.problem_params);
  const auto all = problem->published();
  // A range row names both ends at its one resolution.
  const bool range = row.bound == LedgerRow::Bound::range;
  for (std::size_t k = 0; k < (range ? row.paper.size() : row.nodes.size()); ++k) {
    const std::size_t i = range ? 0 : k;
    const double value = row.paper[k];
    std::vector<const PublishedValue*> found;
    for (const auto& pv : all)
      if (pv.source == row.published_source && pv.quantity == row.quantity &&
          pv.method == row.method && pv.nodes == row.nodes[i] &&
          params_match(resolved, pv.method_params) &&
          problem_params_match(problem_resolved, pv.problem_params))
        found.push_back(&pv);
    std::erase_if(found, [&](const PublishedValue* pv) { return pv->value != value; });
    if (found.empty())
      r.fail(row.line,
             fmt::format("row '{}': {} publishes no '{}' from '{}' for {} at {} nodes with the "
                         "value {}",
                         row.id, row.problem, row.quantity, row.published_source, row.method,
                         row.nodes[i], value),
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
    "tolerance", "compare", "measure", "statistic", "finding", "try", "check", "role",
    "follow"};

}  // namespace

bool ledger_internal::is_rate_measure(const std::string& m) {
  return m == "l2_rate" || m == "h1_rate" || m == "energy_rate";
}

namespace {

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
    std::vector<std::string> own = {"kind", "route", "refinement", "order"};
    for (const char* key : {"refinement", "order"})
      if (const auto* v = t.get(key)) {
        const auto x = number_of(*v);
        if (!x || !(*x > (std::string(key) == "refinement" ? 1.0 : 0.0)) || !std::isfinite(*x))
          r.fail(line_of(*v),
                 fmt::format("'{}' must be a finite number {}", key,
                             std::string(key) == "refinement" ? "> 1" : "> 0"),
                 "refinement = h over the check's h (2: half the step), order = the formal "
                 "order of the refined quantity");
        (std::string(key) == "refinement" ? c.refinement : c.order) = *x;
      }
    // A finding judged on an independent implementation's recorded studies
    // (verify/reference_studies.hpp): the second route that shares no code with ours.
    if (base.kind == LedgerRow::Kind::finding) own.insert(own.end(), {"reference", "studies"});
    c.row = variant_of(r, base, t, "check", own, manifest, catalogue);
    if (t.size() - t.contains("refinement") - t.contains("order") == 2)
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
    row.follow = get_string(r, *t, "follow", false, row.line);
    if (!row.follow.empty()) {
      const auto f = std::find_if(ledger.rows.begin(), ledger.rows.end(),
                                  [&](const LedgerRow& x) { return x.id == row.follow; });
      if (f == ledger.rows.end() || f->kind != LedgerRow::Kind::measure || row.measure.empty())
        r.fail(row.line, fmt::format("row '{}' follows '{}', which is no earlier measure row "
                                     "(or this row measures nothing)", row.id, row.follow),
               "name an earlier measure row of the same figure");
    }
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
    else if (compare == "range") row.bound = LedgerRow::Bound::range;
    else if (!compare.empty() && compare != "ratio")
      r.fail(row.line,
             fmt::format("compare = \"{}\" is not ratio, difference, at_least, at_most or range",
                         compare),
             "write compare = \"ratio\", \"difference\", \"at_least\", \"at_most\" or "
             "\"range\"");
    const std::string role = get_string(r, *t, "role", false, row.line);
    if (role == "check") row.role = LedgerRow::Role::check;
    else if (role == "cost") row.role = LedgerRow::Role::cost;
    else if (!role.empty() && role != "claim")
      r.fail(row.line, fmt::format("role = \"{}\" is not claim, check or cost", role),
             "write role = \"check\" for our own check of the suite (not a paper's claim), "
             "role = \"cost\" for a paper's claim about CPU time");

    // The kind, and what it needs.
    const int kinds = !row.published_source.empty() + !row.measure.empty() + !finding.empty();
    if (kinds > 1)
      r.fail(row.line, fmt::format("row '{}' mixes published, measure and finding", row.id),
             "give one kind per row");
    auto need_numbers = [&](std::size_t n) {
      if (row.bound == LedgerRow::Bound::range) {
        if (row.kind != LedgerRow::Kind::published || row.nodes.size() != 1 ||
            row.paper.size() != 2 || !(row.paper[0] < row.paper[1]))
          r.fail(row.line, fmt::format("range row '{}' needs one resolution and paper = [low, "
                                       "high] with low < high", row.id),
                 "write nodes = [n] and paper = [low, high]");
        if (!(row.tolerance > 0))
          r.fail(row.line, fmt::format("row '{}' states no tolerance", row.id),
                 "add tolerance = <relative tolerance at each end>");
        return;
      }
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

}  // namespace mfv
