/// The commands refuse a report target they may not replace before any computation, and leave
/// it as it was: issue 12's `mfv study ... -r DIR` that deleted the user's file, a baseline or
/// CTest script that is not mfv's, and a `--vtk` file of the user's.
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "apps/commands.hpp"
#include "methods/core/errors.hpp"
#include "reports/atomic.hpp"
#include "tests/temp_files.hpp"
#include "apps/catalogue.hpp"

namespace mfv {
namespace {

namespace fs = std::filesystem;
using test::expect_refused;

struct TempDir : test::TempDir {
  TempDir() : test::TempDir("mfv-report-cmd") {}
};

CompareOptions study(const fs::path& report) {
  CompareOptions o;
  o.problem = "laplace-tanh";
  o.methods = {"fem"};
  o.nodes = {21, 41};
  o.report = report.string();
  return o;
}

TEST(ReportCommands, StudyIntoAUsersDirectoryIsRefusedAndTheFileKept) {
  const Catalogue c;
  TempDir dir;
  const auto target = dir.path() / "DIR";
  test::write_text(target / "user.txt", "precious");
  std::ostringstream out, progress;
  expect_refused([&] { command_compare(c, study(target), out, progress); }, target);
  EXPECT_EQ(test::read_file(target / "user.txt"), "precious");
  EXPECT_EQ(test::names_in(target), std::vector<std::string>{"user.txt"});
  // Refused before the computation: no study ran.
  EXPECT_EQ(progress.str(), "");
}

TEST(ReportCommands, StudyReplacesItsOwnReport) {
  const Catalogue c;
  TempDir dir;
  const auto target = dir.path() / "run";
  std::ostringstream out, progress;
  ASSERT_EQ(command_compare(c, study(target), out, progress), 0);
  ASSERT_TRUE(read_report_marker(target));
  ASSERT_EQ(command_compare(c, study(target), out, progress), 0);
  EXPECT_TRUE(fs::exists(target / "index.md"));
  EXPECT_EQ(test::names_in(dir.path()), std::vector<std::string>{"run"});
}

TEST(ReportCommands, AnalyseAndVerifyRefuseAForeignTarget) {
  const Catalogue c;
  TempDir dir;
  const auto target = dir.path() / "file";
  test::write_text(target, "user data");
  AnalyseOptions a;
  a.problem = "time-step";
  a.method = "fem";
  a.report = target.string();
  std::ostringstream out, progress;
  expect_refused([&] { command_analyse(c, a, out); }, target);
  const auto manifest = dir.path() / "m.toml";
  test::write_text(manifest,
              "[suite]\nname = \"t\"\n[[case]]\nid = \"a\"\nproblem = \"laplace-tanh\"\n"
              "method = \"fem\"\nnodes = [11, 21]\n");
  VerifyOptions v;
  v.manifest = manifest.string();
  v.report = target.string();
  expect_refused([&] { command_verify(c, v, out, progress); }, target);
  EXPECT_EQ(test::read_file(target), "user data");
}

TEST(ReportCommands, ForeignBaselineCtestScriptAndVtkFileAreNotOverwritten) {
  const Catalogue c;
  TempDir dir;
  const auto baseline = dir.path() / "baseline.toml";
  test::write_text(baseline, "my notes, not a baseline\n");
  const auto manifest = dir.path() / "m.toml";
  test::write_text(manifest,
              "[suite]\nname = \"t\"\nbaseline = \"baseline.toml\"\n[[case]]\nid = \"a\"\n"
              "problem = \"laplace-tanh\"\nmethod = \"fem\"\nnodes = [11, 21]\n");
  VerifyOptions v;
  v.manifest = manifest.string();
  v.update_baseline = true;
  v.no_report = true;
  std::ostringstream out, progress;
  expect_refused([&] { command_verify(c, v, out, progress); }, baseline);
  EXPECT_EQ(test::read_file(baseline), "my notes, not a baseline\n");

  const auto script = dir.path() / "tests.cmake";
  test::write_text(script, "my cmake\n");
  expect_refused([&] { command_manifest_ctest(manifest.string(), "mfv", script.string()); }, script);
  EXPECT_EQ(test::read_file(script), "my cmake\n");

  const auto vtk = dir.path() / "mine.vtp";
  test::write_text(vtk, "not VTK\n");
  RunOptions r;
  r.problem = "laplace-tanh";
  r.method = "fem";
  r.nodes = 11;
  r.vtk = vtk.string();
  expect_refused([&] { command_run(c, r, out); }, vtk);
  EXPECT_EQ(test::read_file(vtk), "not VTK\n");
}

TEST(ReportCommands, EveryStaticProblemWritesItsReportWithVtk) {
  // The VTK writers take each problem's own stress rows (a 2D problem without a material once
  // handed them the 4-row gradient, and the whole report failed).
  const Catalogue c;
  TempDir dir;
  for (const auto& [problem, nodes] : std::vector<std::pair<std::string, std::vector<int>>>{
           {"laplace-tanh", {11, 21}}, {"elastic-patch", {3, 5}}, {"cantilever", {3, 5}}}) {
    CompareOptions o;
    o.problem = problem;
    o.methods = {"fem"};
    o.nodes = nodes;
    o.report = (dir.path() / problem).string();
    std::ostringstream out, progress;
    EXPECT_EQ(command_compare(c, o, out, progress), 0) << problem;
    EXPECT_TRUE(fs::exists(dir.path() / problem / "index.md")) << problem;
  }
}

}  // namespace
}  // namespace mfv
