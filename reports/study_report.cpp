#include "reports/study_report.hpp"

#include <cctype>
#include <cmath>
#include <limits>
#include <set>

#include <fmt/format.h>

#include "reports/markdown.hpp"
#include "reports/plot.hpp"
#include "reports/vtk.hpp"

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

double our_value(const CaseResult& r, const std::string& quantity) {
  if (quantity == "error u") return r.errors.l2_rel;
  if (quantity == "error du/dx") return r.errors.h1_semi_rel;
  const auto it = r.headline.find(quantity);
  return it == r.headline.end() ? kNaN : it->second;
}

std::string join_lines(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& l : lines) out += l + "\n";
  return out;
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

void add_to_sections(std::vector<ReportSection>& sections, StudyResult study) {
  if (study.cases.empty()) return;
  const CaseSpec& spec = study.cases.front().spec;
  // Transient studies of one problem share a section whatever their loading, frame or
  // prestress: their findings compare across those parameters (Lagrangian vs Eulerian,
  // σ̄ sweeps), and each study's parameters are in its label and engine description.
  // Analyses likewise: one section per problem, the parameters of each case in its row.
  const bool transient = study.cases.front().transient.steps > 0;
  const bool analysis = !study.cases.front().analysis.empty();
  const Params key = transient || analysis ? Params{} : spec.problem_params;
  for (auto& s : sections) {
    if (s.problem == spec.problem && s.problem_params.to_string() == key.to_string()) {
      s.studies.push_back(std::move(study));
      return;
    }
  }
  ReportSection s;
  s.problem = spec.problem;
  s.problem_params = key;
  s.studies.push_back(std::move(study));
  sections.push_back(std::move(s));
}

std::vector<PublishedComparison> compare_published(const Problem& problem,
                                                   const std::vector<StudyResult>& studies) {
  std::vector<PublishedComparison> out;
  for (const auto& pv : problem.published()) {
    bool matched = false;
    for (const auto& s : studies) {
      for (const auto& r : s.cases) {
        if (r.spec.method != pv.method || r.spec.nodes != pv.nodes) continue;
        if (!params_match(r.method_params, pv.method_params)) continue;
        bool same_problem = true;
        for (const auto& [k, v] : pv.problem_params.values())
          if (r.spec.problem_params.has(k) &&
              format_value(r.spec.problem_params.values().at(k)) != format_value(v))
            same_problem = false;
        if (!same_problem) continue;
        out.push_back({pv, s.label, our_value(r, pv.quantity)});
        matched = true;
      }
    }
    if (!matched) out.push_back({pv, "", kNaN});
  }
  return out;
}

std::string write_vtk_collections(const std::filesystem::path& dir, const std::string& base,
                                  const std::vector<StudyResult>& studies,
                                  const std::vector<VtkPart>& parts) {
  std::string md;
  for (const auto& s : studies) {
    const std::string sub = fmt::format("vtk/{}/{}", base, slug(s.label));
    std::filesystem::create_directories(dir / sub);
    std::vector<std::pair<double, std::string>> entries;
    for (std::size_t i = 0; i < s.cases.size(); ++i)
      for (const auto& [suffix, write] : parts) {
        const std::string name = fmt::format("n{}{}", s.cases[i].spec.nodes, suffix);
        write(dir / sub / name, s.cases[i]);
        entries.emplace_back(static_cast<double>(i), name);
      }
    write_pvd(dir / sub / "study.pvd", entries);
    md += fmt::format("- `{}`: [{}/study.pvd]({}/study.pvd)\n", s.label, sub, sub);
  }
  return md + "\n";
}

std::string published_block(const Problem& problem, const std::vector<StudyResult>& studies) {
  std::string md;
  const auto comparisons = compare_published(problem, studies);
  if (!comparisons.empty()) {
    md += "### Published values beside ours\n\n";
    MarkdownTable t({"source", "quantity", "method", "nodes", "paper", "ours", "ours − paper",
                     "our study"},
                    {'l', 'l', 'l', 'r', 'r', 'r', 'r', 'l'});
    std::set<std::string> notes;
    int not_run = 0;
    std::vector<std::string> not_run_examples;
    for (const auto& c : comparisons) {
      const PublishedValue& p = c.published;
      const std::string params = p.method_params.to_string();
      const std::string method = params.empty() ? p.method : p.method + " " + params;
      if (c.study.empty()) {
        ++not_run;
        if (not_run_examples.size() < 4)
          not_run_examples.push_back(fmt::format("{} at {} nodes", method, p.nodes));
        continue;
      }
      if (!p.note.empty()) notes.insert(fmt::format("{}: {}", p.source, p.note));
      const bool small = std::abs(p.value) < 1;
      t.add_row({p.source, p.quantity, method, std::to_string(p.nodes),
                 small ? fmt_sci(p.value, 4) : fmt::format("{:.4f}", p.value),
                 small ? fmt_sci(c.ours, 4) : fmt::format("{:.4f}", c.ours),
                 std::isnan(c.ours) ? "–" : fmt::format("{:+.4g}", c.ours - p.value), c.study});
    }
    if (t.rows() > 0) md += t.str() + "\n";
    for (const auto& n : notes) md += fmt::format("_{}._\n", n);
    if (not_run > 0)
      md += fmt::format("\n{} published value(s) have no matching study in this run (e.g. {}); "
                        "run them with `mfv compare` or the `--full` suite.\n",
                        not_run, fmt::join(not_run_examples, "; "));
    md += "\n";
    const auto explain = problem.published_notes();
    if (!explain.empty()) md += join_lines(explain) + "\n";
  }
  return md;
}

std::string write_problem_section(const Catalogue& catalogue, const ReportSection& section,
                                  const std::filesystem::path& dir, bool vtk) {
  namespace fs = std::filesystem;
  const auto problem = catalogue.problems.create(section.problem, section.problem_params);
  const std::string title = section_title(section);
  if (problem->transient())
    return write_transient_section(catalogue, section, title, dir, vtk);
  if (problem->analysis()) return write_analysis_section(catalogue, section, title, dir);
  if (!section.studies.empty() && !section.studies.front().cases.empty() &&
      section.studies.front().cases.front().components > 1)
    return write_elasticity_section(catalogue, section, title, dir, vtk);
  const std::string base = slug(title);
  std::string md = fmt::format("## {}\n\n{}\n\n", title,
                               catalogue.problems.entry(section.problem).description);

  const auto exact_headline = problem->headline_exact();
  std::vector<std::string> headline_names;
  for (const auto& s : section.studies)
    for (const auto& r : s.cases)
      for (const auto& [k, v] : r.headline)
        if (std::find(headline_names.begin(), headline_names.end(), k) == headline_names.end())
          headline_names.push_back(k);
  if (!exact_headline.empty()) {
    std::vector<std::string> parts;
    for (const auto& [k, v] : exact_headline) parts.push_back(fmt::format("{} = {:.6g}", k, v));
    md += fmt::format("Exact: {}.\n\n", fmt::join(parts, ", "));
  }

  // 1. Methods: what each study label stands for.
  md += "**Methods.**\n\n";
  for (const auto& s : section.studies)
    md += fmt::format("- `{}`: {}\n", s.label, s.cases.front().method_description);
  for (const auto& f : section.failures) md += fmt::format("- **could not run:** {}\n", f);
  md += "\n";

  // 2. Errors and times per resolution.
  md += "### Errors and CPU times\n\nErrors on the common rule (uniform cells, 6 Gauss points "
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
        row.push_back(fmt_sci(r.solve.condition, 1));
        row.push_back(fmt::format("{:.4f}", r.cpu.setup));
        row.push_back(fmt::format("{:.4f}", r.cpu.assembly));
        row.push_back(fmt::format("{:.4f}", r.cpu.solve));
        t.add_row(row);
      }
    }
    md += t.str() + "\n";
  }

  // 3. Rates.
  md += "### Convergence rates\n\nLeast-squares slope of ln e against ln h over all "
        "resolutions (004 II eq 7.3), and the slope between successive resolutions; the paper "
        "rule integrates with 12 Gauss points between neighbouring particles.\n\n";
  {
    MarkdownTable t({"method", "L2 rate", "L2 pairwise", "H1 rate", "H1 pairwise",
                     "L2 rate (paper rule)", "H1 rate (paper rule)"},
                    {'l', 'r', 'r', 'r', 'r', 'r', 'r'});
    for (const auto& s : section.studies)
      t.add_row({s.label, fmt_rate(s.rates.l2), fmt_rates(s.rates.l2_pairwise),
                 fmt_rate(s.rates.h1_semi), fmt_rates(s.rates.h1_semi_pairwise),
                 fmt_rate(s.rates_paper.l2), fmt_rate(s.rates_paper.h1_semi)});
    md += t.str() + "\n";
  }

  // 4. Plots.
  fs::create_directories(dir / "plots");
  for (bool h1 : {false, true}) {
    const std::string name = fmt::format("plots/{}-{}.svg", base, h1 ? "h1" : "l2");
    const PlotSpec spec = convergence_plot(
        fmt::format("{}: {} error", title, h1 ? "H1 seminorm" : "L2"), section.studies, h1);
    if (const auto why = write_svg_plot(dir / name, spec))
      md += fmt::format("_{} plot skipped: {}_\n\n", h1 ? "H1" : "L2", *why);
    else
      md += fmt::format("![{} error against h]({})\n\n", h1 ? "H1 seminorm" : "L2", name);
  }

  // 5. Published values beside ours.
  md += published_block(*problem, section.studies);

  // 6. VTK files: one ParaView collection per study, stepping through the resolutions.
  if (vtk) {
    md += "### VTK files\n\nParticles (u_h, u_exact, error, du/dx, coefficients, volumes) and "
          "the densely sampled solution as a line; open the `.pvd` in ParaView and step "
          "through the resolutions.\n\n";
    md += write_vtk_collections(dir, base, section.studies,
                                {{".vtp", write_case_vtp}, {"-line.vtp", write_line_vtp}});
  }
  return md;
}

}  // namespace mfv
