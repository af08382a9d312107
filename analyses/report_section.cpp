#include "analyses/report_section.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <tuple>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "reports/atomic.hpp"
#include "reports/markdown.hpp"
#include "reports/plot.hpp"
#include "analyses/case_vtk.hpp"
#include "reports/vtk.hpp"
#include "problems/comparison.hpp"

namespace mfv {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string section_title(const ReportSection& s) {
  const std::string p = s.problem_params.to_string();
  return p.empty() ? s.problem : s.problem + " (" + p + ")";
}

/// Whether the resolved parameters of a study contain every published parameter.
bool params_match(const Params& resolved, const Params& wanted) {
  for (const auto& [k, v] : wanted.values()) {
    if (!resolved.has(k)) return false;
    if (format_value(resolved.values().at(k)) != format_value(v)) return false;
  }
  return true;
}

/// Whether case `r` measures published value `pv`: method, node count, method parameters,
/// and each published problem parameter as the case set it or, unset, at its default.
bool case_matches(const PublishedValue& pv, const CaseResult& r, const Params& defaults) {
  if (r.spec.method != pv.method || r.spec.nodes != pv.nodes) return false;
  if (!params_match(r.method_params, pv.method_params)) return false;
  for (const auto& [k, v] : pv.problem_params.values()) {
    const Params& from = r.spec.problem_params.has(k) ? r.spec.problem_params : defaults;
    if (from.has(k) && format_value(from.values().at(k)) != format_value(v)) return false;
  }
  return true;
}

double our_value(const CaseResult& r, const std::string& quantity) {
  if (quantity == "error u") return r.errors.l2_rel;
  if (quantity == "error du/dx") return r.errors.h1_semi_rel;
  const auto it = r.headline.find(quantity);
  return it == r.headline.end() ? kNaN : it->second;
}

/// Markdown paragraphs, one per entry.
std::string paragraphs(const std::vector<std::string>& texts) {
  std::string out;
  for (const auto& t : texts) out += t + "\n\n";
  return out;
}

/// A value as a person reads it: 5 significant digits, scientific when tiny or huge.
std::string value_text(double v) {
  if (std::isnan(v)) return "–";
  if (v == 0) return "0";
  return std::abs(v) < 1e-2 || std::abs(v) >= 1e5 ? fmt_sci(v, 4) : fmt::format("{:.5g}", v);
}

std::string ratio_text(double r) {
  if (!std::isfinite(r)) return "–";
  return std::abs(r) < 1e-2 || std::abs(r) >= 1e3 ? fmt_sci(r, 2) : fmt::format("{:.3g}", r);
}

/// "rkpm j=1,kernel=gaussian", with the problem parameters the value belongs to in brackets
/// ("xefg (dim=2)"), so values that differ only there do not read as duplicates.
std::string method_text(const PublishedValue& p) {
  const std::string params = p.method_params.to_string();
  const std::string problem = p.problem_params.to_string();
  return (params.empty() ? p.method : p.method + " " + params) +
         (problem.empty() ? "" : " (" + problem + ")");
}

/// compare_value under the value's own tolerance; a tolerance that is not a positive number
/// gives no verdict rather than a made-up one.
struct Judged {
  double ratio = kNaN;
  std::string tolerance, verdict;
};
Judged judge(double ours, const PublishedValue& p) {
  Judged j;
  if (!(p.tolerance > 0) || !std::isfinite(p.tolerance)) {
    j.ratio = p.value != 0 ? ours / p.value : kNaN;
    j.tolerance = "–";
    j.verdict = fmt::format("no verdict: tolerance {} is not positive", p.tolerance);
    return j;
  }
  const Comparison c = compare_value(ours, p.value, p.tolerance);
  j.ratio = c.ratio;
  j.tolerance = fmt::format("{:g}%", 100 * p.tolerance);
  j.verdict = c.verdict;
  return j;
}

std::vector<std::string> spacings(const StudyResult& s) {
  std::vector<std::string> out;
  for (const auto& c : s.cases) out.push_back(fmt::format("{:.4g}", c.h));
  return out;
}

/// Counts of verdict words, the ledger's order first (reproduced … not yet built), others
/// after in first-seen order: "2 reproduced, 1 not reproduced".
std::string count_text(const std::vector<std::string>& verdicts) {
  std::vector<std::pair<std::string, int>> counts;
  for (const char* v : {kReproduced, kReproducedReading, kPartly, kNotReproduced, kNotReached,
                        "not run", kNotYetBuilt})
    counts.emplace_back(v, 0);
  for (const auto& v : verdicts) {
    auto it = std::find_if(counts.begin(), counts.end(), [&](const auto& c) { return c.first == v; });
    if (it == counts.end()) counts.emplace_back(v, 1);
    else ++it->second;
  }
  std::erase_if(counts, [](const auto& c) { return c.second == 0; });
  std::vector<std::string> parts;
  for (const auto& [v, n] : counts) parts.push_back(fmt::format("{} {}", n, v));
  return fmt::format("{}", fmt::join(parts, ", "));
}

}  // namespace

std::string slug(const std::string& text) {
  std::string out;
  for (unsigned char c : text) {
    if (std::isalnum(c) || c == '.') out += static_cast<char>(std::tolower(c));
    else if (!out.empty() && out.back() != '-') out += '-';
  }
  while (!out.empty() && out.back() == '-') out.pop_back();
  return out.empty() ? "x" : out;
}

void add_to_sections(const Registries& plugins, std::vector<ReportSection>& sections,
                     StudyResult study) {
  if (study.cases.empty()) return;
  const CaseSpec& spec = study.cases.front().spec;
  // A case built by hand may not say its analysis: the problem's default ran it.
  const std::string analysis =
      !study.cases.front().analysis.empty()
          ? study.cases.front().analysis
          : create_problem(plugins, spec.problem, spec.problem_params)->analyses().front();
  // Transient studies of one problem share a section whatever their loading, frame or
  // prestress: their findings compare across those parameters (Lagrangian vs Eulerian,
  // σ̄ sweeps), and each study's parameters are in its label and engine description.
  // Figure analyses likewise: one section per problem, the parameters of each case in its
  // row. A static solve's parameters make another problem (another exact solution).
  const Params key = plugins.analyses.create(analysis)->section_per_problem_params()
                         ? spec.problem_params
                         : Params{};
  for (auto& s : sections) {
    if (s.problem == spec.problem && s.analysis == analysis &&
        s.problem_params.to_string() == key.to_string()) {
      s.studies.push_back(std::move(study));
      return;
    }
  }
  ReportSection s;
  s.problem = spec.problem;
  s.analysis = analysis;
  s.problem_params = key;
  s.studies.push_back(std::move(study));
  sections.push_back(std::move(s));
}

std::vector<PublishedComparison> compare_published(const Problem& problem,
                                                   const std::vector<StudyResult>& studies,
                                                   const Params& problem_defaults) {
  std::vector<PublishedComparison> out;
  for (const auto& pv : problem.published()) {
    bool matched = false;
    for (const auto& s : studies)
      for (const auto& r : s.cases)
        if (case_matches(pv, r, problem_defaults)) {
          out.push_back({pv, s.label, our_value(r, pv.quantity)});
          matched = true;
        }
    if (!matched) out.push_back({pv, "", kNaN});
  }
  return out;
}

std::vector<PublishedRow> published_rows(const Problem& problem,
                                         const std::vector<StudyResult>& studies,
                                         const Params& problem_defaults) {
  std::vector<PublishedRow> rows;
  std::set<std::string> seen;
  for (const auto& pv : problem.published()) {
    // A problem may list one value twice (once per problem parameter it loops over): one row.
    const std::string key =
        fmt::format("{}\x1f{}\x1f{}\x1f{}\x1f{}\x1f{:.17g}\x1f{}", pv.source, pv.quantity,
                    pv.method, pv.method_params.to_string(), pv.nodes, pv.value,
                    pv.problem_params.to_string());
    if (!seen.insert(key).second) continue;
    PublishedRow row{pv, {}, {}};
    for (const auto& s : studies)
      for (const auto& r : s.cases) {
        if (!case_matches(pv, r, problem_defaults)) continue;
        const double v = our_value(r, pv.quantity);
        if (std::isfinite(v)) row.ours.emplace_back(s.label, v);
        else row.unmeasured.push_back(s.label);
      }
    rows.push_back(std::move(row));
  }
  return rows;
}

std::string write_vtk_collections(const std::filesystem::path& dir, const std::string& base,
                                  const std::vector<StudyResult>& studies,
                                  const std::vector<VtkPart>& parts, bool finest_only) {
  std::string md;
  for (const auto& s : studies) {
    const std::string sub = fmt::format("vtk/{}/{}", base, slug(s.label));
    make_report_subdir(dir, sub);
    std::vector<std::pair<double, std::string>> entries;
    for (std::size_t k = finest_only && !s.cases.empty() ? s.cases.size() - 1 : 0;
         k < s.cases.size(); ++k)
      for (const auto& [suffix, write] : parts) {
        const CaseResult& c = s.cases[k];
        const std::string name = fmt::format("n{}{}", c.spec.nodes, suffix);
        write(dir / sub / name, c);
        entries.emplace_back(c.h, name);  // ParaView's time axis: the spacing h
      }
    write_pvd(dir / sub / "study.pvd", entries);
    md += finest_only
              ? fmt::format("- `{}`: [{}/study.pvd]({}{}/study.pvd) (the finest resolution, h = "
                            "{})\n",
                            s.label, sub, kPageUp, sub,
                            s.cases.empty() ? std::string("–") : spacings(s).back())
              : fmt::format("- `{}`: [{}/study.pvd]({}{}/study.pvd) (time = h: {})\n", s.label,
                            sub, kPageUp, sub, fmt::join(spacings(s), ", "));
  }
  if (finest_only)
    md += "\nThe finest resolution of each study only (`--vtk=finest`, the nightly's default); "
          "`--vtk=all` writes every resolution.\n";
  return md + "\n";
}

std::vector<PaperTable> paper_tables(const Problem& problem,
                                     const std::vector<StudyResult>& studies,
                                     const Params& problem_defaults) {
  const auto rows = published_rows(problem, studies, problem_defaults);
  std::vector<PaperTable> out;
  std::vector<std::string> sources;
  for (const auto& r : rows) {
    const std::string& src = r.published.source;
    const bool table = src.find("Table") != std::string::npos || src.find("table") != std::string::npos;
    if (table && std::find(sources.begin(), sources.end(), src) == sources.end())
      sources.push_back(src);
  }
  for (const auto& src : sources) {
    // Rows: (quantity,) n; columns: each method's paper value and ours, in the order the
    // problem lists them (the paper's order).
    std::vector<std::string> methods, quantities;
    std::vector<int> nodes;
    std::map<std::tuple<std::string, int, std::string>, const PublishedRow*> cell;
    for (const auto& r : rows) {
      const PublishedValue& p = r.published;
      if (p.source != src) continue;
      const std::string m = method_text(p);
      if (std::find(methods.begin(), methods.end(), m) == methods.end()) methods.push_back(m);
      if (std::find(quantities.begin(), quantities.end(), p.quantity) == quantities.end())
        quantities.push_back(p.quantity);
      if (std::find(nodes.begin(), nodes.end(), p.nodes) == nodes.end()) nodes.push_back(p.nodes);
      cell.try_emplace({p.quantity, p.nodes, m}, &r);
    }
    if (cell.size() < 2) continue;  // one value is a row of the list above, not a table
    std::sort(nodes.begin(), nodes.end());
    PaperTable t;
    t.source = src;
    // The header: the row keys, then a paper / ours pair per column.
    auto header = [&t](const char* first, const std::vector<std::string>& columns) {
      t.table.head = {first, "n"};
      for (const auto& c : columns) {
        t.table.head.push_back(c + ": paper");
        t.table.head.push_back(c + ": ours");
      }
      t.table.align.assign(t.table.head.size(), 'r');
      t.table.align[0] = 'l';
    };
    // The paper's value and ours at (quantity, n, method), or two empty cells; true if found.
    auto pair = [&cell](std::vector<std::string>& line, const std::string& q, int n,
                        const std::string& m) {
      const auto it = cell.find({q, n, m});
      if (it == cell.end()) {
        line.insert(line.end(), {"", ""});
        return false;
      }
      const PublishedRow& r = *it->second;
      line.push_back(value_text(r.published.value));
      line.push_back(r.ours.empty() ? "not run" : value_text(r.ours.front().second));
      return true;
    };
    // A table whose methods each sit at one resolution of their own (001 Table 3: SPH at
    // 481 × 41, KBM si at 349 × 30 …) has a row per method, as the paper prints it.
    std::map<std::string, std::set<int>> nodes_of;
    for (const auto& [key, row] : cell) nodes_of[std::get<2>(key)].insert(std::get<1>(key));
    const bool one_each = nodes.size() > 1 && std::all_of(nodes_of.begin(), nodes_of.end(),
                                                          [](const auto& e) { return e.second.size() == 1; });
    if (one_each) {
      header("method", quantities);
      for (const auto& m : methods) {
        const int n = *nodes_of[m].begin();
        std::vector<std::string> line = {m, std::to_string(n)};
        for (const auto& q : quantities) pair(line, q, n, m);
        t.table.rows.push_back(std::move(line));
      }
    } else {
      header("quantity", methods);
      for (const auto& q : quantities)
        for (int n : nodes) {
          std::vector<std::string> line = {q, std::to_string(n)};
          bool any = false;
          for (const auto& m : methods) any = pair(line, q, n, m) || any;
          if (any) t.table.rows.push_back(std::move(line));
        }
    }
    out.push_back(std::move(t));
  }
  return out;
}

std::string published_block(const Problem& problem, const std::vector<StudyResult>& studies,
                            const Params& problem_defaults, const std::string& problem_key) {
  const auto rows = published_rows(problem, studies, problem_defaults);
  std::string md;
  MarkdownTable t({"source", "quantity", "method", "n", "paper", "ours", "ours/paper",
                   "tolerance", "verdict", "our study", "notes"},
                  {'l', 'l', 'l', 'r', 'r', 'r', 'r', 'r', 'l', 'l', 'l'});
  std::vector<std::string> notes;  // numbered under the table, shared by equal texts
  auto note_number = [&notes](const std::string& text) {
    const auto it = std::find(notes.begin(), notes.end(), text);
    if (it != notes.end()) return static_cast<int>(it - notes.begin()) + 1;
    notes.push_back(text);
    return static_cast<int>(notes.size());
  };
  // Values not run: grouped by method and quantity, their node counts listed once each.
  std::vector<std::pair<std::string, std::vector<int>>> not_run;
  for (const auto& row : rows) {
    const PublishedValue& p = row.published;
    const std::string method = method_text(p);
    if (row.ours.empty()) {
      std::string what = fmt::format("{}: {}", method, p.quantity);
      if (!row.unmeasured.empty())
        what += fmt::format(" (`{}` ran there but does not measure it)",
                            fmt::join(row.unmeasured, "`, `"));
      auto it = std::find_if(not_run.begin(), not_run.end(),
                             [&](const auto& e) { return e.first == what; });
      if (it == not_run.end()) it = not_run.insert(not_run.end(), {what, {}});
      if (std::find(it->second.begin(), it->second.end(), p.nodes) == it->second.end())
        it->second.push_back(p.nodes);
      continue;
    }
    const auto& [study, ours] = row.ours.front();
    const Judged j = judge(ours, p);
    std::vector<int> refs;
    if (!p.note.empty()) refs.push_back(note_number(p.note));
    for (std::size_t k = 1; k < row.ours.size(); ++k) {
      const Judged o = judge(row.ours[k].second, p);
      refs.push_back(note_number(fmt::format("also `{}`: ours {}, ratio {}, {}",
                                             row.ours[k].first, value_text(row.ours[k].second),
                                             ratio_text(o.ratio), o.verdict)));
    }
    std::vector<std::string> ref_text;
    for (int r : refs) ref_text.push_back(fmt::format("[{}]", r));
    t.add_row({p.source, p.quantity, method, std::to_string(p.nodes), value_text(p.value),
               value_text(ours), ratio_text(j.ratio), j.tolerance, j.verdict, study,
               fmt::format("{}", fmt::join(ref_text, " "))});
  }
  if (t.rows() > 0) {
    md += fmt::format("n counts {}. ", problem.resolution_name());
    md += "\"ours/paper\" is the ratio; the verdict is reproduced when |ours/paper − 1| is "
          "within the value's tolerance, partly within 3× it, not reproduced beyond "
          "(problems/comparison.hpp).\n\n";
    md += t.str() + "\n";
    for (std::size_t i = 0; i < notes.size(); ++i)
      md += fmt::format("[{}] {}  \n", i + 1, notes[i]);
    if (!notes.empty()) md += "\n";
  }
  if (!not_run.empty()) {
    md += "**Not run or not measured in this suite** (run them with `mfv compare` or the "
          "`--full` suite):\n\n";
    for (const auto& [what, nodes] : not_run)
      md += fmt::format("- {} at {} {}\n", what, fmt::join(nodes, ", "),
                        problem.resolution_name());
    md += "\n";
  }
  // The paper's tables rebuilt from the rows above: its values with ours beside each.
  for (const auto& t : paper_tables(problem, studies, problem_defaults))
    md += fmt::format("**{} in the paper's layout** (a row per method where each has its own "
                      "resolution, else per quantity and resolution; the paper's value and ours "
                      "side by side, n counting {}; the first matching study's value; CSV and LaTeX: "
                      "`tables/{}/{}.csv`, `.tex`):\n\n{}\n",
                      t.source, problem.resolution_name(), slug(problem_key),
                      paper_table_stem(t.source), t.table.markdown());
  const auto explain = problem.published_notes();
  md += paragraphs(explain);
  return md;
}

std::string paper_table_stem(const std::string& source) { return "paper-" + slug(source); }

std::string problem_page(const std::string& title, const std::string& description,
                         const PageParts& parts) {
  std::string md = fmt::format("# {}\n\n[← report](../index.md)\n\n{}\n\n", title, description);
  if (!parts.lead.empty()) md += parts.lead + "\n\n";
  if (!parts.methods.empty()) md += "**Methods.**\n\n" + parts.methods + "\n";
  const std::pair<const char*, const std::string*> sections[] = {
      {"The paper's findings and ours", &parts.findings},
      {"Errors and CPU times", &parts.errors},
      {"Verdicts and measured values", &parts.verdicts},
      {"Convergence rates", &parts.rates},
      {"Plots", &parts.plots},
      {"Published values beside ours", &parts.published},
      {"VTK files", &parts.vtk}};
  for (const auto& [heading, body] : sections)
    if (!body->empty()) md += fmt::format("## {}\n\n{}", heading, *body);
  return md;
}

std::string section_page(const Registries& plugins, const Problem& problem,
                         const ReportSection& section, const std::string& title,
                         PageParts page, const std::filesystem::path& dir) {
  page.findings = findings_block(plugins, problem, section.studies);
  const Params defaults =
      resolved_case_params(plugins, section.problem, Params{}, section.analysis);
  page.published = published_block(problem, section.studies, defaults, section.problem);
  // The paper tables as files: tables/<problem>/paper-<source>.csv and .tex.
  for (const auto& t : paper_tables(problem, section.studies, defaults)) {
    const std::filesystem::path sub =
        make_report_subdir(dir, std::filesystem::path("tables") / slug(section.problem));
    write_file_atomic(sub / (paper_table_stem(t.source) + ".csv"), t.table.csv());
    write_file_atomic(sub / (paper_table_stem(t.source) + ".tex"), t.table.tex());
  }
  return problem_page(title, plugins.problems.entry(section.problem).description, page);
}

std::string methods_list(const ReportSection& section,
                         const std::function<std::string(const StudyResult&)>& item) {
  std::string md;
  for (const auto& s : section.studies)
    if (!s.cases.empty()) md += fmt::format("- {}\n", item(s));
  for (const auto& f : section.failures) md += fmt::format("- **could not run:** {}\n", f);
  return md;
}

std::string page_lead(const Problem& problem) {
  std::vector<std::string> exact;
  for (const auto& [k, v] : problem.headline_exact())
    exact.push_back(fmt::format("{} = {:.6g}", k, v));
  const std::string counts = fmt::format("Resolutions count {}.", problem.resolution_name());
  return exact.empty() ? counts : fmt::format("Exact: {}. {}", fmt::join(exact, ", "), counts);
}

std::string plot_image(const std::filesystem::path& dir, const std::string& name,
                       const PlotSpec& spec, const std::string& alt, const std::string& what) {
  make_report_subdir(dir, std::filesystem::path(name).parent_path());
  const std::vector<PlotSpec> parts = split_plot(spec);
  std::string md;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    // One part keeps the name; several are "<stem>-part<k>.svg" beside it.
    std::string file = name;
    if (parts.size() > 1) {
      const std::filesystem::path p(name);
      file = (p.parent_path() / fmt::format("{}-part{}{}", p.stem().string(), k + 1,
                                            p.extension().string()))
                 .generic_string();
    }
    const std::string part_alt =
        parts.size() > 1 ? fmt::format("{} (part {} of {})", alt, k + 1, parts.size()) : alt;
    if (const auto why = write_svg_plot(dir / file, parts[k]))
      md += fmt::format("_{} plot skipped: {}_\n\n", what, *why);
    else
      md += fmt::format("![{}]({}{})\n\n", part_alt, kPageUp, file);
  }
  return md;
}

/// The page of a 1D static problem: methods, findings, errors and CPU per resolution, rates
/// with their trend, plots, published values, VTK.
std::string write_scalar_page(const Registries& catalogue, const ReportSection& section,
                              const std::string& title, const std::filesystem::path& dir,
                              bool vtk) {
  const auto problem = create_problem(catalogue, section.problem, section.problem_params);
  const std::string base = slug(title);
  PageParts page;
  page.lead = page_lead(*problem);
  page.methods = methods_list(section, [](const StudyResult& s) {
    return fmt::format("`{}`: {}", s.label, s.cases.front().method_description);
  });

  // Errors and times per resolution; the headline columns are whatever the cases measured.
  std::vector<std::string> headline_names;
  for (const auto& s : section.studies)
    for (const auto& r : s.cases)
      for (const auto& [k, v] : r.headline)
        if (std::find(headline_names.begin(), headline_names.end(), k) == headline_names.end())
          headline_names.push_back(k);
  page.errors =
      "Errors on the common rule (uniform cells, 6 Gauss points "
      "each, at least 1200 cells; the same for every method); \"H1\" is the seminorm ‖e′‖, "
      "\"rel\" divides by the exact solution's norm; \"cond\" is the 2-norm condition number of "
      "the solved system (above ~1e12 the errors carry round-off). CPU seconds per phase.\n\n";
  {
    std::vector<std::string> head = {"method", "nodes", "h", "L2", "L2 rel", "H1", "H1 rel"};
    for (const auto& n : headline_names) head.push_back(n);
    for (const char* t : {"cond", "setup s", "assembly s", "solve s"}) head.push_back(t);
    std::vector<char> align(head.size(), 'r');
    align[0] = 'l';
    MarkdownTable t(head, align);
    for (const auto& s : section.studies) {
      for (const auto& r : s.cases) {
        std::vector<std::string> row = {s.label, std::to_string(r.spec.nodes), fmt_sci(r.h, 2),
                                        fmt_sci(r.errors.l2), fmt_sci(r.errors.l2_rel),
                                        fmt_sci(r.errors.h1_semi), fmt_sci(r.errors.h1_semi_rel)};
        for (const auto& n : headline_names) {
          const auto it = r.headline.find(n);
          row.push_back(it == r.headline.end() ? "–" : fmt::format("{:.5f}", it->second));
        }
        row.push_back(fmt_sci(r.data<StaticSolveData>().solve.condition, 1));
        row.push_back(fmt::format("{:.4f}", r.cpu.setup));
        row.push_back(fmt::format("{:.4f}", r.cpu.assembly));
        row.push_back(fmt::format("{:.4f}", r.cpu.solve));
        t.add_row(row);
      }
    }
    page.errors += t.str() + "\n";
  }

  page.rates =
      "Least-squares slope of ln e against ln h over all "
      "resolutions (004 II eq 7.3), and the slope between successive resolutions; the paper "
      "rule integrates with 12 Gauss points between neighbouring particles. The L2 trend "
      "judges the pairwise rates and the finest error (reports/convergence.hpp): converges "
      "only if the finest error is the smallest and the last pairwise and the fitted rate "
      "are at least 0.5.\n\n";
  {
    MarkdownTable t({"method", "L2 rate", "L2 pairwise", "H1 rate", "H1 pairwise",
                     "L2 rate (paper rule)", "H1 rate (paper rule)", "L2 trend"},
                    {'l', 'r', 'r', 'r', 'r', 'r', 'r', 'l'});
    for (const auto& s : section.studies)
      t.add_row({s.label, fmt_rate(s.rates.rate("L2")), fmt_rates(s.rates.pairwise_of("L2")),
                 fmt_rate(s.rates.rate("H1-semi")), fmt_rates(s.rates.pairwise_of("H1-semi")),
                 fmt_rate(s.rates_paper.rate("L2")), fmt_rate(s.rates_paper.rate("H1-semi")),
                 judge_study(s, [](const CaseResult& c) { return c.errors.l2_rel; }).label()});
    page.rates += t.str() + "\n";
  }

  // Relative errors (dimensionless), so every axis has its unit.
  for (bool h1 : {false, true}) {
    const PlotSpec spec =
        h1 ? convergence_plot(title + ": H1 seminorm error", section.studies,
                              "relative H1 seminorm error |u_h - u|_1 / |u|_1 (dimensionless)",
                              [](const CaseResult& c) { return c.errors.h1_semi_rel; },
                              [](const Rates& r) { return r.rate("H1-semi"); })
           : convergence_plot(title + ": L2 error", section.studies,
                              "relative L2 error ||u_h - u|| / ||u|| (dimensionless)",
                              [](const CaseResult& c) { return c.errors.l2_rel; },
                              [](const Rates& r) { return r.rate("L2"); });
    page.plots +=
        plot_image(dir, fmt::format("plots/{}-{}.svg", base, h1 ? "h1" : "l2"), spec,
                   fmt::format("{} error against h", h1 ? "H1 seminorm" : "L2"), h1 ? "H1" : "L2");
  }

  // One ParaView collection per study, stepping through the resolutions.
  if (vtk)
    page.vtk =
        "Particles (u_h, u_exact, error, du/dx, coefficients, volumes) and "
        "the densely sampled solution as a line; open the `.pvd` in ParaView and step "
        "through the resolutions: its time axis is the particle spacing h.\n\n" +
        write_vtk_collections(dir, base, section.studies,
                              {{".vtp", write_case_vtp}, {"-line.vtp", write_line_vtp}},
                              section.vtk_finest_only);
  return section_page(catalogue, *problem, section, title, std::move(page), dir);
}

ConvergenceJudgement judge_study(const StudyResult& study,
                                 const std::function<double(const CaseResult&)>& error) {
  std::vector<double> e, h;
  for (const auto& c : study.cases) {
    e.push_back(error(c));
    h.push_back(c.h);
  }
  return judge_convergence(e, h);
}

namespace {

/// The finest resolution every study of the section has; 0 when they share none.
int finest_common_resolution(const std::vector<StudyResult>& studies) {
  std::set<int> common;
  bool first = true;
  for (const auto& s : studies) {
    if (s.cases.empty()) continue;
    std::set<int> mine;
    for (const auto& c : s.cases) mine.insert(c.spec.nodes);
    if (first) {
      common = mine;
      first = false;
    } else {
      std::set<int> both;
      std::set_intersection(common.begin(), common.end(), mine.begin(), mine.end(),
                            std::inserter(both, both.begin()));
      common = std::move(both);
    }
  }
  return common.empty() ? 0 : *common.rbegin();
}

/// The resolution a ranking compares at: the finest that at least half of the studies (and
/// at least two) reached, so that one study stopped at a coarse resolution does not pull
/// every method's comparison down to it (issue 28: the cantilever was ranked at 9 particles
/// across the depth, where an erratic variant came first). Falls back to the finest common
/// resolution; 0 when there is none.
int ranking_resolution(const std::vector<StudyResult>& studies) {
  std::map<int, std::size_t> reached;
  std::size_t n = 0;
  for (const auto& s : studies) {
    if (s.cases.empty()) continue;
    ++n;
    std::set<int> mine;
    for (const auto& c : s.cases) mine.insert(c.spec.nodes);
    for (int r : mine) ++reached[r];
  }
  const std::size_t needed = std::max<std::size_t>(2, (n + 1) / 2);
  for (auto it = reached.rbegin(); it != reached.rend(); ++it)
    if (it->second >= needed) return it->first;
  return finest_common_resolution(studies);
}

}  // namespace

/// The method ranking of a section with errors: relative L2 error (the problem's main field)
/// at the ranking resolution (ranking_resolution), the finest error where a study goes
/// further or stopped short (unranked, last), the fitted
/// rate with its trend, CPU seconds and correct digits per CPU second; best first.
std::string ranking_block(const std::vector<StudyResult>& studies, const std::string& resolution,
                          const std::string& error_name) {
  const int common = ranking_resolution(studies);
  struct Row {
    std::string label;
    const CaseResult* at = nullptr;  // the case at the ranking resolution (or the finest)
    const CaseResult* finest = nullptr;
    ConvergenceJudgement trend;
    bool ranked = true;  // reached the ranking resolution
  };
  std::vector<Row> rows;
  bool further = false;
  std::size_t unranked = 0;
  for (const auto& s : studies) {
    if (s.cases.empty()) continue;
    Row r{s.label, &s.cases.back(), &s.cases.back(),
          judge_study(s, [](const CaseResult& c) { return c.errors.l2_rel; })};
    if (common > 0) {
      r.ranked = false;
      for (const auto& c : s.cases)
        if (c.spec.nodes == common) {
          r.at = &c;
          r.ranked = true;
        }
    }
    if (!r.ranked) ++unranked;
    further = further || r.at != r.finest || !r.ranked;
    rows.push_back(std::move(r));
  }
  if (rows.empty()) return "";
  const bool any_error = std::any_of(rows.begin(), rows.end(), [](const Row& r) {
    for (const auto& s : {r.at, r.finest})
      if (std::isfinite(s->errors.l2_rel) && s->errors.l2_rel > 0) return true;
    return false;
  });
  if (!any_error) {
    double cpu = 0;
    for (const auto& s : studies)
      for (const auto& c : s.cases) cpu += c.cpu.total();
    return fmt::format("No {} is measured for this problem (its findings judge what the "
                       "studies show); {} stud{}, {:.3f} CPU s in all.\n\n",
                       error_name, rows.size(), rows.size() == 1 ? "y" : "ies", cpu);
  }
  // Best first; an error that is missing, not finite or exactly 0 (nothing measured: no
  // floating-point solution is exact) goes last.
  // Studies that stopped short of the ranking resolution come last, unranked.
  const auto measured = [](const Row& r) {
    const double e = r.at->errors.l2_rel;
    return r.ranked && std::isfinite(e) && e > 0;
  };
  std::stable_sort(rows.begin(), rows.end(), [&](const Row& a, const Row& b) {
    if (measured(a) != measured(b)) return measured(a);
    return measured(a) && a.at->errors.l2_rel < b.at->errors.l2_rel;
  });
  const std::string at =
      common > 0 ? fmt::format("{} {}", common, resolution) : std::string("each study's finest");
  std::string md = fmt::format(
      "Ranked by the {} at {}{}; rate: least-squares slope, with the trend judged from the "
      "pairwise rates and the finest error; CPU s of that case; digits/s: −log₁₀(error) per "
      "CPU second (higher is better).\n\n",
      error_name, at,
      common == 0 ? " (they share no resolution)"
      : unranked > 0
          ? fmt::format(", the finest resolution at least half the studies reached ({} of {}); "
                        "the {} that stopped coarser {} listed last, unranked, with their finest "
                        "error",
                        rows.size() - unranked, rows.size(), unranked,
                        unranked == 1 ? "is" : "are")
          : std::string(", the finest resolution all studies share"));
  std::vector<std::string> head{"method", fmt::format("error at {}", common > 0 ? std::to_string(common) : "finest")};
  if (further) head.push_back("finest error (n)");
  for (const char* c : {"rate (trend)", "CPU s", "digits/s"}) head.push_back(c);
  std::vector<char> align(head.size(), 'r');
  align[0] = 'l';
  align[head.size() - 3] = 'l';
  MarkdownTable t(head, align);
  for (const auto& r : rows) {
    const double e = r.at->errors.l2_rel, cpu = r.at->cpu.total();
    std::vector<std::string> row{r.label, !r.ranked       ? std::string("not reached (unranked)")
                                          : e == 0        ? std::string("0 (not measured?)")
                                                          : fmt_sci(e, 2)};
    if (further)
      row.push_back(r.finest == r.at && r.ranked ? "–"
                                     : fmt::format("{} ({})", fmt_sci(r.finest->errors.l2_rel, 2),
                                                   r.finest->spec.nodes));
    row.push_back(r.trend.trend == Trend::undetermined
                      ? fmt::format("– ({})", r.trend.reason)
                      : fmt::format("{} ({})", fmt_rate(r.trend.fitted_rate),
                                    trend_name(r.trend.trend)));
    row.push_back(fmt::format("{:.3f}", cpu));
    row.push_back(r.ranked && std::isfinite(e) && e > 0 && cpu > 0
                      ? fmt::format("{:.3g}", std::max(0.0, -std::log10(e)) / cpu)
                      : "–");
    t.add_row(row);
  }
  return md + t.str() + "\n";
}

namespace {

/// The one-line verdict counts of the findings and the published values.
std::string verdict_lines(const Registries& plugins, const Problem& problem, const ReportSection& section,
                          const Params& defaults) {
  std::string md;
  const auto findings = problem.findings();
  if (!findings.empty()) {
    const auto summaries = summarize(plugins, section.studies);
    std::vector<std::string> v;
    for (const auto& f : findings) v.push_back(f.check(summaries).status);
    md += fmt::format("Findings of the papers ({}): {}.  \n", v.size(), count_text(v));
  }
  const auto rows = published_rows(problem, section.studies, defaults);
  if (!rows.empty()) {
    std::vector<std::string> v;
    int not_run = 0;
    for (const auto& r : rows) {
      if (r.ours.empty()) ++not_run;
      else v.push_back(judge(r.ours.front().second, r.published).verdict);
    }
    if (v.empty())
      md += fmt::format("Published values: none run in this suite ({} listed on the page).  \n",
                        not_run);
    else
      md += fmt::format("Published values ({} compared): {}{}.  \n", v.size(), count_text(v),
                        not_run > 0 ? fmt::format("; {} not run in this suite", not_run) : "");
  }
  if (!section.failures.empty())
    md += fmt::format("**{} stud{} could not run** (reasons on the page).  \n",
                      section.failures.size(), section.failures.size() == 1 ? "y" : "ies");
  return md;
}

/// A one-line form of an analysis verdict: the text up to the first ';', cut at a word
/// boundary near 100 characters (the whole verdict is on the page).
std::string short_verdict(const std::vector<std::string>& verdicts) {
  if (verdicts.empty()) return "–";
  std::string v = verdicts.front();
  if (const auto semi = v.find(';'); semi != std::string::npos) v = v.substr(0, semi) + " …";
  if (v.size() > 110) {
    const auto space = v.rfind(' ', 100);
    v = v.substr(0, space == std::string::npos ? 100 : space) + " …";
  }
  if (verdicts.size() > 1) v += fmt::format(" (+{} more)", verdicts.size() - 1);
  return v;
}

}  // namespace

std::string figures_summary(const ReportSection& section) {
  MarkdownTable t({"case", "verdict", "CPU s"}, {'l', 'l', 'r'});
  for (const auto& s : section.studies) {
    if (s.cases.empty()) continue;
    const CaseResult& r = s.cases.back();
    const std::string pp = r.spec.problem_params.to_string();
    t.add_row({pp.empty() ? s.label : s.label + " | " + pp, short_verdict(r.data<FigureData>().verdicts),
               fmt::format("{:.3f}", r.cpu.total())});
  }
  return t.rows() > 0 ? t.str() + "\n" : "";
}

namespace {

/// problems/<slug>.md, or <slug>-2.md, … if a page of that name is there already.
std::filesystem::path page_path(const std::filesystem::path& dir, const std::string& title) {
  const std::string base = slug(title);
  std::filesystem::path p = dir / kPagesDir / (base + ".md");
  for (int k = 2; std::filesystem::exists(p); ++k)
    p = dir / kPagesDir / fmt::format("{}-{}.md", base, k);
  return p;
}

}  // namespace

std::string write_problem_section(const Registries& catalogue, const ReportSection& section,
                                  const std::filesystem::path& dir, bool vtk) {
  const auto problem = create_problem(catalogue, section.problem, section.problem_params);
  // A section built by hand may not say its analysis: the problem's default.
  const std::string analysis_name =
      section.analysis.empty() ? problem->analyses().front() : section.analysis;
  const auto analysis = catalogue.analyses.create(analysis_name);
  const Params defaults = resolved_case_params(catalogue, section.problem, Params{}, analysis_name);
  const std::string title = section_title(section);
  const std::string page = analysis->page(catalogue, section, title, dir, vtk);
  make_report_subdir(dir, kPagesDir);
  const std::filesystem::path path = page_path(dir, title);
  write_file_atomic(path, page);
  const std::string link = fmt::format("{}/{}", kPagesDir, path.filename().string());

  std::string md = fmt::format("## {}\n\n{}\n\n", title,
                               catalogue.problems.entry(section.problem).description);
  md += analysis->summary(*problem, section);
  md += verdict_lines(catalogue, *problem, section, defaults);
  md += fmt::format("\n**Details:** [{}]({}) — {}.\n\n", link, link,
                    analysis->page_contents(vtk));
  return md;
}

PlotSpec convergence_plot(const std::string& title, const std::vector<StudyResult>& studies,
                          const std::string& ylabel,
                          const std::function<double(const CaseResult&)>& error,
                          const std::function<double(const Rates&)>& rate) {
  PlotSpec spec;
  spec.title = title;
  spec.xlabel = "nominal particle spacing h (length unit of x)";
  spec.ylabel = ylabel;
  spec.logx = spec.logy = true;
  spec.style = "linespoints";
  double steepest = 0;
  for (const auto& study : studies) {
    Series s;
    const double r = rate(study.rates);
    s.label = fmt::format("{} (rate {})", study.label, fmt_rate(r));
    if (std::isfinite(r)) steepest = std::max(steepest, r);
    for (const auto& c : study.cases) {
      s.x.push_back(c.h);
      s.y.push_back(error(c));
    }
    spec.series.push_back(std::move(s));
  }
  spec.reference_slopes = {1, 2};
  const int top = static_cast<int>(std::lround(std::min(steepest, 10.0)));
  if (top > 2) spec.reference_slopes.push_back(top);
  return spec;
}

PlotSpec convergence_plot(const std::string& title, const std::vector<StudyResult>& studies,
                          bool h1) {
  if (h1)
    return convergence_plot(
        title, studies, "H1 seminorm error ||u_h' - u'||",
        [](const CaseResult& c) { return c.errors.h1_semi; },
        [](const Rates& r) { return r.rate("H1-semi"); });
  return convergence_plot(
      title, studies, "L2 error ||u_h - u||", [](const CaseResult& c) { return c.errors.l2; },
      [](const Rates& r) { return r.rate("L2"); });
}

}  // namespace mfv
