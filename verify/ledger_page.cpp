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

/// The ledger for people and spreadsheets: ledger.md (counts by paper and section, the rows,
/// every reading tried and its checks) and ledger.csv.
namespace mfv {

using namespace ledger_internal;

namespace {
/// "± 0.4 (p = 1.9, monotone; inside)" per value, or the reason there is none.
std::string uncertainty_text(const LedgerEntry& e) {
  const LedgerReadingOutcome& c = e.readings[e.chosen];
  std::vector<std::string> parts;
  for (std::size_t i = 0; i < c.uncertainty.size(); ++i) {
    const Uncertainty& u = c.uncertainty[i];
    // A finding's uncertainties are of the numbers its verdict rests on: each named.
    const std::string of = i < c.uncertainty_of.size() ? c.uncertainty_of[i] + " " : "";
    if (!u.known()) {
      parts.push_back(of + "– (" + u.why_none + ")");
      continue;
    }
    if (!of.empty()) {
      parts.push_back(fmt::format("{}{:.4g} {}", of, u.value, u.text()));
      continue;
    }
    std::string t = u.text();
    if (i < c.paper_inside.size()) {
      t.pop_back();
      t += c.paper_inside[i] ? "; paper inside)" : "; paper outside)";
    }
    parts.push_back(t);
  }
  return fmt::format("{}", fmt::join(parts, "; "));
}

std::string tolerance_text(const LedgerEntry& e) {
  const LedgerRow& row = *e.row;
  if (row.kind == LedgerRow::Kind::finding) return e.criterion;
  if (!(row.tolerance > 0)) return "–";
  if (row.bound == LedgerRow::Bound::range)
    return fmt::format("in [low − {0:g}%, high + {0:g}%]", 100 * row.tolerance);
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
      {"other", "Other sources (closed forms, experiments)"},
      {"cost", "Claims about CPU time (judged on this machine's CPU seconds, which move with "
               "its load; counted apart)"},
      {"check", "Our own checks of the suite (not claims of a paper; counted apart)"}};
  return t;
}

std::vector<std::string> paper_order() {
  return {"000", "001", "003", "004", "other", "cost", "check"};
}

/// The page's group of a row: its paper, or `cost` for a claim about CPU time (whose paper
/// stays in ledger.csv's and ledger.json's paper_id).
std::string ledger_group(const LedgerRow& row) {
  return row.role == LedgerRow::Role::cost ? std::string("cost") : ledger_paper(row);
}

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
    const std::string p = ledger_group(*e.row), s = ledger_section(*e.row);
    per_paper[p].add(e);
    auto& order = section_order[p];
    if (std::find(order.begin(), order.end(), s) == order.end()) order.push_back(s);
    per_section[p][s].add(e);
    if (e.row->role == LedgerRow::Role::claim) all.add(e);
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
  cells.insert(cells.begin(), "**all claims** (CPU-time claims and our own checks apart)");
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
  if (row.role == LedgerRow::Role::check) return "check";
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

UncertaintyCoverage uncertainty_coverage(const std::vector<LedgerEntry>& entries) {
  UncertaintyCoverage c;
  for (const auto& e : entries) {
    if (e.row->role != LedgerRow::Role::claim || e.evidence != kEvidenceConverged) continue;
    ++c.converged;
    const auto& u = e.readings[e.chosen].uncertainty;
    const auto known = std::count_if(u.begin(), u.end(), [](const Uncertainty& x) {
      return x.known();
    });
    c.some += known > 0;
    c.every += !u.empty() && known == static_cast<std::ptrdiff_t>(u.size());
  }
  return c;
}

std::string ledger_markdown(const std::vector<LedgerEntry>& entries) {
  std::string md = "## Counts by paper and section\n\n" + counts_markdown(entries, true) +
                   "\nEvidence: **independent** (a second computation by another route agrees "
                   "within the row's tolerance), **converged** (a finer resolution, quadrature or "
                   "time step moves ours by less than the tolerance), **single run** (no check "
                   "agrees, or none exists).\n\n";
  const UncertaintyCoverage cov = uncertainty_coverage(entries);
  md += fmt::format(
      "Uncertainty: of the {} claim rows with converged evidence, {} carry a discretization "
      "uncertainty (GCI, observed order, extrapolated value) for at least one of their numbers "
      "and {} for every one; the others say why none.\n\n",
      cov.converged, cov.some, cov.every);
  for (const auto& p : paper_order()) {
    std::vector<const LedgerEntry*> mine;
    for (const auto& e : entries)
      if (ledger_group(*e.row) == p) mine.push_back(&e);
    if (mine.empty()) continue;
    md += fmt::format("## {}\n\n", paper_titles().at(p));
    md += "| id | source | claim | paper | ours | ± uncertainty (order, class; paper inside?) | "
          "ours/paper (or −) | tolerance | verdict | evidence | reading (of those tried) "
          "|\n|:--|:--|:--|--:|--:|:--|--:|:--|:--|:--|:--|\n";
    for (const LedgerEntry* e : mine) {
      const LedgerRow& row = *e->row;
      const std::string tried = e->readings.size() > 1
                                    ? fmt::format("{} ([{} tried](#{}))", e->reading,
                                                  e->readings.size(), anchor(row))
                                    : fmt::format("{} ([details](#{}))", e->reading, anchor(row));
      md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | **{}** | {} | {} |\n",
                        cell(row.id), cell(row.source), cell(row.claim), cell(paper_text(*e)),
                        cell(ours_text(*e)), cell(uncertainty_text(*e)),
                        cell(comparison_text(*e)), cell(tolerance_text(*e)), e->verdict,
                        cell(e->evidence), cell(tried));
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
      "verdict,evidence,reading,readings_tried,checks,gap_reason,uncertainty,observed_order,"
      "extrapolated,gci,convergence_class,paper_inside_uncertainty,uncertainty_why_none,"
      "uncertainty_of,role\n";
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
    std::vector<std::string> fields = {
        row.id, ledger_paper(row), ledger_section(row), row.source, row.claim,
        case_text(*e.read), join_values(row.paper, true),
        row.kind == LedgerRow::Kind::finding ? ours_text(e) : join_values(e.ours, true),
        comparison_text(e),
        row.kind == LedgerRow::Kind::finding ? e.criterion
        : row.tolerance > 0                  ? fmt::format("{:g}", row.tolerance)
                                             : "",
        row.kind == LedgerRow::Kind::finding ? "finding"
        : row.bound == LedgerRow::Bound::range    ? "range"
        : row.bound == LedgerRow::Bound::at_least ? "at_least"
        : row.bound == LedgerRow::Bound::at_most  ? "at_most"
        : row.compare == CompareBy::ratio    ? "ratio"
                                             : "difference",
        e.verdict, e.evidence, e.reading, fmt::format("{}", fmt::join(tried, " | ")),
        fmt::format("{}", fmt::join(checks, " | ")), e.why};
    // The chosen reading's uncertainty per value (";" between values, as ours).
    const LedgerReadingOutcome& c = e.readings[e.chosen];
    std::vector<std::string> u, p, x, g, k, in, why;
    auto num = [](double v) { return std::isfinite(v) ? fmt::format("{}", v) : std::string(); };
    for (std::size_t i = 0; i < c.uncertainty.size(); ++i) {
      const Uncertainty& q = c.uncertainty[i];
      u.push_back(num(q.absolute));
      p.push_back(num(q.order) + (q.assumed_order && std::isfinite(q.order) ? " (assumed)" : ""));
      x.push_back(num(q.extrapolated));
      g.push_back(num(q.gci));
      k.push_back(convergence_class_name(q.cls));
      in.push_back(i < c.paper_inside.size() && q.known() ? (c.paper_inside[i] ? "yes" : "no")
                                                            : "");
      why.push_back(q.why_none);
    }
    using Column = const std::vector<std::string>*;
    for (Column col : {Column{&u}, Column{&p}, Column{&x}, Column{&g}, Column{&k}, Column{&in},
                       Column{&why}, Column{&c.uncertainty_of}})
      fields.push_back(fmt::format("{}", fmt::join(*col, ";")));
    fields.push_back(row.role == LedgerRow::Role::check  ? "check"
                     : row.role == LedgerRow::Role::cost ? "cost"
                                                         : "claim");
    std::vector<std::string> quoted;
    for (const auto& f : fields) quoted.push_back(csv_field(f));
    out += fmt::format("{}\n", fmt::join(quoted, ","));
  }
  return out;
}

}  // namespace mfv
