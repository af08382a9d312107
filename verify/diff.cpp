#include "verify/diff.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "methods/core/errors.hpp"
#include "verify/ledger.hpp"

namespace mfv {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

double number_of(const json& j) { return j.is_number() ? j.get<double>() : NAN; }

/// Throughput and timing headlines measure the machine: not compared.
bool machine_measure(const std::string& key) {
  return key.find("per second") != std::string::npos || key.find("CPU") != std::string::npos ||
         key.find("cpu") != std::string::npos;
}

RunRecord flatten(const json& run) {
  RunRecord f;
  const json& studies = run.at("studies");
  static const std::pair<const char*, const char*> kNorms[] = {
      {"l2", "L2"}, {"h1", "H1"}, {"h1_seminorm", "H1-seminorm"}, {"energy", "energy"}};
  for (const json& c : run.at("cases")) {
    const std::string id = c.at("id").get<std::string>();
    if (f.numbers.count(id)) continue;  // an id twice (hand-edited file): the first counts
    f.order.push_back(id);
    f.case_verdicts[id] = c.value("verdict", "");
    auto& q = f.numbers[id];
    if (!c.contains("study") || c.at("study").is_null()) continue;
    const json& s = studies.at(c.at("study").get<std::size_t>());
    if (!s.contains("resolutions")) continue;
    double cpu = 0;
    for (const json& r : s.at("resolutions")) {
      if (r.contains("cpu_seconds")) cpu += number_of(r.at("cpu_seconds").value("total", json()));
      const std::string at = fmt::format(" at {} nodes", r.at("nodes").get<long>());
      if (r.contains("errors") && r.at("errors").contains("common"))
        for (const auto& [key, name] : kNorms)
          if (r.at("errors").at("common").contains(key))
            q[fmt::format("{} relative error{}", name, at)] = {
                number_of(r.at("errors").at("common").at(key).at("relative")), -1};
      if (r.contains("headline"))
        for (const auto& [k, v] : r.at("headline").items())
          if (!machine_measure(k)) q[k + at] = {number_of(v), 0};
    }
    f.cpu_seconds[id] = cpu;
    if (s.contains("rates") && s.at("rates").contains("common"))
      for (const auto& [key, name] : kNorms)
        if (s.at("rates").at("common").contains(key))
          q[fmt::format("{} rate (least squares)", name)] = {
              number_of(s.at("rates").at("common").at(key).at("least_squares")), +1};
  }
  if (run.contains("ledger") && run.at("ledger").is_object())
    for (const json& row : run.at("ledger").at("rows"))
      f.ledger_verdicts[row.at("id").get<std::string>()] = row.value("verdict", "");
  return f;
}

std::string label_of(const json& run) {
  const json& r = run.at("run");
  std::string commit = "commit not recorded";
  if (r.contains("provenance")) {
    const json& p = r.at("provenance");
    commit = "commit " + p.value("commit", std::string("unknown")).substr(0, 12) +
             (p.value("dirty", false) ? "+changes" : "");
  }
  return fmt::format("{}, {}", r.value("generated_utc", std::string("time not recorded")), commit);
}

std::string number_text(double v) { return std::isfinite(v) ? fmt::format("{:.4g}", v) : "–"; }

/// Rank of a ledger verdict: lower is closer to the paper; "not yet built" (and a word the
/// ledger does not know) is not comparable (-1). "not run" never gets here: diff_runs counts
/// those rows apart.
int ledger_rank(const std::string& v) {
  const auto& all = ledger_verdicts();
  const auto it = std::find(all.begin(), all.end(), v);
  if (it == all.end() || v == kNotYetBuilt) return -1;
  return static_cast<int>(it - all.begin());
}

}  // namespace

int RunDiff::worse() const {
  int n = 0;
  for (const auto& e : numbers) n += e.direction == DiffEntry::Direction::worse;
  for (const auto& e : verdicts) n += e.direction == DiffEntry::Direction::worse;
  return n;
}

int RunDiff::better() const {
  int n = 0;
  for (const auto& e : numbers) n += e.direction == DiffEntry::Direction::better;
  for (const auto& e : verdicts) n += e.direction == DiffEntry::Direction::better;
  return n;
}

json load_run_results(const fs::path& path) {
  std::error_code ec;
  const fs::path file = fs::is_directory(path, ec) ? path / "results.json" : path;
  // A regular file of a size a verify run writes (the default suite's is a few MB): a FIFO
  // would block diff for ever, a 300 MB file took 1.3 GB to parse.
  constexpr std::uintmax_t kMaxResultsBytes = std::uintmax_t{256} << 20;
  if (const auto st = fs::status(file, ec); !ec && fs::exists(st) && !fs::is_regular_file(st))
    throw InputError(fmt::format("mfv diff: '{}' is not a regular file; give a verify report "
                                 "directory or its results.json",
                                 file.string()));
  if (const auto size = fs::file_size(file, ec); !ec && size > kMaxResultsBytes)
    throw InputError(fmt::format("mfv diff: '{}' is {} MB, larger than any results.json mfv "
                                 "writes ({} MB at most); give a verify run's results.json",
                                 file.string(), size >> 20, kMaxResultsBytes >> 20));
  std::ifstream in(file);
  if (!in)
    throw InputError(fmt::format("mfv diff: cannot read '{}'; give a verify report directory or "
                                 "its results.json",
                                 file.string()));
  json j;
  try {
    in >> j;
  } catch (const json::exception& e) {
    throw InputError(fmt::format("mfv diff: '{}' is not JSON ({}); give a results.json that "
                                 "mfv verify wrote",
                                 file.string(), e.what()));
  }
  if (!j.is_object() || !j.contains("cases") || !j.contains("studies") || !j.contains("run") ||
      !j.at("cases").is_array())
    throw InputError(fmt::format("mfv diff: '{}' is not the results.json of an `mfv verify` run "
                                 "(no cases); diff compares two verification runs",
                                 file.string()));
  return j;
}

RunRecord run_record(const json& results) {
  try {
    RunRecord r = flatten(results);
    r.label = label_of(results);
    if (results.contains("suite") && results.at("suite").is_object())
      r.suite = results.at("suite").value("name", std::string());
    return r;
  } catch (const json::exception& e) {
    throw InputError(fmt::format("mfv diff: a results.json does not have the layout of "
                                 "docs/schemas/results.schema.json ({})",
                                 e.what()));
  }
}

RunDiff diff_runs(const json& before, const json& after, const DiffOptions& o) {
  return diff_runs(run_record(before), run_record(after), o);
}

RunDiff diff_runs(const RunRecord& before, const RunRecord& after, const DiffOptions& o) {
  RunDiff d;
  d.before_label = before.label;
  d.after_label = after.label;
  RunRecord a = before, b = after;
  // Membership by the case lists (a case that could not run has verdicts but no numbers).
  const std::set<std::string> in_a(a.order.begin(), a.order.end()),
      in_b(b.order.begin(), b.order.end());
  for (const auto& id : b.order)
    if (!in_a.count(id)) d.added.push_back(id);
  for (const auto& id : a.order)
    if (!in_b.count(id)) d.removed.push_back(id);
  using Dir = DiffEntry::Direction;
  for (const auto& id : a.order) {
    if (!in_b.count(id)) continue;
    const auto& va = a.case_verdicts[id];
    const auto& vb = b.case_verdicts[id];
    if (va != vb)
      d.verdicts.push_back({vb == "FAIL" ? Dir::worse : vb == "PASS" ? Dir::better : Dir::moved, id,
                            "regression verdict", va, vb, 0});
    const auto& qa = a.numbers[id];
    const auto& qb = b.numbers[id];
    for (const auto& [name, x] : qa) {
      const auto it = qb.find(name);
      if (it == qb.end()) continue;  // not measured by B's resolutions: nothing to compare
      const double y = it->second.value;
      const bool fa = std::isfinite(x.value), fb = std::isfinite(y);
      if (!fa && !fb) continue;
      if (fa != fb) {
        // A measurement lost is worse whatever its sense; one gained is better.
        d.numbers.push_back({fa ? Dir::worse : Dir::better, id, name, number_text(x.value),
                             number_text(y), fa ? -INFINITY : INFINITY});
        continue;
      }
      if (std::abs(x.value) < o.floor && std::abs(y) < o.floor) continue;
      const double rel = (y - x.value) / std::max(std::abs(x.value), o.floor);
      if (!(std::abs(rel) > o.tolerance)) continue;
      const Dir dir = x.sense == 0                     ? Dir::moved
                      : (rel > 0) == (x.sense > 0)     ? Dir::better
                                                       : Dir::worse;
      d.numbers.push_back({dir, id, name, number_text(x.value), number_text(y), rel});
    }
  }
  for (const auto& [row, va] : a.ledger_verdicts) {
    const auto it = b.ledger_verdicts.find(row);
    if (it == b.ledger_verdicts.end() || it->second == va) continue;
    if (va == kNotRun || it->second == kNotRun) {
      d.ledger_not_compared.push_back(row);
      continue;
    }
    const int ra = ledger_rank(va), rb = ledger_rank(it->second);
    const Dir dir = ra < 0 || rb < 0 ? Dir::moved : rb > ra ? Dir::worse : Dir::better;
    d.verdicts.push_back({dir, "", "ledger " + row, va, it->second, 0});
  }
  // Worst first: the largest relative moves lead.
  std::stable_sort(d.numbers.begin(), d.numbers.end(), [](const auto& x, const auto& y) {
    if (x.direction != y.direction) return x.direction < y.direction;
    return std::abs(x.relative) > std::abs(y.relative);
  });
  std::stable_sort(d.verdicts.begin(), d.verdicts.end(),
                   [](const auto& x, const auto& y) { return x.direction < y.direction; });
  return d;
}

std::string diff_text(const RunDiff& d, bool md) {
  auto count = [](const std::vector<DiffEntry>& v, DiffEntry::Direction dir) {
    return std::count_if(v.begin(), v.end(), [&](const auto& e) { return e.direction == dir; });
  };
  using Dir = DiffEntry::Direction;
  std::string out;
  const long moved = count(d.numbers, Dir::moved) + count(d.verdicts, Dir::moved);
  const std::string summary = fmt::format(
      "{} worse, {} better, {} moved (direction not known), {} case(s) added, {} removed",
      d.worse(), d.better(), moved, d.added.size(), d.removed.size());
  out += md ? fmt::format("Before: {}. After: {}.\n\n**{}**\n\n", d.before_label, d.after_label,
                          summary)
            : fmt::format("before: {}\nafter:  {}\n{}\n", d.before_label, d.after_label, summary);
  auto change = [](const DiffEntry& e) {
    if (e.relative == 0 || !std::isfinite(e.relative)) return std::string();
    return fmt::format(" ({:+.1f} %)", 100 * e.relative);
  };
  auto section = [&](const char* title, Dir dir) {
    std::vector<const DiffEntry*> rows;
    for (const auto& e : d.verdicts)
      if (e.direction == dir) rows.push_back(&e);
    for (const auto& e : d.numbers)
      if (e.direction == dir) rows.push_back(&e);
    if (rows.empty()) return;
    if (md) {
      out += fmt::format("{} ({}):\n\n| case | quantity | before | after |\n|:--|:--|--:|--:|\n",
                         title, rows.size());
      for (const auto* e : rows)
        out += fmt::format("| {} | {} | {} | {}{} |\n", e->case_id.empty() ? "–" : e->case_id,
                           e->quantity, e->before, e->after, change(*e));
      out += "\n";
    } else {
      out += fmt::format("{} ({}):\n", title, rows.size());
      for (const auto* e : rows)
        out += fmt::format("  {:<44} {:<40} {} → {}{}\n", e->case_id.empty() ? "–" : e->case_id,
                           e->quantity, e->before, e->after, change(*e));
    }
  };
  section("Worse", Dir::worse);
  section("Better", Dir::better);
  section("Moved", Dir::moved);
  // Long lists are cut in the report (its first screen is for what changed); the text lists all.
  auto some = [md](const std::vector<std::string>& ids) {
    constexpr std::size_t kShown = 8;
    if (!md || ids.size() <= kShown) return fmt::format("{}", fmt::join(ids, ", "));
    return fmt::format("{} and {} more", fmt::join(ids.begin(), ids.begin() + kShown, ", "),
                       ids.size() - kShown);
  };
  if (!d.added.empty())
    out += fmt::format("{}Cases added ({}): {}\n", md ? "\n" : "", d.added.size(), some(d.added));
  if (!d.removed.empty())
    out += fmt::format("{}Cases removed ({}): {}\n", md ? "\n" : "", d.removed.size(),
                       some(d.removed));
  if (!d.ledger_not_compared.empty())
    out += fmt::format("{}Ledger rows not compared, their cases ran in one of the runs only "
                       "({}): {}\n",
                       md ? "\n" : "", d.ledger_not_compared.size(), some(d.ledger_not_compared));
  return out;
}

}  // namespace mfv
