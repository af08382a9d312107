#include "verify/results_json.hpp"

#include "reports/uncertainty.hpp"

#include "dynamics/external_solver.hpp"
#include "verify/provenance.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <map>
#include <set>
#include <string>

#include <fmt/format.h>

#include "analyses/report_section.hpp"
#include "analyses/analysis.hpp"

namespace mfv {

using nlohmann::json;

json JsonNumbers::number(double x, const std::string& pointer, const std::string& why) {
  if (std::isfinite(x)) return x;
  nulls_[pointer] = fmt::format("{}: {}", std::isnan(x) ? "NaN" : x > 0 ? "+inf" : "-inf", why);
  return nullptr;
}

json JsonNumbers::absent(const std::string& pointer, const std::string& why) {
  nulls_[pointer] = why;
  return nullptr;
}

namespace {

json params_json(const Params& p) {
  json out = json::object();
  for (const auto& [k, v] : p.values()) {
    if (const double* d = std::get_if<double>(&v)) {
      if (std::isfinite(*d)) out[k] = *d;
      else out[k] = format_value(v);  // a parameter is input: keep what was given, as text
    } else if (std::holds_alternative<std::vector<double>>(v)) {
      out[k] = format_value(v);  // "0:30:45", as a case gives it
    } else {
      out[k] = std::get<std::string>(v);
    }
  }
  return out;
}

/// JSON pointer escaping of one reference token (RFC 6901).
std::string token(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

/// The units headline names state in their last parentheses (every name of the default suite
/// was read, 2026-12-05): SI and the papers' scaled ones (a wavenumber in π/dx, a time in
/// dx/c, wave transits or sound crossings, Martin & Moyce's Z/a, H/a and T).
constexpr std::array<const char*, 28> kUnits = {
    "s", "ms", "m", "mm", "m/s", "1/s", "Pa", "MPa", "GPa", "N/m", "J", "J/m", "deg",
    "rad", "kg/s per m", "kg", "kg/m³", "T", "Z/a", "H/a", "pi/dx", "c pi/dx", "dx/c",
    "c kappa", "transits l/c", "crossings", "nominal strain", "m²"};

/// Greek letters and signs of headline names, spelled out in ASCII.
constexpr std::array<std::pair<const char*, const char*>, 16> kSpelled = {{
    {"σ", "sigma"}, {"θ", "theta"}, {"ε", "epsilon"}, {"ψ", "psi"}, {"ρ", "rho"},
    {"Δ", "delta"}, {"α", "alpha"}, {"β", "beta"}, {"ω", "omega"}, {"λ", "lambda"},
    {"μ", "mu"}, {"ν", "nu"}, {"τ", "tau"}, {"−", "minus"}, {"+", "plus"}, {"²", "2"}}};

/// The error norms of a case, each measured (as its analysis says) or null with the reason.
json norms_json(const ErrorNorms& e, int components, const MeasuredErrors& m,
                const std::string& at, JsonNumbers& n) {
  constexpr const char* kUndefined = "undefined (a zero or non-finite exact norm, or a blow-up)";
  auto pair = [&](const char* name, double abs, double rel) {
    const std::string p = at + "/" + name;
    const bool measured = m.has(name);
    return json{{"absolute", measured && m.absolute ? n.number(abs, p + "/absolute", kUndefined)
                                                    : n.absent(p + "/absolute", m.why_not)},
                {"relative", measured ? n.number(rel, p + "/relative", kUndefined)
                                      : n.absent(p + "/relative", m.why_not)}};
  };
  json out = {{"l2", pair("l2", e.l2, e.l2_rel)},
              {"h1_seminorm", pair("h1_seminorm", e.h1_semi, e.h1_semi_rel)},
              {"h1", pair("h1", e.h1, e.h1_rel)}};
  // 1D problems have no separate energy norm (it is the H1 seminorm); 2D ones do.
  if (components > 1) out["energy"] = pair("energy", e.energy, e.energy_rel);
  return out;
}

}  // namespace

json uncertainty_json(const Uncertainty& u) {
  json j = {{"levels", u.levels},
            {"class", convergence_class_name(u.cls)},
            {"assumed_order", u.assumed_order}};
  // Absent numbers were not estimated; why_none says why (no "nulls" entry per field).
  auto put = [&](const char* key, double v) {
    if (std::isfinite(v)) j[key] = v;
  };
  put("value", u.value);
  put("order", u.order);
  put("order_least_squares", u.order_least_squares);
  put("extrapolated", u.extrapolated);
  put("gci", u.gci);
  put("uncertainty", u.absolute);
  put("asymptotic_ratio", u.asymptotic);
  if (!u.method.empty()) j["method"] = u.method;
  if (!u.why_none.empty()) j["why_none"] = u.why_none;
  return j;
}

namespace {

json rates_json(const Rates& r, int components, const MeasuredErrors& m, const std::string& at,
                JsonNumbers& n) {
  constexpr const char* kWhy = "fewer than two resolutions with finite, non-zero errors";
  auto one = [&](const char* name, double ls, const std::vector<double>& pw) {
    const std::string p = at + "/" + name;
    json pairwise = json::array();
    if (!m.has(name))
      return json{{"least_squares", n.absent(p + "/least_squares", "no such error is measured")},
                  {"pairwise", pairwise}};
    for (std::size_t i = 0; i < pw.size(); ++i)
      pairwise.push_back(n.number(pw[i], fmt::format("{}/pairwise/{}", p, i), kWhy));
    return json{{"least_squares", n.number(ls, p + "/least_squares", kWhy)},
                {"pairwise", pairwise}};
  };
  json out = {{"l2", one("l2", r.rate("L2"), r.pairwise_of("L2"))},
              {"h1_seminorm", one("h1_seminorm", r.rate("H1-semi"), r.pairwise_of("H1-semi"))}};
  if (components > 1) out["energy"] = one("energy", r.rate("energy"), r.pairwise_of("energy"));
  return out;
}

bool contains_params(const Params& resolved, const Params& wanted) {
  for (const auto& [k, v] : wanted.values())
    if (!resolved.has(k) || format_value(resolved.values().at(k)) != format_value(v)) return false;
  return true;
}

/// The problem's published values this study measures, each with ours and the verdict of
/// problems/comparison.hpp under the value's own tolerance.
json published_json(const Registries& catalogue, const StudyResult& study, const std::string& at,
                    JsonNumbers& n) {
  json out = json::array();
  const CaseResult& first = study.cases.front();
  if (!catalogue.problems.contains(first.spec.problem)) return out;
  const auto problem = create_problem(catalogue, first.spec.problem, first.spec.problem_params);
  const Params pp = resolved_case_params(catalogue, first.spec.problem, first.spec.problem_params,
                                         first.analysis);
  for (const auto& pv : problem->published()) {
    if (pv.method != first.spec.method || !contains_params(first.method_params, pv.method_params))
      continue;
    bool same_problem = true;
    for (const auto& [k, v] : pv.problem_params.values())
      if (pp.has(k) && format_value(pp.values().at(k)) != format_value(v)) same_problem = false;
    if (!same_problem) continue;
    for (const auto& r : study.cases) {
      if (r.spec.nodes != pv.nodes) continue;
      const std::string p = fmt::format("{}/{}", at, out.size());
      const double ours = our_published_value(r, pv.quantity);
      const Comparison c = compare_value(ours, pv.value, pv.tolerance);
      out.push_back({{"source", pv.source},
                     {"quantity", pv.quantity},
                     {"nodes", pv.nodes},
                     {"paper", pv.value},
                     {"ours", n.number(ours, p + "/ours", "the case did not compute or reach it")},
                     {"ratio", n.number(c.ratio, p + "/ratio", "ours is missing or the paper's is 0")},
                     {"tolerance", pv.tolerance},
                     {"verdict", c.verdict},
                     {"note", pv.note}});
    }
  }
  return out;
}

/// Every finding of the studies' problems, checked on those studies: one group per problem
/// and set of problem parameters (the findings of a problem read its studies under the same
/// conditions), each finding matching its studies by method and parameters itself.
json findings_json(const Registries& catalogue, const std::vector<StudyResult>& studies) {
  json out = json::array();
  std::vector<std::pair<std::string, Params>> groups;
  auto key = [](const StudyResult& s) {
    return std::make_pair(s.cases.front().spec.problem, s.cases.front().spec.problem_params);
  };
  for (const auto& s : studies) {
    if (s.cases.empty()) continue;
    const auto k = key(s);
    if (std::none_of(groups.begin(), groups.end(), [&](const auto& g) {
          return g.first == k.first && g.second.to_string() == k.second.to_string();
        }))
      groups.push_back(k);
  }
  for (const auto& [name, params] : groups) {
    if (!catalogue.problems.contains(name)) continue;
    std::vector<StudyResult> mine;
    for (const auto& s : studies)
      if (!s.cases.empty() && key(s).first == name &&
          key(s).second.to_string() == params.to_string())
        mine.push_back(s);
    const auto problem = create_problem(catalogue, name, params);
    const auto findings = problem->findings();
    for (const auto& o : check_findings(catalogue, findings, mine)) {
      json f = {{"problem", name},
                {"id", o.finding->id},
                {"source", o.finding->source},
                {"claim", o.finding->claim},
                {"criterion", o.finding->criterion},
                {"verdict", o.verdict.status},
                {"ours", o.verdict.ours}};
      if (!params.values().empty()) f["problem_params"] = params.to_string();
      if (!o.ran.empty()) f["ran"] = o.ran;
      out.push_back(std::move(f));
    }
  }
  return out;
}

json run_json(const RunInfo& run) {
  return {{"kind", run.kind},
          {"generated_utc", run.generated_utc},
          {"machine", {{"cores", run.cores}}},
          {"wall_seconds", run.wall_seconds},
          {"cpu_seconds", run.cpu_seconds},
          // Plugin libraries whose kernels, methods or problems the run could use.
          {"plugins", run.plugins},
          // What built the numbers and where they ran: two runs' numbers are comparable only
          // when these say so (issue 28).
          {"provenance", provenance_json(provenance())}};
}

}  // namespace

std::string headline_id(const std::string& name) {
  std::string words;
  auto separate = [&words] {
    if (!words.empty() && words.back() != '_') words += '_';
  };
  for (std::size_t i = 0; i < name.size();) {
    bool spelled = false;
    for (const auto& [sign, word] : kSpelled) {
      const std::size_t len = std::char_traits<char>::length(sign);
      if (name.compare(i, len, sign) == 0) {
        separate();
        words += word;
        separate();
        i += len;
        spelled = true;
        break;
      }
    }
    if (spelled) continue;
    const unsigned char c = static_cast<unsigned char>(name[i]);
    if (std::isalnum(c) && c < 0x80) {
      words += static_cast<char>(std::tolower(c));
    } else if (c == '/') {
      separate();
      words += "per";
      separate();
    } else {
      separate();
    }
    ++i;
  }
  while (!words.empty() && words.back() == '_') words.pop_back();
  return words.empty() ? std::string("headline") : words;
}

std::string headline_unit(const std::string& name) {
  const std::size_t open = name.rfind('(');
  if (open == std::string::npos) return "";
  const std::size_t close = name.find(')', open);
  if (close == std::string::npos) return "";
  const std::string inside = name.substr(open + 1, close - open - 1);
  for (const char* u : kUnits)
    if (inside == u) return inside;
  return "";
}

json study_json(const Registries& catalogue, const StudyResult& study, const std::string& at,
                JsonNumbers& n) {
  json out = json::object();
  out["label"] = study.label;
  if (study.cases.empty()) return out;
  const CaseResult& first = study.cases.front();
  const int comps = first.components;
  out["problem"] = first.spec.problem;
  out["problem_params"] = params_json(first.spec.problem_params);
  out["method"] = first.spec.method;
  out["method_params"] = params_json(first.method_params);
  out["method_description"] = first.method_description;
  out["dim"] = first.dim;
  out["components"] = comps;
  out["resolution_name"] = catalogue.problems.contains(first.spec.problem)
                               ? create_problem(catalogue, first.spec.problem,
                                                first.spec.problem_params)
                                     ->resolution_name()
                               : "nodes";
  out["perturbation"] = first.spec.perturbation;
  // The headline names of every resolution with their stable ids and stated units.
  {
    std::map<std::string, std::string> ids;  // name → id, unique within the study
    std::set<std::string> taken;
    for (const auto& r : study.cases)
      for (const auto& [k, v] : r.headline) {
        if (ids.contains(k)) continue;
        std::string id = headline_id(k);
        for (int suffix = 2; taken.contains(id); ++suffix) id = fmt::format("{}_{}", headline_id(k), suffix);
        taken.insert(id);
        ids[k] = id;
      }
    json headlines = json::array();
    for (const auto& [k, id] : ids)
      headlines.push_back({{"name", k}, {"id", id}, {"unit", headline_unit(k)}});
    out["headlines"] = headlines;
  }
  json resolutions = json::array();
  for (std::size_t i = 0; i < study.cases.size(); ++i) {
    const CaseResult& r = study.cases[i];
    const std::string p = fmt::format("{}/resolutions/{}", at, i);
    json res = {{"nodes", r.spec.nodes},
                {"particles", r.particles},
                {"h", n.number(r.h, p + "/h", "no particle spacing")},
                {"quadrature_points", r.quadrature_points}};
    const MeasuredErrors m = catalogue.analyses.create(analysis_of(catalogue, r))->measured_errors();
    res["errors"] = {{"common", norms_json(r.errors, comps, m, p + "/errors/common", n)},
                     {"paper", norms_json(r.errors_paper, comps, m, p + "/errors/paper", n)}};
    json headline = json::object();
    for (const auto& [k, v] : r.headline)
      headline[k] = n.number(v, p + "/headline/" + token(k),
                             "the run did not reach or could not define it");
    res["headline"] = headline;
    res["cpu_seconds"] = {{"setup", n.number(r.cpu.setup, p + "/cpu_seconds/setup", "not timed")},
                          {"assembly", n.number(r.cpu.assembly, p + "/cpu_seconds/assembly", "not timed")},
                          {"solve", n.number(r.cpu.solve, p + "/cpu_seconds/solve", "not timed")},
                          {"total", n.number(r.cpu.total(), p + "/cpu_seconds/total", "not timed")}};
    if (const StaticSolveData* st = r.find<StaticSolveData>(); st && !st->solve.solver.empty())
      res["solver"] = {{"name", st->solve.solver},
                       {"unknowns", st->solve.unknowns},
                       {"nonzeros", st->solve.nonzeros},
                       {"residual", n.number(st->solve.residual, p + "/solver/residual", "no solve")},
                       {"rcond", n.number(st->solve.rcond, p + "/solver/rcond", "not estimated by this solver")},
                       {"condition", n.number(st->solve.condition, p + "/solver/condition",
                                             "not computed (dense SVD only up to 1,200 "
                                             "unknowns) or singular")}};
    if (const TransientData* t = r.find<TransientData>())
      res["transient"] = {{"dt", n.number(t->dt, p + "/transient/dt", "no step")},
                          {"dt_critical",
                           n.number(t->dt_critical, p + "/transient/dt_critical", "not estimated")},
                          {"end_time", n.number(t->end_time, p + "/transient/end_time", "not reached")},
                          {"steps", t->steps},
                          {"dynamics", t->dynamics}};
    if (const TransientData* t = r.find<TransientData>(); t && t->external)
      res["transient"]["external"] = {{"solver", t->external->solver},
                                      {"protocol", kExternalProtocol},
                                      {"command", t->external->command},
                                      {"wall_seconds", t->external->wall_seconds},
                                      {"cpu_seconds", t->external->cpu_seconds},
                                      {"frames", t->external->frames},
                                      {"solver_steps", t->external->solver_steps},
                                      {"stdout_tail", t->external->stdout_tail},
                                      {"stderr_tail", t->external->stderr_tail}};
    const FigureData* fig = r.find<FigureData>();
    res["verdicts"] = fig ? fig->verdicts : std::vector<std::string>{};
    resolutions.push_back(std::move(res));
  }
  out["resolutions"] = std::move(resolutions);
  out["published"] = published_json(catalogue, study, at + "/published", n);
  const MeasuredErrors m =
      catalogue.analyses.create(analysis_of(catalogue, first))->measured_errors();
  out["rates"] = {{"common", rates_json(study.rates, comps, m, at + "/rates/common", n)},
                  {"paper", rates_json(study.rates_paper, comps, m, at + "/rates/paper", n)}};
  // The finest resolution's discretization uncertainty (reports/uncertainty.hpp): of each
  // relative error the analysis measures (common rule) and of each headline.
  {
    std::vector<double> h;
    for (const auto& c : study.cases) h.push_back(c.h);
    auto series = [&](auto pick) {
      std::vector<double> v;
      for (const auto& c : study.cases) v.push_back(pick(c));
      return v;
    };
    json errors = json::object();
    if (m.has("l2"))
      errors["l2"] = uncertainty_json(grid_uncertainty(h, series([](const CaseResult& c) { return c.errors.l2_rel; })));
    if (m.has("h1_seminorm"))
      errors["h1_seminorm"] = uncertainty_json(
          grid_uncertainty(h, series([](const CaseResult& c) { return c.errors.h1_semi_rel; })));
    if (comps > 1 && m.has("energy"))
      errors["energy"] = uncertainty_json(
          grid_uncertainty(h, series([](const CaseResult& c) { return c.errors.energy_rel; })));
    json headlines = json::object();
    for (const auto& [name, v0] : first.headline) {
      (void)v0;
      headlines[headline_id(name)] = uncertainty_json(grid_uncertainty(
          h, series([&name = name](const CaseResult& c) {
            const auto it = c.headline.find(name);
            return it == c.headline.end() ? NAN : it->second;
          })));
    }
    out["uncertainty"] = {{"errors", errors}, {"headlines", headlines}};
  }
  return out;
}

std::string results_json(const Registries& catalogue, const RunInfo& run,
                         const std::vector<StudyResult>& studies,
                         const std::vector<std::string>& failures) {
  JsonNumbers n;
  json doc = {{"schema", kResultsSchema}, {"run", run_json(run)}};
  json list = json::array();
  for (std::size_t i = 0; i < studies.size(); ++i)
    list.push_back(study_json(catalogue, studies[i], fmt::format("/studies/{}", i), n));
  doc["studies"] = std::move(list);
  doc["findings"] = findings_json(catalogue, studies);
  doc["failures"] = failures;
  doc["nulls"] = n.nulls();
  return doc.dump(1) + "\n";
}

json ledger_json(const Ledger& ledger, const std::vector<LedgerEntry>& entries,
                 const std::string& at, JsonNumbers& n) {
  json counts = json::object();
  for (const auto& [verdict, count] : count_verdicts(entries)) counts[verdict] = count;
  json check_counts = json::object();
  for (const auto& [verdict, count] : count_verdicts(entries, LedgerRow::Role::check))
    check_counts[verdict] = count;
  json cost_counts = json::object();
  for (const auto& [verdict, count] : count_verdicts(entries, LedgerRow::Role::cost))
    cost_counts[verdict] = count;
  json rows = json::array();
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const LedgerEntry& e = entries[i];
    const LedgerRow& row = *e.row;
    const std::string p = fmt::format("{}/rows/{}", at, i);
    static const char* kKinds[] = {"published", "measure", "finding", "open"};
    json r = {{"id", row.id},
              {"source", row.source},
              {"claim", row.claim},
              {"kind", kKinds[static_cast<int>(row.kind)]},
              {"verdict", e.verdict},
              {"why", e.why}};
    if (!row.cases.empty()) r["cases"] = row.cases;
    if (!row.problem.empty()) r["problem"] = row.problem;
    if (!row.finding.empty()) r["finding"] = row.finding;
    if (!row.measure.empty()) r["measure"] = row.measure;
    if (!row.quantity.empty()) r["quantity"] = row.quantity;
    if (!row.nodes.empty()) r["nodes"] = row.nodes;
    if (!row.reading.empty()) r["reading"] = row.reading;
    if (!row.reason.empty()) r["reason"] = row.reason;
    r["paper"] = row.paper;
    if (row.kind == LedgerRow::Kind::published || row.kind == LedgerRow::Kind::measure) {
      r["tolerance"] = row.tolerance;
      r["compare"] = row.bound == LedgerRow::Bound::range      ? "range"
                     : row.bound == LedgerRow::Bound::at_least ? "at_least"
                     : row.bound == LedgerRow::Bound::at_most ? "at_most"
                     : row.compare == CompareBy::ratio        ? "ratio"
                                                              : "difference";
      json ours = json::array(), ratio = json::array(), diff = json::array();
      for (std::size_t k = 0; k < e.ours.size(); ++k)
        ours.push_back(n.number(e.ours[k], fmt::format("{}/ours/{}", p, k),
                                e.why.empty() ? e.verdict : e.verdict + ": " + e.why));
      for (std::size_t k = 0; k < e.compared.size(); ++k) {
        ratio.push_back(n.number(e.compared[k].ratio, fmt::format("{}/ratio/{}", p, k),
                                 "ours is missing or the paper's value is 0"));
        diff.push_back(n.number(e.compared[k].difference, fmt::format("{}/difference/{}", p, k),
                                "ours is missing"));
      }
      r["ours"] = ours;
      r["ratio"] = ratio;
      r["difference"] = diff;
    }
    if (row.kind == LedgerRow::Kind::finding) {
      r["criterion"] = e.criterion;
      r["ours_text"] = e.ours_text;
    }
    // Discretization uncertainty of ours, per value (reports/uncertainty.hpp).
    {
      const LedgerReadingOutcome& c = e.readings[e.chosen];
      json us = json::array();
      for (const Uncertainty& u : c.uncertainty) us.push_back(uncertainty_json(u));
      r["uncertainty"] = us;
      // null where ours has no uncertainty: inside or not is then not known.
      json inside = json::array();
      for (std::size_t i = 0; i < c.paper_inside.size(); ++i)
        inside.push_back(i < c.uncertainty.size() && c.uncertainty[i].known()
                             ? json(bool(c.paper_inside[i]))
                             : json());
      r["paper_inside"] = inside;
      if (row.kind == LedgerRow::Kind::finding) {
        r["uncertainty_of"] = c.uncertainty_of;
        json numbers = json::array();
        auto finite_or_null = [](const std::vector<double>& xs) {
          json a = json::array();
          for (double x : xs) a.push_back(std::isfinite(x) ? json(x) : json(nullptr));
          return a;
        };
        for (const FindingNumber& n : c.numbers)
          numbers.push_back(
              {{"name", n.name}, {"h", finite_or_null(n.h)}, {"values", finite_or_null(n.values)}});
        r["numbers"] = numbers;
      }
      if (e.source) r["source_group"] = e.source->name;
    }
    r["role"] = row.role == LedgerRow::Role::check  ? "check"
                : row.role == LedgerRow::Role::cost ? "cost"
                                                    : "claim";
    r["paper_id"] = ledger_paper(row);
    r["section"] = ledger_section(row);
    if (!row.quote.empty()) r["quote"] = row.quote;
    r["evidence"] = e.evidence;
    r["reading_used"] = e.reading;
    // The reading search: every reading tried (the row's own first) and its checks.
    const bool values = row.kind == LedgerRow::Kind::published || row.kind == LedgerRow::Kind::measure;
    json readings = json::array();
    for (std::size_t k = 0; k < e.readings.size(); ++k) {
      const LedgerReadingOutcome& o = e.readings[k];
      const std::string rp = fmt::format("{}/readings/{}", p, k);
      json rd = {{"name", o.name()},
                 {"own", o.reading == nullptr},
                 {"fitted", o.reading != nullptr && o.reading->fitted},
                 {"chosen", k == e.chosen},
                 {"verdict", o.verdict},
                 {"evidence", o.evidence},
                 {"cases", o.row->cases}};
      const std::string quote = o.reading ? o.reading->quote : row.quote;
      if (!quote.empty()) rd["quote"] = quote;
      if (!o.why.empty()) rd["why"] = o.why;
      if (o.row->kind == LedgerRow::Kind::published) {
        rd["nodes"] = o.row->nodes;
        rd["quantity"] = o.row->quantity;
      }
      if (o.row->kind == LedgerRow::Kind::measure) {
        rd["measure"] = o.row->measure;
        if (!o.from_case.empty()) rd["from_case"] = o.from_case;
        rd["statistic"] = o.row->statistic == RateStatistic::finest_pair ? "finest_pair"
                          : o.row->statistic == RateStatistic::best_pair ? "best_pair"
                                                                         : "least_squares";
      }
      if (o.row->kind == LedgerRow::Kind::finding) {
        rd["finding"] = o.row->problem + ":" + o.row->finding;
        rd["ours_text"] = o.ours_text;
      }
      if (values) {
        json ours = json::array(), ratio = json::array();
        for (std::size_t i = 0; i < o.ours.size(); ++i)
          ours.push_back(n.number(o.ours[i], fmt::format("{}/ours/{}", rp, i),
                                  o.why.empty() ? o.verdict : o.verdict + ": " + o.why));
        for (std::size_t i = 0; i < o.compared.size(); ++i)
          ratio.push_back(n.number(o.compared[i].ratio, fmt::format("{}/ratio/{}", rp, i),
                                   "ours is missing or the paper's value is 0"));
        rd["ours"] = ours;
        rd["ratio"] = ratio;
      }
      json checks = json::array();
      for (std::size_t c = 0; c < o.checks.size(); ++c) {
        const LedgerCheckOutcome& co = o.checks[c];
        json cj = {{"kind", co.check->kind == LedgerCheck::Kind::independent ? "independent"
                                                                             : "converged"},
                   {"route", co.check->route},
                   {"cases", co.check->row->cases},
                   {"verdict", co.verdict},
                   {"agrees", co.agrees}};
        if (co.check->row->kind == LedgerRow::Kind::finding) {
          cj["finding"] = co.check->row->problem + ":" + co.check->row->finding;
          cj["ours_text"] = co.ours_text;
        } else {
          json vals = json::array();
          for (std::size_t i = 0; i < co.values.size(); ++i)
            vals.push_back(n.number(co.values[i], fmt::format("{}/checks/{}/values/{}", rp, c, i),
                                    "the check gave no finite value: " + co.ours_text));
          cj["values"] = vals;
          if (co.check->row->kind == LedgerRow::Kind::published) cj["nodes"] = co.check->row->nodes;
        }
        checks.push_back(std::move(cj));
      }
      rd["checks"] = checks;
      readings.push_back(std::move(rd));
    }
    r["readings"] = readings;
    rows.push_back(std::move(r));
  }
  const UncertaintyCoverage cov = uncertainty_coverage(entries);
  return {{"ledger_file", ledger.path.string()},
          {"counts", counts},
          {"check_counts", check_counts},
          {"cost_counts", cost_counts},
          {"uncertainty_coverage",
           {{"converged", cov.converged}, {"some", cov.some}, {"every", cov.every}}},
          {"rows", rows}};
}

std::string ledger_json_text(const Ledger& ledger, const std::vector<LedgerEntry>& entries) {
  JsonNumbers n;
  json doc = ledger_json(ledger, entries, "", n);
  doc["schema"] = kLedgerSchema;
  doc["nulls"] = n.nulls();
  return doc.dump(1) + "\n";
}

std::string verify_results_json(const Registries& catalogue, const RunInfo& run,
                                const std::string& suite, const std::string& manifest,
                                bool full, const std::vector<VerifyCaseJson>& cases,
                                const Ledger* ledger, const std::vector<LedgerEntry>& entries,
                                const VerifyTimingJson* timing,
                                const std::map<std::string, int>& failed_by) {
  JsonNumbers n;
  json doc = {{"schema", kResultsSchema}, {"run", run_json(run)}};
  doc["suite"] = {{"name", suite}, {"manifest", manifest}, {"full", full}};
  int failed = 0;
  json list = json::array(), studies = json::array();
  for (const auto& c : cases) {
    if (c.verdict != "PASS") ++failed;
    json j = {{"id", c.id},           {"problem", c.problem}, {"method", c.method},
              {"nodes", c.nodes},     {"bands", c.bands},     {"baseline", c.baseline},
              {"verdict", c.verdict}, {"messages", c.messages},
              {"failed_kinds", c.failed_kinds}};
    // Present only where the CPU was judged (regression.timing says why not otherwise).
    if (std::isfinite(c.cpu_ratio)) j["cpu_ratio"] = c.cpu_ratio;
    if (std::isfinite(c.cpu_relative)) j["cpu_relative"] = c.cpu_relative;
    if (c.study) {
      j["study"] = studies.size();
      studies.push_back(
          study_json(catalogue, *c.study, fmt::format("/studies/{}", studies.size()), n));
    } else {
      j["study"] = nullptr;
      j["error"] = c.error;
    }
    list.push_back(std::move(j));
  }
  doc["regression"] = {{"status", failed == 0 ? "PASS" : "FAIL"},
                       {"failed", failed},
                       {"cases", cases.size()},
                       {"failed_by", failed_by},
                       {"meaning", "against the manifest's bands and the baseline: no "
                                   "regression; says nothing about reproducing the papers "
                                   "(that is the ledger)"}};
  if (timing) {
    const VerifyTimingJson& t = *timing;
    const std::string at = "/regression/timing";
    auto num = [&](double x, const std::string& key, const std::string& why) {
      return std::isfinite(x) ? json(x) : n.absent(at + "/" + key, why);
    };
    doc["regression"]["timing"] = {
        {"factor", num(t.factor, "factor", "no machine factor: " + t.why_unknown)},
        {"rule", t.rule},
        {"median", num(t.median, "median", "too few cases with a baseline CPU time")},
        {"median_cases", t.median_cases},
        {"reference_ratio",
         num(t.reference_ratio, "reference_ratio", "the reference workload is not in the baseline")},
        {"reference_seconds", num(t.reference_seconds, "reference_seconds", "not measured")},
        {"baseline_reference_seconds",
         num(t.baseline_reference_seconds, "baseline_reference_seconds", "not in the baseline")},
        {"load_average_start",
         num(t.load_start >= 0 ? t.load_start : NAN, "load_average_start", "unknown")},
        {"load_average_end", num(t.load_end >= 0 ? t.load_end : NAN, "load_average_end", "unknown")},
        {"steal_fraction", num(t.steal, "steal_fraction", "/proc/stat not readable")},
        {"gated", t.gated},
        {"slower", t.slower},
        {"status", t.status}};
  }
  doc["cases"] = std::move(list);
  doc["studies"] = std::move(studies);
  doc["failures"] = json::array();
  for (const auto& c : cases)
    if (!c.study) doc["failures"].push_back(fmt::format("{}: {}", c.id, c.error));
  doc["ledger"] = ledger ? ledger_json(*ledger, entries, "/ledger", n) : json(nullptr);
  doc["nulls"] = n.nulls();
  return doc.dump(1) + "\n";
}

}  // namespace mfv
