/// The report page of the figure analyses (dispersion, critical time steps, crack sweeps,
/// stable-domain maps): what each case analysed, the findings, every verdict and headline
/// value side by side, the problem's figures as SVG plots and its tables as CSV files.
#include <cmath>
#include <set>

#include <fmt/format.h>

#include "reports/atomic.hpp"
#include "reports/markdown.hpp"
#include "reports/plot.hpp"
#include "analyses/figures.hpp"
#include "analyses/report_section.hpp"

namespace mfv {

namespace fs = std::filesystem;

namespace {

std::string value_text(double v) {
  if (std::isnan(v)) return "–";
  if (v == 0) return "0";
  return std::abs(v) < 1e-2 || std::abs(v) >= 1e5 ? fmt_sci(v, 3) : fmt::format("{:.4g}", v);
}

std::string csv_text(const FigureData::Table& t) {
  std::string out = fmt::format("{}\n", fmt::join(t.columns, ","));
  for (const auto& row : t.rows) {
    std::vector<std::string> cells;
    for (double v : row) cells.push_back(std::isnan(v) ? "nan" : fmt::format("{:.10g}", v));
    out += fmt::format("{}\n", fmt::join(cells, ","));
  }
  return out;
}

/// "kbm-ni kernel=quartic-spline | frame=eulerian,sigma=1": what one analysis case is.
std::string case_label(const StudyResult& s) {
  const std::string pp = s.cases.front().spec.problem_params.to_string();
  return pp.empty() ? s.label : s.label + " | " + pp;
}

}  // namespace

std::string write_analysis_section(const Registries& catalogue, const ReportSection& section,
                                   const std::string& title, const fs::path& dir) {
  const auto problem = create_problem(catalogue, section.problem, section.problem_params);
  const std::string base = slug(title);
  PageParts page;
  page.methods = methods_list(section, [](const StudyResult& s) {
    const CaseResult& r = s.cases.back();
    return fmt::format("`{}`: {}; {}", case_label(s), r.method_description,
                       r.data<FigureData>().setup);
  });

  std::vector<std::string> keys;
  for (const auto& s : section.studies)
    for (const auto& [k, v] : s.cases.back().headline)
      if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
  page.verdicts =
      "One row per case; CPU seconds of the analysis "
      "(set-up of the operator, then the scans).\n\n";
  std::vector<std::string> header{"case", "verdict"};
  std::vector<char> align{'l', 'l'};
  for (const auto& k : keys) {
    header.push_back(k);
    align.push_back('r');
  }
  header.push_back("CPU s");
  align.push_back('r');
  MarkdownTable t(header, align);
  for (const auto& s : section.studies) {
    const CaseResult& r = s.cases.back();
    std::vector<std::string> row{case_label(s), fmt::format("{}", fmt::join(r.data<FigureData>().verdicts, "; "))};
    for (const auto& k : keys) {
      const auto it = r.headline.find(k);
      row.push_back(it == r.headline.end() ? "–" : value_text(it->second));
    }
    row.push_back(fmt::format("{:.3f}", r.cpu.total()));
    t.add_row(row);
  }
  page.verdicts += t.str() + "\n";

  // Figures and data of every case.
  make_report_subdir(dir, "plots");
  make_report_subdir(dir, "data");
  for (const auto& s : section.studies) {
    const CaseResult& r = s.cases.back();
    if (r.data<FigureData>().figures.empty() && r.data<FigureData>().tables.empty()) continue;
    const std::string stem = base + "-" + slug(case_label(s));
    page.plots += fmt::format("**`{}`**", case_label(s));
    std::vector<std::string> links;
    for (const auto& table : r.data<FigureData>().tables) {
      const std::string name = fmt::format("data/{}-{}.csv", stem, table.name);
      write_file_atomic(dir / name, csv_text(table));
      links.push_back(fmt::format("[{}.csv]({}{})", table.name, kPageUp, name));
    }
    if (!links.empty()) page.plots += fmt::format(" (data: {})", fmt::join(links, ", "));
    page.plots += "\n\n";
    for (const auto& fig : r.data<FigureData>().figures) {
      PlotSpec spec;
      spec.title = fmt::format("{}: {}", case_label(s), fig.title);
      spec.xlabel = fig.xlabel;
      spec.ylabel = fig.ylabel;
      spec.logy = fig.logy;
      spec.style = fig.style;
      for (const auto& c : r.data<FigureData>().curves)
        if (c.figure == fig.id) spec.series.push_back(Series{c.label, c.x, c.y});
      page.plots += plot_image(dir, fmt::format("plots/{}-{}.svg", stem, fig.id), spec,
                               fig.title, fig.id);
    }
  }
  return section_page(catalogue, *problem, section, title, std::move(page), dir);
}

std::string FigureAnalysis::page(const Registries& plugins, const ReportSection& section,
                                 const std::string& title, const std::filesystem::path& dir,
                                 bool) const {
  return write_analysis_section(plugins, section, title, dir);
}

std::string FigureAnalysis::summary(const Problem&, const ReportSection& section) const {
  return figures_summary(section);
}

std::string FigureAnalysis::page_contents(bool) const {
  return "every case's verdicts and measured values, figures, CSV data and published values";
}

int FigureAnalysis::print_case(const CaseResult& r, std::ostream& out) const {
  const FigureData& a = r.data<FigureData>();
  out << fmt::format("setup     {}\n", a.setup);
  for (const auto& v : a.verdicts) out << fmt::format("verdict   {}\n", v);
  for (const auto& [k, v] : r.headline) out << fmt::format("  {:<40} {:.6g}\n", k, v);
  out << fmt::format("CPU       {:.3f} s\n", r.cpu.total());
  return 0;
}

}  // namespace mfv
