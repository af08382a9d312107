/// The readable report: the shared convergence judgement (reports/convergence.hpp), the
/// cantilever findings that use it, and the problem pages with their one-screen summaries.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "reports/plot.hpp"
#include "analyses/report_section.hpp"
#include "temp_files.hpp"
#include "apps/catalogue.hpp"
#include "reports/convergence.hpp"

namespace mfv {
namespace {

/// Errors at spacings h from a coarsest error and the pairwise rates between them.
std::vector<double> errors_from_rates(double e0, const std::vector<double>& h,
                                      const std::vector<double>& rates) {
  std::vector<double> e{e0};
  for (std::size_t i = 0; i < rates.size(); ++i)
    e.push_back(e.back() * std::pow(h[i + 1] / h[i], rates[i]));
  return e;
}

struct TrendCase {
  const char* name;
  std::vector<double> h;
  std::vector<double> rates;  ///< pairwise, used to build the errors
  Trend expected;
  const char* reason_part;    ///< a piece of the reason that must be printed
};

class Judgement : public ::testing::TestWithParam<TrendCase> {};

TEST_P(Judgement, TrendFollowsPairwiseRatesAndFinestError) {
  const TrendCase& c = GetParam();
  const auto e = errors_from_rates(1e-2, c.h, c.rates);
  const ConvergenceJudgement j = judge_convergence(e, c.h);
  EXPECT_EQ(trend_name(j.trend), std::string(trend_name(c.expected))) << j.reason;
  ASSERT_EQ(j.pairwise.size(), c.rates.size());
  for (std::size_t i = 0; i < c.rates.size(); ++i) EXPECT_NEAR(j.pairwise[i], c.rates[i], 1e-9);
  EXPECT_NE(j.reason.find(c.reason_part), std::string::npos) << j.reason;
  EXPECT_EQ(j.converges(), c.expected == Trend::converges);
  if (c.expected != Trend::converges) {
    EXPECT_EQ(j.label().find("converges"), std::string::npos) << j.label();
  }
}

// The cantilever's constant-support resolutions 5, 7, 9, 13 across the depth D = 12:
// h = 3, 2, 1.5, 1. EFG ci there had pairwise rates 6.5, 9.2, −9.3 and a least-squares
// slope of 1.9 — an error that rises 43× at the finest resolution is no convergence.
const std::vector<double> kCantileverH{3, 2, 1.5, 1};
INSTANTIATE_TEST_SUITE_P(
    Cases, Judgement,
    ::testing::Values(
        TrendCase{"second_order", {1, 0.5, 0.25, 0.125}, {2, 2, 2}, Trend::converges,
                  "finest error is the smallest"},
        TrendCase{"preasymptotic_then_second_order", {1, 0.5, 0.25, 0.125}, {-0.3, 1.5, 2},
                  Trend::converges, "pairwise rates -0.30, 1.50, 2.00"},
        TrendCase{"efg_ci_constant_support", kCantileverH, {6.5, 9.2, -9.3}, Trend::erratic,
                  "pairwise rates 6.50, 9.20, -9.30; finest error 43"},
        TrendCase{"kbm_si_stagnating", {1, 0.5, 0.25, 0.125}, {1.0, 0.3, 0.05},
                  Trend::stagnates, "the last below 0.5"},
        TrendCase{"sph_constant_support_rising", kCantileverH, {-0.5, -0.6, -0.6},
                  Trend::diverges, "the coarsest"},
        TrendCase{"rising_at_the_end", {1, 0.5, 0.25, 0.125}, {0.5, -0.3, -1.0},
                  Trend::diverges, "pairwise rates 0.50, -0.30, -1.00"},
        TrendCase{"flat", {1, 0.5, 0.25}, {0, 0}, Trend::stagnates, "pairwise rates 0.00, 0.00"},
        TrendCase{"back_where_it_started", {1, 0.5, 0.25}, {1, -1}, Trend::erratic,
                  "finest error 2× the smallest"},
        TrendCase{"converged_to_roundoff_then_noise", {1, 0.5, 0.25, 0.125}, {8, 3, -1.5},
                  Trend::erratic, "the smallest"}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(Judgement, MissingOrBadInputIsUndeterminedNeverConverges) {
  const std::vector<double> h{1, 0.5, 0.25};
  struct Bad {
    std::vector<double> e, h;
    const char* reason;
  };
  for (const Bad& b : std::vector<Bad>{
           {{1e-2}, {1}, "fewer than two"},
           {{}, {}, "fewer than two"},
           {{1e-2, 2.5e-3}, h, "2 errors for 3 spacings"},
           {{1e-2, NAN, 6e-4}, h, "is nan"},
           {{1e-2, INFINITY, 6e-4}, h, "is inf"},
           {{1e-2, 0, 6e-4}, h, "is 0"},
           {{1e-2, -1e-3, 6e-4}, h, "is -0.001"},
           {{1e-2, 2.5e-3, 6e-4}, {1, 0, 0.25}, "not positive"},
           {{1e-2, 2.5e-3, 6e-4}, {1, 1, 0.25}, "do not decrease"},
       }) {
    const auto j = judge_convergence(b.e, b.h);
    EXPECT_EQ(j.trend, Trend::undetermined) << b.reason;
    EXPECT_FALSE(j.converges());
    EXPECT_TRUE(std::isnan(j.fitted_rate));
    EXPECT_NE(j.reason.find(b.reason), std::string::npos) << j.reason;
  }
}

TEST(Judgement, LabelNamesTheRateOnlyWhenItConverges) {
  const std::vector<double> h{1, 0.5, 0.25};
  EXPECT_EQ(judge_convergence({1e-2, 2.5e-3, 6.25e-4}, h).label(), "converges (rate 2.00)");
  const auto j = judge_convergence({1e-2, 1e-2 * 0.99, 1e-2 * 0.985}, h);
  EXPECT_EQ(j.label().rfind("stagnates (", 0), 0u) << j.label();
}

/// The cantilever findings that say "converges" ask the judgement, not the slope.
TEST(CantileverFindings, ConstantSupportConvergenceUsesTheJudgement) {
  const Catalogue catalogue;
  const auto p = catalogue.problems.create("cantilever");
  auto verdict_of = [&](const StudySummary& s, const std::string& claim_start) {
    for (const auto& f : p->findings())
      if (f.claim.rfind(claim_start, 0) == 0) return f.check({s});
    return Verdict{"no such finding", ""};
  };
  StudySummary efg;
  efg.method = "efg-ci";
  efg.label = "efg-ci radius=4.5";
  efg.params.set("radius", 4.5);
  efg.resolutions = 4;
  efg.h = kCantileverH;
  efg.l2_rel = errors_from_rates(1e-2, efg.h, {6.5, 9.2, -9.3});
  efg.l2_rate = 1.9;  // the slope alone would pass
  efg.l2_trend = judge_convergence(efg.l2_rel, efg.h);
  const Verdict v = verdict_of(efg, "EFG with cell integration converges");
  EXPECT_EQ(v.status, "not reproduced") << v.ours;
  EXPECT_NE(v.ours.find("erratic"), std::string::npos) << v.ours;

  efg.l2_rel = errors_from_rates(1e-2, efg.h, {2, 2, 2});
  efg.l2_trend = judge_convergence(efg.l2_rel, efg.h);
  EXPECT_EQ(verdict_of(efg, "EFG with cell integration converges").status, "reproduced");

  StudySummary sph = efg;
  sph.method = "sph";
  sph.label = "sph radius=4.5";
  EXPECT_EQ(verdict_of(sph, "SPH converges when the support").status, "reproduced");
  sph.l2_rel = errors_from_rates(1e-2, sph.h, {-0.5, -0.6, -0.6});
  sph.l2_trend = judge_convergence(sph.l2_rel, sph.h);
  sph.l2_rate = 0.6;
  EXPECT_EQ(verdict_of(sph, "SPH converges when the support").status, "not reproduced");
}

// ------------------------------------------------------------------ problem pages

namespace fs = std::filesystem;
using test::read_file;
using test::TempDir;

const Catalogue& catalogue() {
  static const Catalogue c;
  return c;
}

/// A laplace-tanh study of `method` at `nodes` with second-order errors, CPU times and the
/// headline 004 II Table 1 prints (peak du/dx at x = 3), unless `with_peak` is false.
StudyResult laplace_study(const std::string& label, const std::string& method,
                          const std::vector<int>& nodes, double scale, bool with_peak = true) {
  StudyResult s;
  s.label = label;
  for (int n : nodes) {
    CaseResult c;
    c.spec.problem = "laplace-tanh";
    c.spec.method = method;
    c.spec.nodes = n;
    c.method_description = method + " (synthetic)";
    c.h = 6.0 / (n - 1);
    c.errors.l2 = c.errors.l2_rel = scale * c.h * c.h;
    c.errors.h1_semi = c.errors.h1_semi_rel = scale * c.h;
    c.cpu.assembly = 1e-4 * n;
    if (with_peak) c.headline["peak du/dx at x=3"] = 10 - 30.0 / n;
    s.cases.push_back(c);
  }
  std::vector<double> h, e;
  for (const auto& c : s.cases) {
    h.push_back(c.h);
    e.push_back(c.errors.l2);
  }
  s.rates.fitted["L2"] = s.rates.fitted["H1-semi"] = 2;
  return s;
}

ReportSection laplace_section() {
  ReportSection section;
  section.problem = "laplace-tanh";
  section.studies.push_back(laplace_study("fem-a", "fem", {21, 41, 81, 161, 241}, 1.0));
  // Matches the same published FEM values: one row each, the second study in a note.
  section.studies.push_back(laplace_study("fem-b", "fem", {21, 41, 81, 161}, 3.0));
  return section;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

/// The rows of the Markdown table that follows `heading` in `md`.
std::vector<std::string> table_after(const std::string& md, const std::string& heading) {
  const auto at = md.find(heading);
  if (at == std::string::npos) return {};
  std::vector<std::string> rows;
  bool in_table = false;
  for (const auto& l : lines_of(md.substr(at))) {
    if (l.starts_with("|")) {
      in_table = true;
      rows.push_back(l);
    } else if (in_table) {
      break;
    }
  }
  return rows.size() >= 2 ? std::vector<std::string>(rows.begin() + 2, rows.end()) : rows;
}

/// The trimmed cells of a Markdown table row.
std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  std::size_t start = 1;
  for (std::size_t bar = row.find('|', start); bar != std::string::npos;
       start = bar + 1, bar = row.find('|', start)) {
    std::string c = row.substr(start, bar - start);
    c.erase(0, c.find_first_not_of(' '));
    c.erase(c.find_last_not_of(' ') + 1);
    out.push_back(c);
  }
  return out;
}

TEST(ProblemPage, IsWrittenAndLinkedFromASmallSummary) {
  TempDir dir("mfv-pages");
  const ReportSection section = laplace_section();
  const std::string summary = write_problem_section(catalogue(), section, dir.path(), false);
  const fs::path page = dir.path() / "problems" / "laplace-tanh.md";
  ASSERT_TRUE(fs::exists(page));
  EXPECT_NE(summary.find("## laplace-tanh"), std::string::npos) << summary;
  EXPECT_NE(summary.find("](problems/laplace-tanh.md)"), std::string::npos) << summary;
  // One screen: the ranking and counts, not the per-resolution tables.
  EXPECT_LT(summary.size(), 2500u) << summary;
  EXPECT_LT(lines_of(summary).size(), 25u) << summary;
  EXPECT_EQ(summary.find("### "), std::string::npos) << summary;
  EXPECT_EQ(summary.find("Errors and CPU times"), std::string::npos);

  const std::string text = read_file(page);
  EXPECT_EQ(text.rfind("# laplace-tanh", 0), 0u) << text.substr(0, 200);
  EXPECT_NE(text.find("](../index.md)"), std::string::npos);
  EXPECT_NE(text.find("## Errors and CPU times"), std::string::npos);
  EXPECT_NE(text.find("## Convergence rates"), std::string::npos);
  // Every link of the page into the report's folders goes up from problems/.
  for (const char* folder : {"(plots/", "(vtk/", "(data/", "(histories/"})
    EXPECT_EQ(text.find(folder), std::string::npos) << folder;
  if (gnuplot_available()) {
    EXPECT_NE(text.find("](../plots/laplace-tanh-l2.svg)"), std::string::npos);
    EXPECT_TRUE(fs::exists(dir.path() / "plots" / "laplace-tanh-l2.svg"));
  }
  // Every relative link of the page resolves from the page's own folder (index.md is the
  // caller's to write).
  for (std::size_t at = text.find("]("); at != std::string::npos; at = text.find("](", at + 2)) {
    const std::string target = text.substr(at + 2, text.find(')', at) - at - 2);
    if (target != "../index.md") {
      EXPECT_TRUE(fs::exists(page.parent_path() / target)) << target;
    }
  }
}

TEST(ProblemPage, RankingIsAtTheFinestCommonResolutionBestFirst) {
  TempDir dir("mfv-pages");
  const std::string summary =
      write_problem_section(catalogue(), laplace_section(), dir.path(), false);
  EXPECT_NE(summary.find("at 161 nodes, the finest resolution all studies share"),
            std::string::npos)
      << summary;
  const auto rows = table_after(summary, "Ranked by");
  ASSERT_EQ(rows.size(), 2u) << summary;
  EXPECT_EQ(rows[0].find("| fem-a "), 0u) << rows[0];  // 3× smaller errors
  EXPECT_NE(rows[0].find("(241)"), std::string::npos) << "fem-a goes further: " << rows[0];
  EXPECT_NE(rows[0].find("2.00 (converges)"), std::string::npos) << rows[0];
  EXPECT_NE(summary.find("digits/s"), std::string::npos);
  EXPECT_NE(summary.find("Published values (5 compared)"), std::string::npos) << summary;
}

TEST(ProblemPage, AStudyStoppedCoarseIsListedUnrankedNotTheRankingsResolution) {
  TempDir dir("mfv-pages");
  ReportSection section = laplace_section();
  // Errors 100× smaller, but only at 21 nodes: it would rank first at 21 if it set the
  // resolution for everyone.
  section.studies.push_back(laplace_study("coarse-only", "fem", {21}, 0.01));
  const std::string summary = write_problem_section(catalogue(), section, dir.path(), false);
  EXPECT_NE(summary.find("at 161 nodes, the finest resolution at least half the studies reached "
                         "(2 of 3); the 1 that stopped coarser is listed last, unranked"),
            std::string::npos)
      << summary;
  const auto rows = table_after(summary, "Ranked by");
  ASSERT_EQ(rows.size(), 3u) << summary;
  EXPECT_EQ(rows[0].find("| fem-a "), 0u) << rows[0];
  EXPECT_EQ(rows[2].find("| coarse-only "), 0u) << rows[2];
  EXPECT_NE(rows[2].find("not reached (unranked)"), std::string::npos) << rows[2];
  EXPECT_NE(rows[2].find("(21)"), std::string::npos) << "its finest error shown: " << rows[2];
}

TEST(ProblemPage, PaperTablesInThePapersLayoutAsMarkdownCsvAndLatex) {
  TempDir dir("mfv-pages");
  write_problem_section(catalogue(), laplace_section(), dir.path(), false);
  const std::string page = read_file(dir.path() / "problems" / "laplace-tanh.md");
  EXPECT_NE(page.find("**004 II Table 1 in the paper's layout**"), std::string::npos) << page;
  const fs::path csv = dir.path() / "tables" / "laplace-tanh" / "paper-004-ii-table-1.csv";
  ASSERT_TRUE(fs::exists(csv)) << page;
  const std::string text = read_file(csv);
  // The paper's columns: RKPM at each dilation, then FEM; a row per node count.
  const std::string head = text.substr(0, text.find('\n'));
  EXPECT_EQ(head.find("quantity,n,\"rkpm j=0.5,kernel=gaussian: paper\""), 0u) << head;
  EXPECT_TRUE(head.ends_with(",fem: paper,fem: ours")) << head;
  // 241 nodes: the paper's FEM 9.7967 beside ours, 10 − 30/241; RKPM not run here.
  EXPECT_NE(text.find("peak du/dx at x=3,241,9.858,not run,"), std::string::npos) << text;
  EXPECT_NE(text.find(",9.7967,9.8755\n"), std::string::npos) << text;
  const std::string tex = read_file(csv.parent_path() / "paper-004-ii-table-1.tex");
  EXPECT_NE(tex.find("\\begin{tabular}{lrrrrrrrrrrrrrrr}"), std::string::npos) << tex;
  EXPECT_NE(tex.find("& 9.7967 & 9.8755 \\\\"), std::string::npos) << tex;
  EXPECT_NE(tex.find("\\toprule"), std::string::npos);
  EXPECT_NE(tex.find("\\bottomrule"), std::string::npos);
}

TEST(TextTable, ShortRowsAreRefusedAndCsvQuotes) {
  TextTable t{{"a", "b"}, {}, {{"x, y", "1"}}};
  EXPECT_EQ(t.csv(), "a,b\n\"x, y\",1\n");
  EXPECT_NE(t.tex().find("x, y & 1 \\\\"), std::string::npos) << t.tex();
  t.rows.push_back({"only one"});
  EXPECT_THROW(t.csv(), std::invalid_argument);
  EXPECT_THROW(t.markdown(), std::invalid_argument);
}

TEST(ProblemPage, PublishedValuesOneRowEachWithRatioAndVerdict) {
  TempDir dir("mfv-pages");
  ReportSection section = laplace_section();
  // A study that matches the RKPM values' method and nodes but does not measure the peak.
  StudyResult rkpm = laplace_study("rkpm-no-peak", "rkpm", {21}, 1.0, false);
  rkpm.cases[0].method_params.set("kernel", "gaussian");
  rkpm.cases[0].method_params.set("j", 1.0);
  section.studies.push_back(rkpm);
  write_problem_section(catalogue(), section, dir.path(), false);
  const std::string page = read_file(dir.path() / "problems" / "laplace-tanh.md");
  const auto rows = table_after(page, "## Published values beside ours");
  ASSERT_EQ(rows.size(), 5u) << page;  // the five FEM values of Table 1, once each
  std::set<std::string> unique(rows.begin(), rows.end());
  EXPECT_EQ(unique.size(), rows.size());
  for (const auto& r : rows) {
    EXPECT_NE(r.find("| fem "), std::string::npos) << r;
    EXPECT_NE(r.find("| fem-a "), std::string::npos) << "first matching study: " << r;
    EXPECT_NE(r.find(" 1% | "), std::string::npos) << r;
    EXPECT_TRUE(r.find("| reproduced ") != std::string::npos ||
                r.find("| partly ") != std::string::npos ||
                r.find("| not reproduced ") != std::string::npos)
        << r;
    EXPECT_EQ(r.find("| – "), std::string::npos) << "no empty cell: " << r;
  }
  // 241 nodes: ours 10 − 30/241 = 9.8755 against 9.7967, ratio 1.008 → reproduced at 1%.
  EXPECT_EQ(cells(rows[4]), (std::vector<std::string>{
                                "004 II Table 1", "peak du/dx at x=3", "fem", "241", "9.7967",
                                "9.8755", "1.01", "1%", "reproduced", "fem-a", ""}))
      << rows[4];
  // The second study's values are a numbered note right under the table, not a row.
  EXPECT_NE(page.find("[1] also `fem-b`: ours"), std::string::npos) << page;
  // Values no study measured are listed apart, the unmeasuring study named.
  EXPECT_NE(page.find("**Not run or not measured in this suite**"), std::string::npos);
  EXPECT_NE(page.find("rkpm j=1,kernel=gaussian: peak du/dx at x=3 (`rkpm-no-peak` ran there "
                      "but does not measure it) at 21 nodes"),
            std::string::npos)
      << page;
}

TEST(ProblemPage, NoRankingWhereNoErrorIsMeasured) {
  TempDir dir("mfv-pages");
  ReportSection section;
  section.problem = "laplace-tanh";
  section.studies.push_back(laplace_study("zero", "fem", {21, 41}, 0.0));
  section.studies.push_back(laplace_study("nan", "fem", {21, 41}, NAN));
  const std::string summary = write_problem_section(catalogue(), section, dir.path(), false);
  EXPECT_NE(summary.find("No relative L2 error is measured"), std::string::npos) << summary;
  EXPECT_EQ(summary.find("Ranked by"), std::string::npos) << summary;
}

TEST(ProblemPage, ElasticityPageSaysEnergyWhereItShowsTheEnergyError) {
  TempDir dir("mfv-pages");
  ReportSection section;
  section.problem = "cantilever";
  StudyResult s;
  s.label = "efg-ci";
  for (int n : {5, 9, 17}) {
    CaseResult c;
    c.spec.problem = "cantilever";
    c.spec.method = "efg-ci";
    c.spec.nodes = n;
    c.components = c.dim = 2;
    c.h = 12.0 / (n - 1);
    c.errors.l2_rel = 1e-3 * c.h * c.h;
    c.errors.energy_rel = 1e-2 * c.h;
    c.errors.h1_semi_rel = 99;  // must not be shown as the energy error
    s.cases.push_back(c);
  }
  section.studies.push_back(s);
  const std::string summary = write_problem_section(catalogue(), section, dir.path(), false);
  EXPECT_NE(summary.find("relative L2 displacement error"), std::string::npos) << summary;
  const std::string page = read_file(dir.path() / "problems" / "cantilever.md");
  EXPECT_EQ(page.find("H1"), std::string::npos) << page;
  EXPECT_EQ(page.find("9.9e+01"), std::string::npos);
  EXPECT_NE(page.find("energy rate"), std::string::npos);
  EXPECT_NE(page.find("energy trend"), std::string::npos);
  EXPECT_NE(page.find("converges (rate 1.00)"), std::string::npos) << "energy, rate 1: " << page;
}

/// The "## " headings of a page, in order.
std::vector<std::string> headings(const std::string& page) {
  std::vector<std::string> out;
  for (const auto& line : lines_of(page))
    if (line.rfind("## ", 0) == 0) out.push_back(line.substr(3));
  return out;
}

/// The skeleton's headings in its order (analyses/report_section.hpp PageParts).
const std::vector<std::string> kPageOrder = {
    "The paper's findings and ours", "Errors and CPU times", "Verdicts and measured values",
    "Convergence rates", "Plots", "Published values beside ours", "VTK files"};

/// Whether every heading is one of the skeleton's, each at most once, in its order.
bool follows_the_skeleton(const std::vector<std::string>& found) {
  std::size_t next = 0;
  for (const auto& h : found) {
    const auto it = std::find(kPageOrder.begin() + next, kPageOrder.end(), h);
    if (it == kPageOrder.end()) return false;
    next = static_cast<std::size_t>(it - kPageOrder.begin()) + 1;
  }
  return true;
}

TEST(PageSkeleton, WritesThePartsInOneOrderAndLeavesEmptyOnesOut) {
  PageParts parts;
  parts.vtk = "vtk body\n\n";
  parts.methods = "- `a`: method a\n";
  parts.errors = "errors body\n\n";
  parts.published = "published body\n\n";
  parts.lead = "Resolutions count nodes.";
  const std::string page = problem_page("title", "what it is", parts);
  EXPECT_EQ(page.rfind("# title\n\n[← report](../index.md)\n\nwhat it is\n\n"
                       "Resolutions count nodes.\n\n**Methods.**\n\n- `a`: method a\n\n",
                       0),
            0u)
      << page;
  EXPECT_EQ(headings(page), (std::vector<std::string>{"Errors and CPU times",
                                                      "Published values beside ours",
                                                      "VTK files"}));
  EXPECT_LT(page.find("errors body"), page.find("published body"));
  EXPECT_LT(page.find("published body"), page.find("vtk body"));
  EXPECT_EQ(page.find("Plots"), std::string::npos) << "an empty part has no heading";
  EXPECT_EQ(problem_page("t", "d", PageParts{}), "# t\n\n[← report](../index.md)\n\nd\n\n");
}

TEST(PageSkeleton, ScalarAndElasticityPagesShareItsHeadings) {
  TempDir dir("mfv-pages");
  write_problem_section(catalogue(), laplace_section(), dir.path(), false);
  const std::string scalar = read_file(dir.path() / "problems" / "laplace-tanh.md");
  EXPECT_TRUE(follows_the_skeleton(headings(scalar))) << scalar;
  EXPECT_NE(scalar.find("**Methods.**"), std::string::npos);
  EXPECT_NE(scalar.find("## Plots"), std::string::npos);

  ReportSection section;
  section.problem = "cantilever";
  StudyResult s;
  s.label = "efg-ci";
  for (int n : {5, 9}) {
    CaseResult c;
    c.spec.problem = "cantilever";
    c.spec.method = "efg-ci";
    c.spec.nodes = n;
    c.components = c.dim = 2;
    c.h = 12.0 / (n - 1);
    c.errors.l2_rel = 1e-3 * c.h * c.h;
    c.errors.energy_rel = 1e-2 * c.h;
    s.cases.push_back(c);
  }
  section.studies.push_back(s);
  write_problem_section(catalogue(), section, dir.path(), false);
  const std::string elasticity = read_file(dir.path() / "problems" / "cantilever.md");
  EXPECT_TRUE(follows_the_skeleton(headings(elasticity))) << elasticity;
  EXPECT_NE(elasticity.find("## Errors and CPU times"), std::string::npos);
  // The cantilever has no published numbers, only notes: they keep their place.
  EXPECT_NE(elasticity.find("## Published values beside ours\n\n001 gives no numbers"),
            std::string::npos)
      << elasticity;
}

TEST(ProblemPage, ASecondSectionOfTheSameTitleGetsItsOwnPage) {
  TempDir dir("mfv-pages");
  write_problem_section(catalogue(), laplace_section(), dir.path(), false);
  const std::string second =
      write_problem_section(catalogue(), laplace_section(), dir.path(), false);
  EXPECT_TRUE(fs::exists(dir.path() / "problems" / "laplace-tanh-2.md"));
  EXPECT_NE(second.find("](problems/laplace-tanh-2.md)"), std::string::npos) << second;
}

TEST(ProblemPage, StudyCollectionsStepThroughTheSpacing) {
  TempDir dir("mfv-pages");
  const ReportSection section = laplace_section();
  const std::string links = write_vtk_collections(
      dir.path(), "lt", {section.studies[0]},
      {{".txt", [](const fs::path& p, const CaseResult&) { std::ofstream(p) << "x"; }}});
  EXPECT_NE(links.find("(../vtk/lt/fem-a/study.pvd)"), std::string::npos) << links;
  EXPECT_NE(links.find("time = h: 0.3, 0.15, 0.075, 0.0375, 0.025"), std::string::npos)
      << links;
  const std::string pvd = read_file(dir.path() / "vtk" / "lt" / "fem-a" / "study.pvd");
  EXPECT_NE(pvd.find("timestep=\"0.3\""), std::string::npos) << pvd;
  EXPECT_NE(pvd.find("timestep=\"0.025\""), std::string::npos) << pvd;
}

TEST(Summaries, CarryPerResolutionErrorsAndTheirTrend) {
  const auto s = summarize(catalogue(), {laplace_study("fem-a", "fem", {21, 41, 81}, 1.0)});
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].h.size(), 3u);
  EXPECT_EQ(s[0].l2_rel.size(), 3u);
  EXPECT_TRUE(s[0].l2_trend.converges()) << s[0].l2_trend.reason;
  ASSERT_EQ(s[0].l2_trend.pairwise.size(), 2u);
  EXPECT_NEAR(s[0].l2_trend.pairwise[0], 2.0, 1e-9);
}

// ------------------------------------------------------------------ plots

PlotSpec many_studies_plot(int studies, double rate) {
  std::vector<StudyResult> all;
  for (int k = 0; k < studies; ++k) {
    StudyResult s = laplace_study("method-" + std::to_string(k), "fem", {21, 41, 81}, 1.0 + k);
    s.rates.fitted["L2"] = rate;
    all.push_back(s);
  }
  return convergence_plot("t", all, "relative L2 error (dimensionless)",
                          [](const CaseResult& c) { return c.errors.l2_rel; },
                          [](const Rates& r) { return r.rate("L2"); });
}

TEST(PlotScript, LegendOutsideDistinctColoursAndReferenceSlopes) {
  const PlotSpec spec = many_studies_plot(kPaletteSize, 4.2);
  EXPECT_EQ(spec.reference_slopes, (std::vector<int>{1, 2, 4}));
  const std::string gp = gnuplot_script(spec);
  EXPECT_NE(gp.find("set key outside right"), std::string::npos) << gp;
  EXPECT_NE(gp.find("set logscale x"), std::string::npos);
  EXPECT_NE(gp.find("set logscale y"), std::string::npos);
  for (const char* ref : {"'∝ h¹ (reference)'", "'∝ h² (reference)'", "'∝ h⁴ (reference)'"})
    EXPECT_NE(gp.find(ref), std::string::npos) << ref;
  std::set<std::string> colours;
  for (const auto& l : lines_of(gp))
    if (l.starts_with("set style line"))
      colours.insert(l.substr(l.find("rgb '") + 5, 7));
  EXPECT_EQ(colours.size(), static_cast<std::size_t>(kPaletteSize));
  // Axis labels name their units.
  EXPECT_NE(gp.find("h (length unit of x)"), std::string::npos);
  EXPECT_NE(gp.find("(dimensionless)"), std::string::npos);
}

TEST(PlotScript, SlopesAreOnlyDrawnOnLogLogAndSeriesPastThePaletteAreDashed) {
  PlotSpec spec = many_studies_plot(kPaletteSize + 1, 1.0);
  EXPECT_EQ(spec.reference_slopes, (std::vector<int>{1, 2}));
  std::string gp = gnuplot_script(spec);
  EXPECT_NE(gp.find(fmt::format("set style line {} lc rgb", kPaletteSize + 1)), std::string::npos);
  EXPECT_NE(gp.find("dt 2\n"), std::string::npos) << "the 21st series is dashed";
  spec.logx = false;
  gp = gnuplot_script(spec);
  EXPECT_EQ(gp.find("(reference)"), std::string::npos) << gp;
}

TEST(PlotScript, LinearAxisTurnsLogarithmicWhenValuesSpanDecades) {
  PlotSpec spec;
  spec.xlabel = "t (s)";
  spec.ylabel = "energy (J)";
  spec.series.push_back({"wide", {0, 1, 2}, {1, 1e2, 1e4}});
  EXPECT_NE(gnuplot_script(spec).find("set logscale y"), std::string::npos);
  spec.series[0].y = {1, 10, 100};  // two decades: stays linear
  EXPECT_EQ(gnuplot_script(spec).find("set logscale y"), std::string::npos);
  spec.series[0].y = {0, 1e2, 1e4};  // a zero cannot go on a log axis
  EXPECT_EQ(gnuplot_script(spec).find("set logscale y"), std::string::npos);
  spec.series[0].y = {1, 1e2, 1e4};
  spec.auto_logy = false;
  EXPECT_EQ(gnuplot_script(spec).find("set logscale y"), std::string::npos);
  spec.series[0].y = {NAN, NAN, NAN};
  EXPECT_EQ(gnuplot_script(spec), "") << "nothing left to plot";
}

TEST(PlotSplit, AtMostEightComputedCurvesPerPartEachWithTheReferences) {
  PlotSpec spec;
  spec.title = "levels";
  spec.series.push_back({"Torricelli", {0, 1}, {0, 1}, SeriesRole::band, {1, 2}});
  for (int k = 0; k < 20; ++k)
    spec.series.push_back({fmt::format("method {}", k), {0, 1}, {1.0 * k, 2.0 * k}});
  spec.series.push_back({"exact", {0, 1}, {0, 1}, SeriesRole::reference});
  const std::vector<PlotSpec> parts = split_plot(spec);
  ASSERT_EQ(parts.size(), 3u);
  std::size_t total = 0;
  for (std::size_t p = 0; p < parts.size(); ++p) {
    std::size_t computed = 0, references = 0;
    for (const auto& s : parts[p].series)
      (s.role == SeriesRole::computed ? computed : references) += 1;
    EXPECT_LE(computed, kMaxCurves);
    EXPECT_GE(computed, 6u) << "parts of nearly equal size";
    EXPECT_EQ(references, 2u) << "the band and the exact curve are in every part";
    EXPECT_EQ(parts[p].title, fmt::format("levels (part {} of 3)", p + 1));
    total += computed;
  }
  EXPECT_EQ(total, 20u) << "no curve lost or repeated";
  EXPECT_EQ(parts[0].series[2].label, "method 0") << "order kept";
  spec.series.resize(9);  // the band and 8 computed curves: one plot
  EXPECT_EQ(split_plot(spec).size(), 1u);
  EXPECT_THROW(split_plot(spec, 0), std::invalid_argument);
}

TEST(PlotScript, ReferencesAreBlackLinesDataOpenCirclesBandsShadedAndDrawnFirst) {
  PlotSpec spec;
  spec.xlabel = "t (s)";
  spec.ylabel = "h (m)";
  spec.style = "lines";
  std::vector<double> t(100), y(100);
  for (int i = 0; i < 100; ++i) t[i] = y[i] = i;
  spec.series.push_back({"ours", t, y});
  spec.series.push_back({"closed form", t, y, SeriesRole::reference});
  spec.series.push_back({"experiment", {1, 2}, {1, 2}, SeriesRole::data});
  spec.series.push_back({"band", {0, 99}, {0, 90}, SeriesRole::band, {10, 99}});
  const std::string gp = gnuplot_script(spec);
  EXPECT_NE(gp.find("with linespoints ls 1 pi 10 title 'ours'"), std::string::npos)
      << "a dense computed curve carries a marker every tenth point\n" << gp;
  EXPECT_NE(gp.find("with lines lc rgb '#000000' lw 2 dt 1 title 'closed form'"),
            std::string::npos) << gp;
  EXPECT_NE(gp.find("with points lc rgb '#000000' pt 6"), std::string::npos) << gp;
  const auto band = gp.find("using 1:2:3 with filledcurves");
  ASSERT_NE(band, std::string::npos) << gp;
  EXPECT_LT(band, gp.find("title 'ours'")) << "the band is drawn underneath";
  EXPECT_NE(gp.find("0 0 10\n"), std::string::npos) << "x, lower and upper edge";
  // A band needs its upper edge at every x.
  spec.series.back().y_hi = {1};
  const auto failure = write_svg_plot("/nonexistent/x.svg", spec);
  ASSERT_TRUE(failure.has_value());
  EXPECT_NE(failure->find("band 'band' has 2 x and 1 upper values"), std::string::npos)
      << *failure;
}

TEST(PlotScript, ABlownUpCurveIsMarkedOffScaleAndTheAxisFitsTheRest) {
  PlotSpec spec;
  spec.xlabel = "θ (deg)";
  spec.ylabel = "σθθ (Pa)";
  for (int k = 0; k < 4; ++k)
    spec.series.push_back({fmt::format("m{}", k), {0, 1, 2}, {-1.0 - k, 0.5, 1.0 + k}});
  spec.series.push_back({"blown", {0, 1, 2}, {0, 3e9, -1e9}});
  const std::string gp = gnuplot_script(spec);
  EXPECT_NE(gp.find("'blown (off scale: peak |y| 3e+09)'"), std::string::npos) << gp;
  EXPECT_NE(gp.find("set clip two"), std::string::npos);
  const auto range = gp.find("set yrange [");
  ASSERT_NE(range, std::string::npos) << gp;
  double lo = 0, hi = 0;
  ASSERT_EQ(std::sscanf(gp.c_str() + range, "set yrange [%lf:%lf]", &lo, &hi), 2);
  EXPECT_NEAR(lo, -4.4, 1e-9) << "the other curves' range, padded 5 %";
  EXPECT_NEAR(hi, 4.4, 1e-9);
  EXPECT_EQ(gp.find("set logscale y"), std::string::npos);
  // Nothing is off scale when the curves are alike, when the large ones are half of them
  // (kinetic energy and its small balance), or with one curve and no reference.
  spec.series.back().y = {0, 3, -1};
  EXPECT_EQ(gnuplot_script(spec).find("off scale"), std::string::npos);
  PlotSpec two;
  two.series.push_back({"kinetic", {0, 1}, {0, 0.5}});
  two.series.push_back({"balance", {0, 1}, {0, 1e-4}});
  EXPECT_EQ(gnuplot_script(two).find("off scale"), std::string::npos);
  PlotSpec one;
  one.series.push_back({"alone", {0, 1}, {0, 1e9}});
  EXPECT_EQ(gnuplot_script(one).find("off scale"), std::string::npos);
  // A reference sets the scale too: one computed curve far above it is off scale.
  one.series.push_back({"exact", {0, 1}, {0, 1}, SeriesRole::reference});
  EXPECT_NE(gnuplot_script(one).find("off scale"), std::string::npos);
  // Not on a logarithmic axis (it shows every size), nor where the caller says the curves
  // are different quantities.
  one.logy = true;
  one.series[0].y = {1, 1e9};
  one.series[1].y = {1, 2};
  EXPECT_EQ(gnuplot_script(one).find("off scale"), std::string::npos);
  one.logy = false;
  one.mark_off_scale = false;
  EXPECT_EQ(gnuplot_script(one).find("off scale"), std::string::npos);
}

TEST(PlotScript, ALogAxisWithinADecadeGetsLabelledTics) {
  PlotSpec spec;
  spec.logx = spec.logy = true;
  spec.series.push_back({"sph", {0.01, 0.02, 0.04}, {1e-2, 3e-3, 8e-4}});
  std::string gp = gnuplot_script(spec);
  const auto tics = gp.find("set xtics (");
  ASSERT_NE(tics, std::string::npos) << "no power of ten inside [0.0083, 0.048]\n" << gp;
  const std::string line = gp.substr(tics, gp.find('\n', tics) - tics);
  for (const char* label : {"'0.01'", "'0.02'"})
    EXPECT_NE(line.find(label), std::string::npos) << line;
  spec.series[0].x = {1e-3, 1e-2, 1e-1};  // decades inside: gnuplot's own tics
  gp = gnuplot_script(spec);
  EXPECT_EQ(gp.find("set xtics ("), std::string::npos) << gp;
}

}  // namespace
}  // namespace mfv
