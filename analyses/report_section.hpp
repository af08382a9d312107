/// A problem's page of the report and its one-screen summary: the page problems/<slug>.md
/// holds the detailed tables (errors, rates, CPU per method × resolution, published values,
/// findings), plots and VTK links; index.md gets a heading, what the problem is, a method
/// ranking, the verdict counts and a link to the page.
#pragma once
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "analyses/analysis.hpp"
#include "analyses/case.hpp"
#include "reports/convergence.hpp"
#include "reports/convergence_table.hpp"
#include "reports/plot.hpp"

namespace mfv {

/// The studies of one problem (with one set of problem parameters).
struct ReportSection {
  std::string problem;
  std::string analysis;  ///< the analysis that ran the studies (analyses/analysis.hpp)
  Params problem_params;
  std::vector<StudyResult> studies;
  std::vector<std::string> failures;  ///< "label: message" of studies that could not run
  /// VTK of each study's finest resolution only (`--vtk=finest`, the nightly's default:
  /// the fields of every resolution were 94 % of a report); false: every resolution.
  bool vtk_finest_only = false;
};

/// Groups studies by (problem, analysis) — and by the problem parameters where the analysis
/// says they make another problem (Analysis::section_per_problem_params) — in first-seen order.
void add_to_sections(const Registries& plugins, std::vector<ReportSection>& sections,
                     StudyResult study);

/// "laplace-tanh s=10" → "laplace-tanh-s-10": a file-name-safe slug.
std::string slug(const std::string& text);

/// The pages' directory inside a report, and the way back from a page to the report's root
/// (plots/, vtk/, data/ and histories/ stay at the root; a page links to them through it).
inline constexpr const char* kPagesDir = "problems";
inline constexpr const char* kPageUp = "../";

/// One published value next to our number for it.
struct PublishedComparison {
  PublishedValue published;
  std::string study;       ///< our study's label; empty when no study matches
  double ours = 0;         ///< NaN when not run
};

/// Every published value of the problem against every study that matches it: same method,
/// resolved parameters containing the published ones, a case with the published node count,
/// the published problem parameters (a key the case left unset is compared at its value in
/// `problem_defaults`, the problem's resolved defaults; without them it matches any value).
/// Quantities: a headline name, "error u" (relative L2 on the common rule) or "error du/dx"
/// (relative H1 seminorm).
std::vector<PublishedComparison> compare_published(const Problem& problem,
                                                   const std::vector<StudyResult>& studies,
                                                   const Params& problem_defaults = {});

/// One row of the published-values table: a published value (listed once however often the
/// problem repeats it) with every study that measured it, first match first.
struct PublishedRow {
  PublishedValue published;
  std::vector<std::pair<std::string, double>> ours;  ///< (study label, finite value)
  /// Studies that matched the case but have no value for the quantity (not measured there).
  std::vector<std::string> unmeasured;
};
/// The published values of the problem, deduplicated, each with what our studies measured.
std::vector<PublishedRow> published_rows(const Problem& problem,
                                         const std::vector<StudyResult>& studies,
                                         const Params& problem_defaults = {});

/// The body of a page's published-values part: one row per published value measured here
/// with ours, the paper's, the ratio ours/paper, the verdict of compare_value under the
/// value's tolerance and numbered notes right under the table (the value's note, other
/// studies that measured it); then the values not run in this suite, grouped, and the
/// problem's published_notes; then each paper table (paper_tables) in the paper's layout,
/// naming its files under tables/<problem_key>/. Empty without published values and notes.
std::string published_block(const Problem& problem, const std::vector<StudyResult>& studies,
                            const Params& problem_defaults = {},
                            const std::string& problem_key = "problem");

/// A paper's table rebuilt with ours beside each entry (issue 28): every published value
/// whose source names a table ("004 II Table 1", "001 §9.2, Table 3") and that has at least
/// two entries: a row per method (with its resolution) when every method sits at one
/// resolution of its own, as 001 Table 3 prints it, with the paper's value and ours per
/// quantity; else a row per quantity and resolution with, per method in the problem's order
/// (the paper's), the paper's value and ours. Ours is the first matching study's; "not run"
/// where none ran it.
struct PaperTable {
  std::string source;
  TextTable table;
};
std::vector<PaperTable> paper_tables(const Problem& problem,
                                     const std::vector<StudyResult>& studies,
                                     const Params& problem_defaults = {});
/// The file stem of a paper table: "paper-<slug of the source>".
std::string paper_table_stem(const std::string& source);
/// One finding of a problem checked on the studies that ran.
struct FindingOutcome {
  const Finding* finding = nullptr;
  Verdict verdict;
  /// For a finding that could not be judged ("not run"): what did run, so that "no study of
  /// kbm-si" is never read as "kbm-si did not run" when it ran under other conditions.
  std::string ran;
};

/// Checks every finding of `findings` (a problem's) on `studies` (summarized once). A study
/// belongs to the problem's findings whatever its method parameters; each finding matches
/// the studies it needs by method and parameters itself.
std::vector<FindingOutcome> check_findings(const Registries& plugins,
                                           const std::vector<Finding>& findings,
                                           const std::vector<StudyResult>& studies);

/// The findings as `mfv study` and `compare` print them after their tables: one line per
/// finding (verdict, source, claim, ours). Empty when the problem has none.
std::string findings_text(const Registries& plugins, const Problem& problem,
                          const std::vector<StudyResult>& studies);

/// The body of a page's findings part: each finding of the papers with its verdict on our
/// studies. Empty when the problem has no findings.
std::string findings_block(const Registries& plugins, const Problem& problem,
                           const std::vector<StudyResult>& studies);

/// The parts of a problem's page, each a Markdown body without its heading; an empty part is
/// left out with its heading. problem_page writes them in this order under the same headings
/// on every page, so that each analysis fills the parts it has and no page invents its own
/// layout.
struct PageParts {
  std::string lead;       ///< under the description: exact values, what a resolution counts
  std::string methods;    ///< "**Methods.**": one list item per study (methods_list)
  std::string findings;   ///< "## The paper's findings and ours" (findings_block)
  std::string errors;     ///< "## Errors and CPU times": per case
  std::string verdicts;   ///< "## Verdicts and measured values": per case, analyses without errors
  std::string rates;      ///< "## Convergence rates": per study
  std::string plots;      ///< "## Plots": convergence plots, time histories, figures, data files
  std::string published;  ///< "## Published values beside ours" (published_block)
  std::string vtk;        ///< "## VTK files": links to the ParaView files
};
/// The page: "# title", the link back to the report, the description, then the parts.
std::string problem_page(const std::string& title, const std::string& description,
                         const PageParts& parts);

/// A problem's page from the parts an analysis writes: the findings and the published values
/// (the same blocks for every analysis) are filled in here, then problem_page lays it out
/// under the problem's description. Writes the paper tables' CSV and LaTeX under
/// `dir`/tables/<problem>/.
std::string section_page(const Registries& plugins, const Problem& problem,
                         const ReportSection& section, const std::string& title,
                         PageParts page, const std::filesystem::path& dir);
/// The methods part: "- `<label>`: <what>" per study (`item` gives label and text, already
/// joined), then one "**could not run:**" item per failure of the section.
std::string methods_list(const ReportSection& section,
                         const std::function<std::string(const StudyResult&)>& item);
/// The lead of a page with resolutions: the problem's exact headline values, if any, and what
/// a resolution counts ("Exact: tip deflection = 0.00889. Resolutions count nodes.").
std::string page_lead(const Problem& problem);
/// Writes `spec` as the SVG `name` (under `dir`, "plots/…") and returns its Markdown image
/// "![alt](../plots/…)", or "_<what> plot skipped: <why>_" when it could not be drawn. A
/// plot of more than kMaxCurves computed curves is split (split_plot) into
/// "<stem>-part1.svg", "<stem>-part2.svg", …, one image each.
std::string plot_image(const std::filesystem::path& dir, const std::string& name,
                       const PlotSpec& spec, const std::string& alt, const std::string& what);

/// The page of a transient problem (explicit dynamics): methods and engine settings,
/// findings, errors and CPU per case, rates, convergence and time-history plots, history
/// CSV files, published values, and ParaView time series per case.
std::string write_transient_section(const Registries& catalogue, const ReportSection& section,
                                    const std::string& title, const std::filesystem::path& dir,
                                    bool vtk);

/// The page of a figure analysis (dispersion, time steps, crack sweeps, stable-domain
/// maps): cases, findings, verdicts and headline values, figures as SVG, tables as CSV.
std::string write_analysis_section(const Registries& catalogue, const ReportSection& section,
                                   const std::string& title, const std::filesystem::path& dir);

/// One VTK file per resolution: its name suffix ("-line.vtp") and its writer.
using VtkPart = std::pair<std::string, std::function<void(const std::filesystem::path&,
                                                          const CaseResult&)>>;
/// Writes vtk/<base>/<study>/n<nodes><suffix> for every part and resolution and a study.pvd
/// whose time axis is the particle spacing h (ParaView's "time" steps through the
/// resolutions, finest first); returns the Markdown list of links to the .pvd files,
/// relative to a page (through kPageUp).
/// With `finest_only`, each study's finest resolution alone (the .pvd then holds one step).
std::string write_vtk_collections(const std::filesystem::path& dir, const std::string& base,
                                  const std::vector<StudyResult>& studies,
                                  const std::vector<VtkPart>& parts, bool finest_only = false);

/// The convergence judgement (reports/convergence.hpp) of `error` over a study's cases.
ConvergenceJudgement judge_study(const StudyResult& study,
                                 const std::function<double(const CaseResult&)>& error);

/// Summaries of studies for a problem's findings (finest case, rates on the common rule).
std::vector<StudySummary> summarize(const Registries& plugins,
                                    const std::vector<StudyResult>& studies);

/// The method ranking of a section with errors: relative L2 error (the problem's main field)
/// at the finest resolution at least half the studies (and two) reached, else the finest
/// common one; the finest error where a study goes further; studies that stopped short
/// last, unranked, with their finest error; the fitted rate with its trend, CPU seconds and
/// correct digits per CPU second; best first.
std::string ranking_block(const std::vector<StudyResult>& studies, const std::string& resolution,
                          const std::string& error_name);

/// The page of a 1D scalar problem (static solves).
std::string write_scalar_page(const Registries& catalogue, const ReportSection& section,
                              const std::string& title, const std::filesystem::path& dir,
                              bool vtk);

/// Each case's verdict in one row (the summary of the figure analyses).
std::string figures_summary(const ReportSection& section);

/// The page of a 2D (vector) problem (static solves).
std::string write_elasticity_section(const Registries& catalogue, const ReportSection& section,
                                     const std::string& title, const std::filesystem::path& dir,
                                     bool vtk);

/// Writes the section's page `dir`/problems/<slug>.md (a new slug if a page of that name
/// exists already), plots under `dir`/plots and VTK files under `dir`/vtk (when `vtk`), and
/// returns the one-screen summary for index.md: heading, what the problem is, the method
/// ranking at the finest resolution at least half the studies reached, the others listed
/// unranked (analyses: each case's verdict), the
/// findings' and published values' verdict counts, and the link to the page.
std::string write_problem_section(const Registries& catalogue, const ReportSection& section,
                                  const std::filesystem::path& dir, bool vtk);

/// A log–log plot of the error against h, one series per study, labelled
/// "<study label> (rate 2.01)": the L2 error and its rate ("L2"), or with `h1` the H1
/// seminorm error and its rate ("H1-semi"). Errors are CaseResult::errors (the common fine rule). Reference
/// slopes 1 and 2, and the largest fitted rate rounded when it is above 2.
PlotSpec convergence_plot(const std::string& title, const std::vector<StudyResult>& studies,
                          bool h1);

/// The same for any norm: `error` of each case against h, labelled with `rate` of each study.
PlotSpec convergence_plot(const std::string& title, const std::vector<StudyResult>& studies,
                          const std::string& ylabel,
                          const std::function<double(const CaseResult&)>& error,
                          const std::function<double(const Rates&)>& rate);

}  // namespace mfv
