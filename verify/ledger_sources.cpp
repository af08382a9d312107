/// The ledger's sources judged under one reading (verify/ledger.hpp, LedgerSource): the page
/// section that shows, per source, every reading its rows tried against every row, so that a
/// reader sees which reading the table's numbers would need and that no reading is chosen row
/// by row.
#include <cmath>
#include <map>
#include <set>

#include <fmt/format.h>

#include "verify/ledger.hpp"

namespace mfv {

namespace {

/// "✓" reproduced (either kind), "~" partly, "✗" not reproduced, "·" not reached, "–" else.
const char* mark(const std::string& verdict) {
  if (verdict == kReproduced || verdict == kReproducedReading) return "✓";
  if (verdict == kPartly) return "~";
  if (verdict == kNotReproduced) return "✗";
  if (verdict == kNotReached) return "·";
  return "–";
}

bool reproduces(const std::string& v) { return v == kReproduced || v == kReproducedReading; }

/// The reading named `name` of an entry ("" : the row's own), or null if the row lacks it.
const LedgerReadingOutcome* reading_of(const LedgerEntry& e, const std::string& name) {
  for (const auto& r : e.readings)
    if ((name.empty() && !r.reading) || (r.reading && r.reading->name == name)) return &r;
  return nullptr;
}

std::string value_cell(const LedgerReadingOutcome* r) {
  if (!r) return "";
  if (r->ours.size() != 1 || r->compared.size() != 1) return mark(r->verdict);
  const double v = r->ours[0], q = r->compared[0].ratio;
  if (!std::isfinite(v)) return fmt::format("– {}", mark(r->verdict));
  return fmt::format("{:.3g} ({}) {}", v,
                     std::isfinite(q) ? fmt::format("{:.2f}×", q) : std::string("–"),
                     mark(r->verdict));
}

std::string escape(const std::string& s) {
  std::string out;
  for (char ch : s) out += ch == '|' ? std::string("\\|") : std::string(1, ch);
  return out;
}

}  // namespace

std::string ledger_sources_markdown(const Ledger& ledger, const std::vector<LedgerEntry>& entries) {
  if (ledger.sources.empty()) return "";
  std::map<std::string, const LedgerEntry*> by_id;
  for (const auto& e : entries) by_id[e.row->id] = &e;
  std::string md =
      "## Sources judged under one reading\n\n"
      "Where a paper's text leaves a choice open, the reading is chosen for the whole table or "
      "figure from its quoted text before the values are compared, and every row of it is "
      "judged under that reading. The other readings the rows tried are shown here against "
      "every row: how many rows each reproduces; one that passes some rows and fails others is "
      "reported, not counted. Cells: ours (ours/paper) and ✓ reproduced, ~ partly, ✗ not "
      "reproduced, · not reached, – not run.\n\n";
  for (const auto& src : ledger.sources) {
    std::vector<const LedgerEntry*> rows;
    for (const auto& id : src.rows)
      if (const auto it = by_id.find(id); it != by_id.end()) rows.push_back(it->second);
    if (rows.empty()) continue;
    md += fmt::format("### {}\n\nThe reading of every row: **{}**. {}\n\n", src.name,
                      src.reading.empty() ? "each row's own (the row as written)" : src.reading,
                      src.quote);
    // The readings: the rows' own, then every try name in the order first met.
    std::vector<std::string> names = {""};
    for (const auto* e : rows)
      for (const auto& r : e->readings)
        if (r.reading && std::find(names.begin(), names.end(), r.reading->name) == names.end())
          names.push_back(r.reading->name);
    md += "| reading |";
    for (const auto* e : rows) md += fmt::format(" {} |", e->row->id);
    md += " rows reproduced |\n|:--|";
    for (std::size_t k = 0; k < rows.size(); ++k) md += "--:|";
    md += ":--|\n";
    std::vector<std::string> split;
    for (const auto& name : names) {
      int tried = 0, passed = 0;
      std::string line = fmt::format("| {}{} |", name.empty() ? "each row's own" : escape(name),
                                     name == src.reading ? " (**the source's**)" : "");
      for (const auto* e : rows) {
        const LedgerReadingOutcome* r = reading_of(*e, name);
        line += fmt::format(" {} |", value_cell(r));
        if (r && r->verdict != kNotRun && r->verdict != kNotYetBuilt) {
          ++tried;
          passed += reproduces(r->verdict);
        }
      }
      line += fmt::format(" {} of {} |\n", passed, tried);
      md += line;
      if (passed > 0 && passed < tried)
        split.push_back(fmt::format("{} ({} of {})", name.empty() ? "each row's own" : name,
                                    passed, tried));
    }
    md += "\n";
    if (!split.empty())
      md += fmt::format("Readings that reproduce some rows of {} and not their siblings (reported, "
                        "not counted): {}.\n\n",
                        src.name, fmt::join(split, "; "));
    if (!src.pairs.empty()) {
      md += "Ratios of each pair (second row over first), ours per reading beside the paper's:\n\n"
            "| reading |";
      for (const auto& [a, b] : src.pairs) md += fmt::format(" {} / {} |", b, a);
      md += "\n|:--|";
      for (std::size_t k = 0; k < src.pairs.size(); ++k) md += "--:|";
      md += "\n| the paper |";
      for (const auto& [a, b] : src.pairs) {
        const LedgerEntry* ea = by_id.at(a);
        const LedgerEntry* eb = by_id.at(b);
        const bool ok = ea->row->paper.size() == 1 && eb->row->paper.size() == 1 &&
                        ea->row->paper[0] != 0;
        md += ok ? fmt::format(" {:.3f} |", eb->row->paper[0] / ea->row->paper[0]) : " – |";
      }
      md += "\n";
      for (const auto& name : names) {
        md += fmt::format("| {} |", name.empty() ? "each row's own" : escape(name));
        for (const auto& [a, b] : src.pairs) {
          const LedgerReadingOutcome* ra = reading_of(*by_id.at(a), name);
          const LedgerReadingOutcome* rb = reading_of(*by_id.at(b), name);
          const bool ok = ra && rb && ra->ours.size() == 1 && rb->ours.size() == 1 &&
                          std::isfinite(ra->ours[0]) && std::isfinite(rb->ours[0]) &&
                          ra->ours[0] != 0;
          md += ok ? fmt::format(" {:.3f} |", rb->ours[0] / ra->ours[0]) : " – |";
        }
        md += "\n";
      }
      md += "\n";
    }
  }
  return md;
}

}  // namespace mfv
