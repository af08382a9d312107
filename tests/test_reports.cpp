// Unit tests of the report writers: atomic files and directories, Markdown, plots, VTK.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <gtest/gtest.h>

#include "temp_files.hpp"

#include "reports/atomic.hpp"
#include "reports/markdown.hpp"
#include "reports/plot.hpp"
#include "analyses/case_vtk.hpp"
#include "analyses/report_section.hpp"
#include "analyses/kernel_comparison.hpp"
#include "reports/vtk.hpp"

// VTK's include directories reach this test only if mfv_reports exports them; without them
// the VTK files are checked as XML text instead.
#if __has_include(<vtkXMLPolyDataReader.h>)
#define MFV_TEST_HAS_VTK_READER 1
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>
#endif

namespace fs = std::filesystem;
using namespace mfv;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

using test::names_in;
using test::read_file;

/// A fresh directory per test (tests/temp_files.hpp).
class TempDir : public test::TempDir {
 public:
  TempDir() : test::TempDir("mfv-test-reports") {}
};

void write_plain(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

/// Every file under `dir` with its content, to compare trees byte for byte.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const auto rel = fs::relative(e.path(), dir).string();
    files[rel] = e.is_regular_file() ? read_file(e.path()) : "<dir>";
  }
  return files;
}

std::size_t code_points(const std::string& s) {
  return static_cast<std::size_t>(
      std::count_if(s.begin(), s.end(), [](char c) { return (c & 0xC0) != 0x80; }));
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

/// Sets PATH for the lifetime of the object and restores it, so a failing assertion in
/// between cannot leave the rest of the tests without gnuplot.
class ScopedPath {
 public:
  explicit ScopedPath(const std::string& value) {
    if (const char* old = std::getenv("PATH")) old_ = old;
    ::setenv("PATH", value.c_str(), 1);
  }
  ScopedPath(const ScopedPath&) = delete;
  ScopedPath& operator=(const ScopedPath&) = delete;
  ~ScopedPath() {
    if (old_) {
      ::setenv("PATH", old_->c_str(), 1);
    } else {
      ::unsetenv("PATH");
    }
  }

 private:
  std::optional<std::string> old_;
};

CaseResult five_particle_case() {
  CaseResult r;
  r.spec.problem = "laplace_tanh";
  r.spec.method = "rkpm";
  r.spec.nodes = 5;
  r.h = 0.25;
  r.particles = 5;
  auto& f = r.data<StaticSolveData>().fields;
  f.x = Eigen::VectorXd::LinSpaced(5, 0.0, 1.0);
  f.u_exact = f.x.array().square();
  f.u_h = f.u_exact.array() + 0.01;
  f.du_exact = 2 * f.x;
  f.du_h = f.du_exact.array() - 0.1;
  f.coefficient = f.u_h;
  f.volume = Eigen::VectorXd::Constant(5, 0.25);
  f.sx = Eigen::VectorXd::LinSpaced(9, 0.0, 1.0);
  f.su = f.sx.array().square();
  f.su_h = f.su.array() + 0.01;
  f.sdu = 2 * f.sx;
  f.sdu_h = f.sdu.array() - 0.1;
  return r;
}

}  // namespace

// ---------------------------------------------------------------- atomic files

TEST(WriteFileAtomic, ReplacesContentAndLeavesNoTemporaryFiles) {
  TempDir dir;
  const auto file = dir.path() / "report.md";
  write_plain(file, "old content that is longer than the new one\n");
  write_file_atomic(file, "new\n");
  EXPECT_EQ(read_file(file), "new\n");
  write_file_atomic(file, "");
  EXPECT_EQ(read_file(file), "");
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"report.md"});
}

TEST(WriteFileAtomic, MissingDirectoryThrowsNamingThePath) {
  TempDir dir;
  const auto file = dir.path() / "no-such-dir" / "report.md";
  try {
    write_file_atomic(file, "text");
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(file));
  EXPECT_FALSE(fs::exists(file.parent_path()));
}

TEST(WriteFileAtomic, FailedRenameKeepsTargetAndRemovesTemporaryFile) {
  TempDir dir;
  // A non-empty directory cannot be replaced by a file: the rename is refused.
  const auto target = dir.path() / "report";
  fs::create_directory(target);
  write_plain(target / "keep.txt", "keep");
  EXPECT_THROW(write_file_atomic(target, "text"), std::runtime_error);
  EXPECT_EQ(read_file(target / "keep.txt"), "keep");
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"report"});
}

TEST(PendingFile, RemovedUnlessCommitted) {
  TempDir dir;
  const auto target = dir.path() / "plot.svg";
  fs::path temp;
  {
    PendingFile pending(target);
    temp = pending.path();
    EXPECT_TRUE(fs::exists(temp));
    EXPECT_EQ(temp.parent_path(), target.parent_path());
    PendingFile second(target);
    EXPECT_NE(second.path(), temp);  // unique even for the same target in one process
  }
  EXPECT_FALSE(fs::exists(temp));
  EXPECT_FALSE(fs::exists(target));
  {
    PendingFile pending(target);
    write_plain(pending.path(), "svg");
    pending.commit();
  }
  EXPECT_EQ(read_file(target), "svg");
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"plot.svg"});
}

// ---------------------------------------------------------------- staged directories

/// An earlier report written by mfv (with its marker), holding `files`.
void write_previous_report(const fs::path& target,
                           const std::map<std::string, std::string>& files) {
  StagedDirectory staged(target);
  for (const auto& [name, text] : files) {
    fs::create_directories((staged.path() / name).parent_path());
    write_plain(staged.path() / name, text);
  }
  staged.commit();
}

TEST(StagedDirectory, CommitReplacesExistingDirectory) {
  TempDir dir;
  const auto target = dir.path() / "run";
  write_previous_report(target, {{"old.md", "old"}, {"sub/old.vtp", "old"}});
  {
    StagedDirectory staged(target);
    EXPECT_NE(staged.path(), target);
    EXPECT_EQ(staged.path().parent_path(), dir.path());
    write_plain(staged.path() / "new.md", "new");
    EXPECT_EQ(read_file(target / "old.md"), "old");  // untouched until commit
    staged.commit();
    EXPECT_TRUE(staged.committed());
  }
  auto after = snapshot(target);
  EXPECT_EQ(after.erase(kReportMarker), 1u);
  const std::map<std::string, std::string> expected{{"new.md", "new"}};
  EXPECT_EQ(after, expected);
  // Neither the staging nor the old copy is left behind.
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"run"});
}

TEST(StagedDirectory, CommitCreatesMissingTarget) {
  TempDir dir;
  const auto target = dir.path() / "reports" / "run";
  {
    StagedDirectory staged(target);
    write_plain(staged.path() / "index.md", "hello");
    staged.commit();
  }
  EXPECT_EQ(read_file(target / "index.md"), "hello");
  EXPECT_EQ(names_in(target.parent_path()), std::vector<std::string>{"run"});
}

TEST(StagedDirectory, WithoutCommitLeavesPreviousReportUntouched) {
  TempDir dir;
  const auto target = dir.path() / "run";
  write_previous_report(target, {{"index.md", "# previous report\n"},
                                 {"vtk/case.vtp", std::string("\0\1\2binary", 9)}});
  const auto before = snapshot(target);
  fs::path staging;
  {
    StagedDirectory staged(target);
    staging = staged.path();
    EXPECT_TRUE(fs::is_directory(staging));
    write_plain(staging / "index.md", "# half-written");
  }
  EXPECT_FALSE(fs::exists(staging));
  EXPECT_EQ(snapshot(target), before);
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"run"});
}

// ---------------------------------------------------------------- Markdown

TEST(MarkdownTable, ColumnsLineUpAndPipesAreEscaped) {
  MarkdownTable t({"method", "L2 error", "rate"}, {'l', 'r', 'c'});
  t.add_row({"rkpm kernel=gaussian", fmt_sci(1.234e-3), fmt_rate(2.0149)});
  t.add_row({"a|b", fmt_sci(kNaN), fmt_rate(kNaN)});
  t.add_row({"fem", "1", "x"});
  const auto lines = lines_of(t.str());
  ASSERT_EQ(lines.size(), 5u);
  for (const auto& l : lines) {
    EXPECT_EQ(code_points(l), code_points(lines[0])) << l;
    EXPECT_EQ(l.front(), '|');
    EXPECT_EQ(l.back(), '|');
  }
  EXPECT_NE(lines[3].find("a\\|b"), std::string::npos) << lines[3];
  // Delimiter row: left ":--", right "--:", centre ":-:".
  EXPECT_EQ(lines[1].find("| :---"), 0u) << lines[1];
  EXPECT_NE(lines[1].find("-: |"), std::string::npos) << lines[1];
  EXPECT_NE(lines[1].find("| :--"), std::string::npos);
  // Right-aligned: the short value ends where the column ends.
  EXPECT_NE(lines[4].find("         1 |"), std::string::npos) << lines[4];
  // The columns are separated in the same places on every line.
  for (const auto& l : lines) EXPECT_EQ(l.find(" | "), lines[0].find(" | ")) << l;
}

TEST(MarkdownTable, WrongCellCountThrows) {
  MarkdownTable t({"a", "b"});
  EXPECT_THROW(t.add_row({"1"}), std::invalid_argument);
  EXPECT_THROW(t.add_row({"1", "2", "3"}), std::invalid_argument);
  EXPECT_NO_THROW(t.add_row({"1", "2"}));
  EXPECT_EQ(t.rows(), 1u);
  EXPECT_THROW(MarkdownTable({"a", "b"}, {'l'}), std::invalid_argument);
  EXPECT_THROW(MarkdownTable({"a"}, {'x'}), std::invalid_argument);
}

TEST(Format, Numbers) {
  EXPECT_EQ(fmt_sci(1.234e-3), "1.234e-03");
  EXPECT_EQ(fmt_sci(12345.0, 1), "1.2e+04");
  EXPECT_EQ(fmt_sci(kNaN), "–");
  EXPECT_EQ(fmt_sci(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(fmt_fix(0.125, 2), "0.12");
  EXPECT_EQ(fmt_fix(kNaN, 2), "–");
  EXPECT_EQ(fmt_rate(2.0149), "2.01");
  EXPECT_EQ(fmt_rate(-0.5), "-0.50");
  EXPECT_EQ(fmt_rate(kNaN), "–");
}

TEST(Format, Seconds) {
  EXPECT_EQ(fmt_seconds(0.0123), "0.012 s");
  EXPECT_EQ(fmt_seconds(3.44), "3.4 s");
  EXPECT_EQ(fmt_seconds(59.97), "1 min 00 s");
  EXPECT_EQ(fmt_seconds(125.2), "2 min 05 s");
  EXPECT_EQ(fmt_seconds(3725), "1 h 02 min");
  EXPECT_EQ(fmt_seconds(kNaN), "–");
  EXPECT_EQ(fmt_seconds(-1), "–");
}

// ---------------------------------------------------------------- plots

TEST(Plot, WritesSvgWhenGnuplotIsAvailable) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot is not installed";
  TempDir dir;
  PlotSpec spec;
  spec.title = "it's a \"title\" with \\ and |";
  spec.xlabel = "h";
  spec.ylabel = "error";
  spec.logx = spec.logy = true;
  spec.series.push_back({"first", {0.5, 0.25, 0.125}, {1e-2, 2.5e-3, 6.25e-4}});
  // The non-positive points are dropped on log axes; the series still plots.
  spec.series.push_back({"second", {0.5, 0.25, 0.0, 0.125}, {2e-2, -1.0, 1.0, 1e-3}});
  // Nothing left after dropping: skipped, not an error.
  spec.series.push_back({"empty", {0.0}, {1.0}});
  const auto svg = dir.path() / "convergence.svg";
  const auto failure = write_svg_plot(svg, spec);
  ASSERT_FALSE(failure.has_value()) << *failure;
  const auto text = read_file(svg);
  EXPECT_NE(text.find("<svg"), std::string::npos);
  EXPECT_NE(text.find("</svg>"), std::string::npos);
  EXPECT_NE(text.find("first"), std::string::npos);
  EXPECT_NE(text.find("second"), std::string::npos);
  EXPECT_EQ(text.find(">empty<"), std::string::npos);
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"convergence.svg"});
}

TEST(Plot, GnuplotErrorIsReportedAndKeepsPreviousSvg) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot is not installed";
  TempDir dir;
  const auto svg = dir.path() / "plot.svg";
  write_plain(svg, "<svg>previous</svg>");
  PlotSpec spec;
  spec.series.push_back({"a", {1, 2}, {1, 2}});
  spec.style = "filledcurves";  // refused before gnuplot runs: the style goes into the script
  const auto failure = write_svg_plot(svg, spec);
  ASSERT_TRUE(failure.has_value());
  EXPECT_NE(failure->find("style"), std::string::npos) << *failure;
  EXPECT_EQ(read_file(svg), "<svg>previous</svg>");
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"plot.svg"});
}

TEST(Plot, BarChartsHaveCategoryTicsAndStartAtZero) {
  PlotSpec spec;
  spec.style = "boxes";
  spec.auto_logy = false;
  spec.xtic_labels = {{0, "sph"}, {1, "efg-ni"}};
  spec.series.push_back({"lagrangian", {-0.16, 0.84}, {1, 2}});
  spec.series.push_back({"eulerian", {0.16, 1.16}, {2, 4}});
  const std::string script = gnuplot_script(spec);
  EXPECT_NE(script.find("with boxes"), std::string::npos) << script;
  EXPECT_NE(script.find("set xtics ('sph' 0, 'efg-ni' 1)"), std::string::npos) << script;
  EXPECT_NE(script.find("set yrange [0:*]"), std::string::npos) << script;
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot is not installed";
  TempDir dir;
  const auto svg = dir.path() / "bars.svg";
  const auto failure = write_svg_plot(svg, spec);
  ASSERT_FALSE(failure.has_value()) << *failure;
  EXPECT_NE(read_file(svg).find("efg-ni"), std::string::npos);
}

TEST(Plot, MissingGnuplotGivesReason) {
  TempDir dir;
  const auto empty_bin = dir.path() / "empty-bin";
  fs::create_directory(empty_bin);
  const auto svg = dir.path() / "plot.svg";
  std::optional<std::string> failure;
  {
    ScopedPath path(empty_bin.string());
    EXPECT_FALSE(gnuplot_available());
    PlotSpec spec;
    spec.series.push_back({"a", {1, 2}, {1, 2}});
    failure = write_svg_plot(svg, spec);
  }
  ASSERT_TRUE(failure.has_value());
  EXPECT_NE(failure->find("gnuplot"), std::string::npos) << *failure;
  EXPECT_EQ(failure->find('\n'), std::string::npos) << "one line: " << *failure;
  EXPECT_FALSE(fs::exists(svg));
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"empty-bin"});
}

TEST(Plot, ConvergencePlotHasOneSeriesPerStudyWithRate) {
  std::vector<StudyResult> studies(2);
  studies[0].label = "fem";
  studies[0].rates.fitted["L2"] = 2.0149;
  studies[0].rates.fitted["H1-semi"] = 0.998;
  studies[1].label = "rkpm kernel=gaussian";
  studies[1].rates.fitted["L2"] = kNaN;
  for (int n : {8, 16, 32}) {
    CaseResult c;
    c.h = 1.0 / n;
    c.errors.l2 = 1.0 / (n * n);
    c.errors.h1_semi = 1.0 / n;
    studies[0].cases.push_back(c);
  }
  studies[1].cases.push_back(studies[0].cases[0]);

  const auto l2 = convergence_plot("Laplace", studies, false);
  EXPECT_EQ(l2.title, "Laplace");
  EXPECT_TRUE(l2.logx && l2.logy);
  ASSERT_EQ(l2.series.size(), 2u);
  EXPECT_EQ(l2.series[0].label, "fem (rate 2.01)");
  EXPECT_EQ(l2.series[1].label, "rkpm kernel=gaussian (rate –)");
  EXPECT_EQ(l2.series[0].x, (std::vector<double>{1.0 / 8, 1.0 / 16, 1.0 / 32}));
  EXPECT_EQ(l2.series[0].y, (std::vector<double>{1.0 / 64, 1.0 / 256, 1.0 / 1024}));

  const auto h1 = convergence_plot("Laplace", studies, true);
  EXPECT_EQ(h1.series[0].label, "fem (rate 1.00)");
  EXPECT_EQ(h1.series[0].y, (std::vector<double>{1.0 / 8, 1.0 / 16, 1.0 / 32}));
  EXPECT_NE(h1.ylabel, l2.ylabel);
}

// ---------------------------------------------------------------- VTK

TEST(Vtk, CaseFileHasParticlesAndArrays) {
  TempDir dir;
  const auto file = dir.path() / "case.vtp";
  const auto r = five_particle_case();
  write_case_vtp(file, r);
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"case.vtp"});
  const auto text = read_file(file);
  EXPECT_NE(text.find("<VTKFile type=\"PolyData\""), std::string::npos);
  EXPECT_NE(text.find("NumberOfPoints=\"5\""), std::string::npos);
  EXPECT_NE(text.find("NumberOfVerts=\"5\""), std::string::npos);
  for (const char* name : {"u_h", "u_exact", "error", "du_h", "du_exact", "du_error",
                           "coefficient", "volume", "h", "nodes"})
    EXPECT_NE(text.find(std::string("Name=\"") + name + "\""), std::string::npos) << name;
#ifdef MFV_TEST_HAS_VTK_READER
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkPolyData* pd = reader->GetOutput();
  ASSERT_EQ(pd->GetNumberOfPoints(), 5);
  EXPECT_EQ(pd->GetNumberOfVerts(), 5);
  vtkDataArray* error = pd->GetPointData()->GetArray("error");
  ASSERT_NE(error, nullptr);
  for (vtkIdType i = 0; i < 5; ++i) {
    EXPECT_DOUBLE_EQ(pd->GetPoint(i)[0], r.data<StaticSolveData>().fields.x[i]);
    EXPECT_NEAR(error->GetTuple1(i), 0.01, 1e-15);
  }
  vtkDataArray* h = pd->GetFieldData()->GetArray("h");
  ASSERT_NE(h, nullptr);
  EXPECT_DOUBLE_EQ(h->GetTuple1(0), 0.25);
#endif
}

TEST(Vtk, CaseFileRejectsMismatchedField) {
  TempDir dir;
  auto r = five_particle_case();
  r.data<StaticSolveData>().fields.volume.resize(4);
  const auto file = dir.path() / "case.vtp";
  EXPECT_THROW(write_case_vtp(file, r), std::invalid_argument);
  EXPECT_FALSE(fs::exists(file));
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(Vtk, LineFileIsOnePolyline) {
  TempDir dir;
  const auto file = dir.path() / "line.vtp";
  write_line_vtp(file, five_particle_case());
  const auto text = read_file(file);
  EXPECT_NE(text.find("NumberOfPoints=\"9\""), std::string::npos);
  EXPECT_NE(text.find("NumberOfLines=\"1\""), std::string::npos);
  EXPECT_NE(text.find("Name=\"u_exact\""), std::string::npos);
  EXPECT_NE(text.find("Name=\"du_h\""), std::string::npos);
#ifdef MFV_TEST_HAS_VTK_READER
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkPolyData* pd = reader->GetOutput();
  ASSERT_EQ(pd->GetNumberOfLines(), 1);
  EXPECT_EQ(pd->GetCell(0)->GetNumberOfPoints(), 9);
#endif
  CaseResult no_sampling = five_particle_case();
  no_sampling.data<StaticSolveData>().fields.sx.resize(0);
  EXPECT_THROW(write_line_vtp(dir.path() / "none.vtp", no_sampling), std::invalid_argument);
}

TEST(Vtk, CollectionListsEntriesWithParts) {
  TempDir dir;
  const auto file = dir.path() / "study.pvd";
  write_pvd(file, {{16, "case_16.vtp"}, {16, "line_16.vtp"}, {32, "a&b.vtp"}});
  const auto text = read_file(file);
  EXPECT_NE(text.find("<VTKFile type=\"Collection\""), std::string::npos);
  EXPECT_NE(text.find("timestep=\"16\" group=\"\" part=\"0\" file=\"case_16.vtp\""),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("timestep=\"16\" group=\"\" part=\"1\" file=\"line_16.vtp\""),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("timestep=\"32\" group=\"\" part=\"0\" file=\"a&amp;b.vtp\""),
            std::string::npos)
      << text;
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"study.pvd"});
}

namespace mfv {
namespace {

/// A study of `method` with the given (resolved = given here) parameters and one error per
/// resolution.
StudyResult kernel_study(const std::string& method, const std::string& params,
                         const std::vector<std::pair<int, double>>& errors) {
  StudyResult s;
  s.label = method + " " + params;
  for (const auto& [n, e] : errors) {
    CaseResult c;
    c.spec.problem = "p";
    c.spec.method = method;
    c.spec.method_params = Params::parse(params);
    c.spec.nodes = n;
    c.method_params = c.spec.method_params;
    c.errors.l2_rel = e;
    c.headline["energy drift"] = 1e-4;
    c.headline["peak"] = 3;  // not a compared kind: not shown
    s.cases.push_back(c);
  }
  return s;
}

TEST(KernelComparison, StudiesDifferingOnlyInTheKernelSideBySideBestFirst) {
  ReportSection sec;
  sec.problem = "p";
  sec.studies = {kernel_study("sph", "kernel=cubic-spline", {{11, 0.4}, {21, 0.1}, {41, 0.03}}),
                 kernel_study("sph", "kernel=wendland-c2,dmax=3", {{11, 0.3}, {21, 0.05}}),
                 // Another method parameter: its own group, with one kernel: no table.
                 kernel_study("sph", "kernel=quintic-spline,mass=uniform", {{11, 0.2}}),
                 // One kernel only: no table.
                 kernel_study("efg", "kernel=gaussian", {{11, 0.01}})};
  const auto all = kernel_comparisons({sec});
  ASSERT_EQ(all.size(), 1u);
  const TextTable& t = all[0].table;
  EXPECT_EQ(all[0].method, "sph");
  EXPECT_EQ(t.head, (std::vector<std::string>{"kernel", "support (dmax)", "error at 21", "rate",
                                               "energy drift", "CPU s"}));
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.rows[0][0], "wendland-c2") << "best error at the common resolution first";
  EXPECT_EQ(t.rows[0][1], "3");
  EXPECT_EQ(t.rows[0][2], "0.05");
  EXPECT_EQ(t.rows[1][0], "cubic-spline");
  EXPECT_EQ(t.rows[1][2], "0.1");
  EXPECT_NE(kernel_comparison_page(all).find("## p: sph"), std::string::npos);
}

TEST(KernelComparison, NoErrorNoErrorColumnAndNothingToCompareNoPage) {
  ReportSection sec;
  sec.problem = "dispersion";
  sec.studies = {kernel_study("sph", "kernel=cubic-spline", {{41, 0.0}}),
                 kernel_study("sph", "kernel=wendland-c2", {{41, 0.0}})};
  const auto all = kernel_comparisons({sec});
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].table.head,
            (std::vector<std::string>{"kernel", "support (dmax)", "energy drift", "CPU s"}));
  sec.studies.pop_back();
  EXPECT_TRUE(kernel_comparisons({sec}).empty());
  EXPECT_EQ(kernel_comparison_page(kernel_comparisons({sec})), "");
}

}  // namespace
}  // namespace mfv
