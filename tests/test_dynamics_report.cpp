/// The transient report section says what the numbers are (issue 12, item 6): unstable runs
/// with their step, checkpoints "not reached", peaks of runs stopped early as lower bounds,
/// criteria that name the side of the bound they test, the convergence axis naming the
/// velocity error, and the measured agreement of Lagrangian and Eulerian kernels.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "analyses/report_section.hpp"
#include "temp_files.hpp"
#include "test_support.hpp"
#include "verify/runner.hpp"

namespace mfv {
namespace {

namespace fs = std::filesystem;

bool has(const std::string& text, const std::string& needle) {
  return text.find(needle) != std::string::npos;
}

StudyResult study(const std::string& problem, const std::string& method, const std::string& mp,
                  const std::string& pp, const std::vector<int>& nodes, const std::string& label) {
  CaseSpec c;
  c.problem = problem;
  c.method = method;
  c.method_params = Params::parse(mp);
  c.problem_params = Params::parse(pp);
  StudyResult s = run_study(test_catalogue(), c, nodes);
  s.label = label;
  return s;
}

std::string section_of(const std::vector<StudyResult>& studies, const fs::path& dir) {
  std::vector<ReportSection> sections;
  for (const auto& s : studies) add_to_sections(test_catalogue(), sections, s);
  EXPECT_EQ(sections.size(), 1u);
  // The detail is on the problem's page; index.md gets the returned summary.
  const std::string summary =
      write_problem_section(test_catalogue(), sections.front(), dir, false);
  const fs::path page = dir / "problems" / (slug(sections.front().problem) + ".md");
  EXPECT_TRUE(fs::exists(page)) << page;
  return test::read_file(page) + "\n" + summary;
}

TEST(TransientReport, PrestressedRodShowsInstabilityCapsAndCriteria) {
  test::TempDir dir("mfv-test-dynamics-report");
  const std::string mp = "kernel=quartic-spline,dmax=1.5";
  const std::string md = section_of(
      {study("prestressed-rod", "kbm-ni", mp, "frame=lagrangian,frames=0,threads=1", {41},
             "lagrangian"),
       study("prestressed-rod", "kbm-ni", mp, "frame=eulerian,frames=0,threads=1", {41},
             "eulerian")},
      dir.path());
  // The unstable run: its step, why, and its peak as a lower bound.
  EXPECT_TRUE(has(md, "unstable at step ")) << md;
  EXPECT_TRUE(has(md, "**Unstable runs.**"));
  EXPECT_TRUE(has(md, "(stopped early)"));
  EXPECT_TRUE(has(md, "peak v/v0 ≥ "));
  // Criteria say which side of the bound each verdict expects.
  EXPECT_TRUE(has(md, "stable: the peak nodal velocity stays at or below 2 v0"));
  EXPECT_TRUE(has(md, "unstable: the peak nodal velocity rises above 2 v0"));
  EXPECT_FALSE(has(md, "stable: peak nodal velocity over the run above"));
  // Two blow-ups (or a blow-up and a stable run) are not compared as kernel frames.
  EXPECT_FALSE(has(md, "### Lagrangian and Eulerian kernels"));
}

TEST(TransientReport, RodPulseLabelsTheVelocityErrorAndExplainsFrameAgreement) {
  test::TempDir dir("mfv-test-dynamics-report");
  const std::string pp = "frames=0,samples=10,transits=1,threads=1";
  const std::string md = section_of(
      {study("rod-pulse", "efg-ni", "", pp, {61, 121}, "lagrangian"),
       study("rod-pulse", "efg-ni", "", pp + ",frame=eulerian", {61, 121}, "eulerian"),
       study("rod-pulse", "efg-ci", "", pp + ",safety=1.5", {61}, "blown-up")},
      dir.path());
  // What the convergence table and plot show: the velocity error, not "L2 error ||u_h - u||".
  EXPECT_TRUE(has(md, "relative L2 velocity error ||v_h - v|| / ||v||")) << md;
  const fs::path svg = dir.path() / "plots" / "rod-pulse-error.svg";
  if (fs::exists(svg)) {
    std::ifstream in(svg);
    std::stringstream text;
    text << in.rdbuf();
    EXPECT_TRUE(has(text.str(), "velocity error"));
    EXPECT_FALSE(has(text.str(), "L2 error ||u_h - u||"));
  }
  // The blown-up run: its checkpoint is "not reached", not 0.
  EXPECT_TRUE(has(md, "not reached"));
  EXPECT_TRUE(has(md, "`blown-up` n=61: unstable at step "));
  // Lagrangian against Eulerian on the small-strain rod: measured, and explained.
  EXPECT_TRUE(has(md, "### Lagrangian and Eulerian kernels"));
  EXPECT_TRUE(has(md, "`lagrangian` (Lagrangian kernel) and `eulerian` (Eulerian): largest "
                      "relative difference"));
  EXPECT_TRUE(has(md, "agree to every printed digit because the strain is small"));
  // The page skeleton's headings (analyses/report_section.hpp), in its order.
  std::size_t last = 0;
  for (const char* heading : {"**Methods.**", "## Errors and CPU times", "### Lagrangian and",
                              "## Convergence rates", "## Plots", "### Time histories"}) {
    const auto at = md.find(heading);
    ASSERT_NE(at, std::string::npos) << heading;
    EXPECT_GT(at, last) << heading;
    last = at;
  }
}

}  // namespace
}  // namespace mfv
