#include "verify/baseline.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <set>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "methods/core/errors.hpp"
#include "verify/manifest.hpp"

namespace mfv {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

int line_of(const toml::node& n) { return static_cast<int>(n.source().begin.line); }

[[noreturn]] void fail(const std::filesystem::path& p, int line, const std::string& what) {
  throw InputError(fmt::format(
      "{}:{}: {}; the baseline is generated: re-run `mfv verify <manifest> --update-baseline`",
      p.string(), line, what));
}

double number(const std::filesystem::path& p, const toml::table& t, const std::string& key,
              int line) {
  const toml::node* n = t.get(key);
  if (!n) fail(p, line, fmt::format("missing '{}'", key));
  if (auto i = n->as_integer()) return static_cast<double>(i->get());
  // An inf or nan float would turn the drift check into a comparison that never fails.
  if (auto f = n->as_floating_point()) {
    if (!std::isfinite(f->get()))
      fail(p, line_of(*n), fmt::format("'{}' = {} is not finite", key, f->get()));
    return f->get();
  }
  // "Not measured" (a norm the problem does not compute, a checkpoint not reached) is the
  // string "nan", so that the file stays readable by any TOML reader.
  if (auto s = n->as_string(); s && s->get() == "nan") return kNaN;
  fail(p, line_of(*n), fmt::format("'{}' must be a number", key));
}

/// 17 significant digits: writing and re-reading a double is exact. A value that is not
/// finite is recorded as "nan" (no value): a baseline never holds an inf (load_baseline
/// refuses one).
std::string exact(double v) {
  if (!std::isfinite(v)) return "\"nan\"";
  std::string s = fmt::format("{:.17g}", v);
  // TOML needs a '.' or an exponent for a float.
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    // Control characters cannot stand in a TOML basic string: \uXXXX.
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      out += fmt::format("\\u{:04X}", static_cast<unsigned char>(c));
      continue;
    }
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

}  // namespace

Baseline load_baseline(const std::filesystem::path& path) {
  Baseline b;
  if (!std::filesystem::exists(path)) return b;
  const std::string text = detail::read_text_file(
      path, "baseline", "re-run `mfv verify <manifest> --update-baseline` to regenerate it");
  toml::table root;
  try {
    root = toml::parse(text, path.string());
  } catch (const toml::parse_error& e) {
    fail(path, static_cast<int>(e.source().begin.line), std::string(e.description()));
  }
  if (auto meta = root["meta"].as_table()) {
    if (auto s = (*meta)["suite"].value<std::string>()) b.suite = *s;
    if (auto m = (*meta)["machine"].value<std::string>()) b.machine = *m;
    if (meta->contains("reference_cpu_seconds"))
      b.reference_seconds = number(path, *meta, "reference_cpu_seconds", line_of(*meta));
  }
  const toml::table* cases = root["cases"].as_table();
  if (!cases) return b;
  for (const auto& [key, node] : *cases) {
    const auto* t = node.as_table();
    if (!t) fail(path, line_of(node), fmt::format("case '{}' must be a table", key.str()));
    const int line = line_of(node);
    BaselineCase c;
    c.l2_rate = number(path, *t, "l2_rate", line);
    c.h1_rate = number(path, *t, "h1_rate", line);
    const auto* res = t->get_as<toml::array>("resolutions");
    if (!res) fail(path, line, fmt::format("case '{}' has no 'resolutions' array", key.str()));
    for (const auto& r : *res) {
      const auto* rt = r.as_table();
      if (!rt) fail(path, line_of(r), "a resolution must be an inline table");
      BaselineEntry e;
      e.nodes = static_cast<int>(number(path, *rt, "nodes", line_of(r)));
      e.l2 = number(path, *rt, "l2", line_of(r));
      e.h1 = number(path, *rt, "h1", line_of(r));
      e.l2_rel = number(path, *rt, "l2_rel", line_of(r));
      e.h1_rel = number(path, *rt, "h1_rel", line_of(r));
      c.resolutions.push_back(e);
    }
    if (t->contains("cpu_seconds")) c.cpu_seconds = number(path, *t, "cpu_seconds", line);
    // Headlines per resolution: [cases."id".headline.<nodes>], "<key>" = value.
    if (const toml::node* h = t->get("headline")) {
      const auto* ht = h->as_table();
      if (!ht) fail(path, line_of(*h), fmt::format("case '{}': 'headline' must be a table", key.str()));
      for (const auto& [nodes_key, values] : *ht) {
        const std::string nk(nodes_key.str());
        const auto* vt = values.as_table();
        const bool digits = !nk.empty() && nk.size() < 10 &&
                            std::all_of(nk.begin(), nk.end(), [](char ch) { return ch >= '0' && ch <= '9'; });
        if (!digits || !vt)
          fail(path, line_of(values),
               fmt::format("case '{}': headline.{} must be a table named by a resolution's nodes",
                           key.str(), nk));
        const int nodes = std::stoi(nk);
        const auto e = std::find_if(c.resolutions.begin(), c.resolutions.end(),
                                    [&](const BaselineEntry& r) { return r.nodes == nodes; });
        if (e == c.resolutions.end())
          fail(path, line_of(values),
               fmt::format("case '{}': headline.{} names no resolution of the case", key.str(), nk));
        for (const auto& [hk, hv] : *vt) {
          (void)hv;
          e->headline[std::string(hk.str())] = number(path, *vt, std::string(hk.str()), line_of(values));
        }
      }
    }
    std::sort(c.resolutions.begin(), c.resolutions.end(),
              [](const auto& a, const auto& b) { return a.nodes < b.nodes; });
    b.cases.emplace(std::string(key.str()), std::move(c));
  }
  return b;
}

std::string baseline_to_toml(const Baseline& b) {
  std::string out =
      "# generated by `mfv verify <manifest> --update-baseline`; edit only by re-running it\n";
  out += fmt::format("[meta]\nsuite = {}\n", quoted(b.suite));
  if (!b.machine.empty()) out += fmt::format("machine = {}\n", quoted(b.machine));
  if (std::isfinite(b.reference_seconds))
    out += fmt::format("reference_cpu_seconds = {}\n", exact(b.reference_seconds));
  for (const auto& [id, c] : b.cases) {
    out += fmt::format("\n[cases.{}]\nl2_rate = {}\nh1_rate = {}\nresolutions = [\n", quoted(id),
                       exact(c.l2_rate), exact(c.h1_rate));
    for (const auto& e : c.resolutions)
      out += fmt::format("  {{ nodes = {}, l2 = {}, h1 = {}, l2_rel = {}, h1_rel = {} }},\n",
                         e.nodes, exact(e.l2), exact(e.h1), exact(e.l2_rel), exact(e.h1_rel));
    out += "]\n";
    if (std::isfinite(c.cpu_seconds)) out += fmt::format("cpu_seconds = {}\n", exact(c.cpu_seconds));
    for (const auto& e : c.resolutions) {
      if (e.headline.empty()) continue;
      out += fmt::format("\n[cases.{}.headline.{}]\n", quoted(id), e.nodes);
      for (const auto& [k, v] : e.headline) out += fmt::format("{} = {}\n", quoted(k), exact(v));
    }
  }
  return out;
}

BaselineCase baseline_from_study(const StudyResult& s) {
  BaselineCase c;
  c.l2_rate = s.cases.size() >= 2 ? s.rates.rate("L2") : kNaN;
  c.h1_rate = s.cases.size() >= 2 ? s.rates.rate("H1-semi") : kNaN;
  double cpu = 0;
  for (const auto& r : s.cases) {
    BaselineEntry e{r.spec.nodes, r.errors.l2, r.errors.h1_semi, r.errors.l2_rel,
                    r.errors.h1_semi_rel, {}};
    for (const auto& [k, v] : r.headline)
      if (!is_timing_headline(k)) e.headline[k] = std::isfinite(v) ? v : kNaN;
    c.resolutions.push_back(std::move(e));
    cpu += r.cpu.total();
  }
  c.cpu_seconds = s.cases.empty() || !std::isfinite(cpu) ? kNaN : cpu;
  std::sort(c.resolutions.begin(), c.resolutions.end(),
            [](const auto& a, const auto& b) { return a.nodes < b.nodes; });
  return c;
}

bool is_timing_headline(const std::string& key) {
  std::string lower;
  for (char ch : key) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return lower.find("cpu") != std::string::npos || lower.find("per second") != std::string::npos ||
         lower.find("steps/s") != std::string::npos;
}

std::string machine_note(const std::string& cpu, unsigned cores, int threads) {
  return fmt::format("{}, {} hardware threads, {} OpenMP threads", cpu.empty() ? "unknown CPU" : cpu,
                     cores, threads);
}

bool same_machine(const std::string& a, const std::string& b) {
  return !a.empty() && a == b && a.find("unknown CPU") == std::string::npos;
}

bool cpu_comparable(const std::string& a, const std::string& b) {
  // machine_note(): "<model>, <n> hardware threads, <t> OpenMP threads"; the model may hold
  // commas, the thread counts are the last two fields.
  auto threads = [](const std::string& note) -> std::string {
    const auto hw = note.rfind(" hardware threads, ");
    if (hw == std::string::npos) return "";
    const auto start = note.rfind(", ", hw);
    return start == std::string::npos ? "" : note.substr(start);
  };
  const std::string ta = threads(a);
  return !ta.empty() && ta == threads(b);
}

std::vector<Drift> check_drift(const std::string& case_id, const BaselineCase& base,
                               const BaselineCase& current, double tolerance, double floor) {
  std::vector<Drift> out;
  // How a move counts: an error is worse when larger, a rate when smaller; a headline has no
  // better direction, so every move beyond the tolerance is one to explain.
  enum class Worse { larger, smaller, any };
  auto add = [&](const std::string& metric, int nodes, double b, double c, double rel, bool worse,
                 bool lost, const std::string& what, Worse rule) {
    // `relative` is the magnitude (baseline.hpp); the message keeps the sign of the change.
    const std::string advice =
        rule == Worse::any ? "a headline moved beyond the tolerance: explain it, and if intended "
                             "run --update-baseline"
        : worse            ? "worse than the baseline"
                           : "better than the baseline; if intended, run --update-baseline";
    out.push_back(Drift{case_id, metric, nodes, b, c, std::abs(rel), worse, lost,
                        fmt::format("{}: {}{} {:.6g} -> {:.6g} ({}); {}", case_id, metric,
                                    what.empty() ? "" : " " + what, b, c,
                                    std::isnan(rel) ? std::string("NaN")
                                                    : fmt::format("{:+.2f}% change", 100 * rel),
                                    advice)});
  };
  // One rule for every number: a value that is not finite is no value, so inf or NaN against
  // a number is a drift (worse when it is the current one, or always for a headline), never a
  // NaN relative change that passes every tolerance. Errors and headlines below `floor` on
  // both sides are round-off; a rate's change is relative to max(1, |base|).
  auto compare = [&](const std::string& metric, int nodes, double b, double c, Worse rule) {
    const bool bn = !std::isfinite(b), cn = !std::isfinite(c);
    if (bn && cn) return;
    const std::string where = nodes > 0 ? fmt::format("at {} nodes", nodes) : "";
    if (bn || cn) {
      // A NaN error or rate is a measurement lost; a NaN headline is a value.
      add(metric, nodes, b, c, kNaN, rule == Worse::any || cn, cn && rule != Worse::any, where,
          rule);
      return;
    }
    const bool rate = rule == Worse::smaller;
    if (!rate && std::abs(b) < floor && std::abs(c) < floor) return;
    const double rel = (c - b) / (rate ? std::max(1.0, std::abs(b)) : std::max(std::abs(b), floor));
    if (!(std::abs(rel) > tolerance)) return;  // 0/0 (both exactly zero) is no change
    const bool worse = rule == Worse::any || (rule == Worse::larger ? c > b : c < b);
    add(metric, nodes, b, c, rel, worse, false, where, rule);
  };

  compare("l2_rate", 0, base.l2_rate, current.l2_rate, Worse::smaller);
  compare("h1_rate", 0, base.h1_rate, current.h1_rate, Worse::smaller);

  std::set<int> all;
  for (const auto& e : base.resolutions) all.insert(e.nodes);
  for (const auto& e : current.resolutions) all.insert(e.nodes);
  auto find = [](const BaselineCase& c, int n) -> const BaselineEntry* {
    for (const auto& e : c.resolutions)
      if (e.nodes == n) return &e;
    return nullptr;
  };
  for (int n : all) {
    const BaselineEntry* b = find(base, n);
    const BaselineEntry* c = find(current, n);
    if (!b || !c) {
      out.push_back(Drift{case_id, "resolution", n, kNaN, kNaN, kNaN, false, false,
                          fmt::format("{}: {} nodes is {}; the case's resolutions "
                                      "changed: run `mfv verify <manifest> --update-baseline`",
                                      case_id, n,
                                      b ? "in the baseline but not in this run"
                                        : "in this run but not in the baseline")});
      continue;
    }
    compare("l2", n, b->l2, c->l2, Worse::larger);
    compare("h1", n, b->h1, c->h1, Worse::larger);
    compare("l2_rel", n, b->l2_rel, c->l2_rel, Worse::larger);
    compare("h1_rel", n, b->h1_rel, c->h1_rel, Worse::larger);
    std::set<std::string> keys;
    for (const auto& [k, v] : b->headline) keys.insert(k);
    for (const auto& [k, v] : c->headline) keys.insert(k);
    const std::string where = fmt::format("at {} nodes", n);
    for (const auto& k : keys) {
      const std::string metric = "headline: " + k;
      const auto bi = b->headline.find(k), ci = c->headline.find(k);
      if (ci == c->headline.end()) {
        const bool finite = std::isfinite(bi->second);
        out.push_back(Drift{case_id, metric, n, bi->second, kNaN, kNaN, finite, finite,
                            fmt::format("{}: {} {}: in the baseline ({:.6g}), not measured by this "
                                        "run", case_id, metric, where, bi->second)});
      } else if (bi == b->headline.end()) {
        out.push_back(Drift{case_id, metric, n, kNaN, ci->second, kNaN, false, false,
                            fmt::format("{}: {} {}: new ({:.6g}), not in the baseline; if "
                                        "intended, run --update-baseline",
                                        case_id, metric, where, ci->second)});
      } else {
        compare(metric, n, bi->second, ci->second, Worse::any);
      }
    }
  }
  return out;
}

}  // namespace mfv
