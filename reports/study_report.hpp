/// The Markdown section of a problem's refinement studies: tables of errors, rates and CPU
/// times per method × resolution, published values beside ours, convergence plots, VTK files.
#pragma once
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "verify/case.hpp"
#include "verify/catalogue.hpp"

namespace mfv {

/// The studies of one problem (with one set of problem parameters).
struct ReportSection {
  std::string problem;
  Params problem_params;
  std::vector<StudyResult> studies;
  std::vector<std::string> failures;  ///< "label: message" of studies that could not run
};

/// Groups studies by (problem, problem parameters), in first-seen order.
void add_to_sections(std::vector<ReportSection>& sections, StudyResult study);

/// "laplace-tanh s=10" → "laplace-tanh-s-10": a file-name-safe slug.
std::string slug(const std::string& text);

/// One published value next to our number for it.
struct PublishedComparison {
  PublishedValue published;
  std::string study;       ///< our study's label; empty when no study matches
  double ours = 0;         ///< NaN when not run
};

/// Every published value of the problem against every study that matches it: same method,
/// resolved parameters containing the published ones, a case with the published node count.
/// Quantities: a headline name, "error u" (relative L2 on the common rule) or "error du/dx"
/// (relative H1 seminorm).
std::vector<PublishedComparison> compare_published(const Problem& problem,
                                                   const std::vector<StudyResult>& studies);
/// "### Published values beside ours": the comparisons as a table with the notes, values
/// no study matched, and the problem's published_notes; empty without published values.
std::string published_block(const Problem& problem, const std::vector<StudyResult>& studies);
/// "### The paper's findings and ours": each finding with its verdict on our studies.
std::string findings_block(const Problem& problem, const std::vector<StudyResult>& studies);
/// The section of a transient problem (explicit dynamics): methods and engine settings,
/// findings, errors and CPU per case, rates, convergence and time-history plots, history
/// CSV files, published values, and ParaView time series per case.
std::string write_transient_section(const Catalogue& catalogue, const ReportSection& section,
                                    const std::string& title, const std::filesystem::path& dir,
                                    bool vtk);

/// The section of an analysis problem (dispersion, time steps, enriched bars, stable-domain
/// maps): cases, findings, verdicts and headline values, figures as SVG, tables as CSV.
std::string write_analysis_section(const Catalogue& catalogue, const ReportSection& section,
                                   const std::string& title, const std::filesystem::path& dir);

/// One VTK file per resolution: its name suffix ("-line.vtp") and its writer.
using VtkPart = std::pair<std::string, std::function<void(const std::filesystem::path&,
                                                          const CaseResult&)>>;
/// Writes vtk/<base>/<study>/n<nodes><suffix> for every part and resolution and a study.pvd
/// stepping through the resolutions; returns the Markdown list of links to the .pvd files.
std::string write_vtk_collections(const std::filesystem::path& dir, const std::string& base,
                                  const std::vector<StudyResult>& studies,
                                  const std::vector<VtkPart>& parts);

/// Summaries of studies for a problem's findings (finest case, rates on the common rule).
std::vector<StudySummary> summarize(const std::vector<StudyResult>& studies);

/// The section of a 2D (vector) problem; write_problem_section dispatches to it.
std::string write_elasticity_section(const Catalogue& catalogue, const ReportSection& section,
                                     const std::string& title, const std::filesystem::path& dir,
                                     bool vtk);

/// Writes plots under `dir`/plots and VTK files under `dir`/vtk (when `vtk`), and returns the
/// section's Markdown with links relative to `dir`.
std::string write_problem_section(const Catalogue& catalogue, const ReportSection& section,
                                  const std::filesystem::path& dir, bool vtk);

}  // namespace mfv
