/// The subcommands end to end: `mfv verify` passes inside its bands and fails, naming the case,
/// when a band is tightened or a number is worse than the baseline; reports are replaced only
/// by complete ones; `mfv compare` and `mfv manifest-ctest` write what they promise.
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include <gtest/gtest.h>
#include <unistd.h>

#include "apps/commands.hpp"
#include "methods/core/errors.hpp"
#include "verify/baseline.hpp"
#include "analyses/norms.hpp"

namespace mfv {
namespace {

namespace fs = std::filesystem;

class Commands : public ::testing::Test {
 protected:
  void SetUp() override {
    static std::atomic<int> n{0};
    dir_ = fs::temp_directory_path() / ("mfv-commands-" + std::to_string(::getpid()) + "-" +
                                        std::to_string(n++));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }
  /// A one-case manifest: linear FEM on laplace-tanh, whose L2 rate is about 2.
  fs::path manifest(const std::string& l2_rate_band, bool baseline = false) {
    return write("suite.toml",
                 std::string("[suite]\nname = \"t\"\n") +
                     (baseline ? "baseline = \"baseline.toml\"\n" : "") +
                     "[[case]]\n"
                     "id = \"lt/fem\"\n"
                     "problem = \"laplace-tanh\"\n"
                     "method = \"fem\"\n"
                     "nodes = [41, 81, 161]\n"
                     "[case.bands]\n"
                     "l2_rate = " + l2_rate_band + "\n");
  }
  int verify(const fs::path& m, std::string& out, bool update = false, bool report = false) {
    VerifyOptions o;
    o.manifest = m.string();
    o.update_baseline = update;
    o.no_report = !report;
    o.report = (dir_ / "report").string();
    o.vtk = true;
    std::ostringstream s, progress;
    const int rc = command_verify(catalogue_, o, s, progress);
    out = s.str();
    return rc;
  }

  const Catalogue catalogue_;
  fs::path dir_;
};

TEST_F(Commands, VerifyPassesInsideTheBand) {
  std::string out;
  EXPECT_EQ(verify(manifest("[1.8, 2.2]"), out), 0) << out;
  EXPECT_NE(out.find("PASS"), std::string::npos) << out;
}

TEST_F(Commands, VerifyFailsNamingTheCaseWhenABandIsTightened) {
  std::string out;
  EXPECT_EQ(verify(manifest("[2.5, 3.0]"), out), 1) << out;
  EXPECT_NE(out.find("lt/fem: l2_rate"), std::string::npos) << out;
  EXPECT_NE(out.find("outside the band"), std::string::npos) << out;
  EXPECT_NE(out.find("suite.toml:9"), std::string::npos) << out;  // the band's line
  EXPECT_NE(out.find("FAIL: 1 of 1"), std::string::npos) << out;
}

TEST_F(Commands, VerifyFailsWhenANumberIsWorseThanTheBaseline) {
  std::string out;
  const fs::path m = manifest("[1.8, 2.2]", true);
  ASSERT_EQ(verify(m, out, true), 0) << out;
  ASSERT_TRUE(fs::exists(dir_ / "baseline.toml"));
  EXPECT_EQ(verify(m, out), 0) << "an unchanged run must match its baseline: " << out;

  // Pretend the recorded finest error was 30% smaller: the current one is then "worse".
  Baseline b = load_baseline(dir_ / "baseline.toml");
  b.cases.at("lt/fem").resolutions.back().l2 *= 0.7;
  std::ofstream(dir_ / "baseline.toml") << baseline_to_toml(b);
  EXPECT_EQ(verify(m, out), 1) << out;
  EXPECT_NE(out.find("lt/fem: l2 at 161 nodes"), std::string::npos) << out;
  EXPECT_NE(out.find("worse than the baseline"), std::string::npos) << out;
}

/// A full_only case (a paper-size run, a check too costly for the nightly) runs only with
/// --full, keeps out of the baseline and the CTest list, and --case names it only with --full.
TEST_F(Commands, AFullOnlyCaseRunsOnlyWithFull) {
  const fs::path m = write("suite.toml",
                           "[suite]\nname = \"t\"\nbaseline = \"baseline.toml\"\n"
                           "[[case]]\nid = \"lt/fem\"\nproblem = \"laplace-tanh\"\n"
                           "method = \"fem\"\nnodes = [21, 41]\n"
                           "[[case]]\nid = \"lt/fem-big\"\nproblem = \"laplace-tanh\"\n"
                           "method = \"fem\"\nnodes = [81, 161]\nfull_only = true\n");
  std::string out;
  ASSERT_EQ(verify(m, out, true), 0) << out;
  EXPECT_EQ(out.find("lt/fem-big"), std::string::npos) << "ran without --full:\n" << out;
  EXPECT_EQ(load_baseline(dir_ / "baseline.toml").cases.count("lt/fem-big"), 0u);
  VerifyOptions o;
  o.manifest = m.string();
  o.no_report = true;
  o.cases = {"lt/fem-big"};
  std::ostringstream s, progress;
  try {
    command_verify(catalogue_, o, s, progress);
    FAIL() << "a full-only case ran without --full";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("add --full"), std::string::npos) << e.what();
  }
  o.full = true;
  std::ostringstream s2;
  EXPECT_EQ(command_verify(catalogue_, o, s2, progress), 0) << s2.str();
  EXPECT_NE(s2.str().find("none (--full only)"), std::string::npos) << s2.str();
  const fs::path script = dir_ / "tests.cmake";
  command_manifest_ctest(m.string(), "/bin/mfv", script.string());
  std::stringstream text;
  text << std::ifstream(script).rdbuf();
  EXPECT_NE(text.str().find("[==[lt/fem]==]"), std::string::npos);
  EXPECT_EQ(text.str().find("lt/fem-big"), std::string::npos) << text.str();
}

/// Issue 26: a case id holding the default bracket's "]==]" still makes a script CMake can
/// read; a manifest and baseline in the working directory can record the baseline.
TEST_F(Commands, ManifestCtestBracketsSurviveAnyIdAndARelativeBaselineIsWritten) {
  const fs::path m = write("odd.toml",
                           "[[case]]\nid = \"a]==]b\"\nproblem = \"laplace-tanh\"\n"
                           "method = \"fem\"\nnodes = [21, 41]\n");
  const fs::path script = dir_ / "tests.cmake";
  command_manifest_ctest(m.string(), "/bin/mfv", script.string());
  std::stringstream text;
  text << std::ifstream(script).rdbuf();
  EXPECT_NE(text.str().find("[===[a]==]b]===]"), std::string::npos) << text.str();

  write("lt.toml", "[suite]\nname = \"lt\"\nbaseline = \"lt-base.toml\"\n[[case]]\nid = \"a\"\n"
                   "problem = \"laplace-tanh\"\nmethod = \"fem\"\nnodes = [21, 41]\n");
  const fs::path cwd = fs::current_path();
  fs::current_path(dir_);
  std::string out;
  const int rc = verify("lt.toml", out, true);
  fs::current_path(cwd);
  EXPECT_EQ(rc, 0) << out;
  EXPECT_TRUE(fs::exists(dir_ / "lt-base.toml")) << out;
}

/// Issue 26: --update-baseline never records "nan" where the baseline held a number (the case
/// fails and keeps its entry), and a baseline of another suite is refused.
TEST_F(Commands, UpdateBaselineKeepsANumberTheRunLostAndRefusesAnotherSuitesBaseline) {
  std::string out;
  // The rod pulse measures no H1 error: its baseline records h1 = "nan".
  const fs::path m = write("rod.toml",
                           "[suite]\nname = \"t\"\nbaseline = \"baseline.toml\"\n[[case]]\n"
                           "id = \"rod\"\nproblem = \"rod-pulse\"\nmethod = \"sph\"\n"
                           "problem_params = { frames = 0, transits = 1, threads = 1 }\n"
                           "nodes = [25]\n");
  ASSERT_EQ(verify(m, out, true), 0) << out;
  Baseline b = load_baseline(dir_ / "baseline.toml");
  ASSERT_TRUE(std::isnan(b.cases.at("rod").resolutions.front().h1));
  // Pretend an earlier run had measured it: this run's NaN would then erase a number.
  b.cases.at("rod").resolutions.front().h1 = 0.5;
  std::ofstream(dir_ / "baseline.toml") << baseline_to_toml(b);
  EXPECT_EQ(verify(m, out, true), 1) << out;
  EXPECT_NE(out.find("rod: h1 at 25 nodes: the baseline holds 0.5, this run measured nothing; "
                     "its baseline entry is kept"),
            std::string::npos)
      << out;
  EXPECT_EQ(load_baseline(dir_ / "baseline.toml").cases.at("rod").resolutions.front().h1, 0.5);

  // Headlines: one the run no longer measures is lost the same way; one it measures with
  // another value is simply updated.
  b.cases.at("rod").resolutions.front().h1 = std::nan("");
  auto& headline = b.cases.at("rod").resolutions.front().headline;
  ASSERT_FALSE(headline.empty()) << "the rod pulse records its headlines";
  const std::string measured = headline.begin()->first;
  headline[measured] = 12345.0;
  headline["a headline no run measures"] = 1.0;
  std::ofstream(dir_ / "baseline.toml") << baseline_to_toml(b);
  EXPECT_EQ(verify(m, out, true), 1) << out;
  EXPECT_NE(out.find("rod: headline: a headline no run measures at 25 nodes: the baseline "
                     "holds 1, this run measured nothing"),
            std::string::npos)
      << out;
  headline.erase("a headline no run measures");
  std::ofstream(dir_ / "baseline.toml") << baseline_to_toml(b);
  EXPECT_EQ(verify(m, out, true), 0) << out;
  EXPECT_NE(load_baseline(dir_ / "baseline.toml").cases.at("rod").resolutions.front().headline.at(
                measured),
            12345.0)
      << "updated to this run's value";

  b.suite = "another";
  std::ofstream(dir_ / "baseline.toml") << baseline_to_toml(b);
  try {
    verify(m, out);
    FAIL() << "another suite's baseline was used: " << out;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("records suite 'another'"), std::string::npos) << e.what();
  }
}

TEST_F(Commands, VerifyRejectsAnUnknownMethodBeforeRunning) {
  const fs::path m = write("bad.toml",
                           "[[case]]\nid = \"x\"\nproblem = \"laplace-tanh\"\nmethod = \"efgg\"\n"
                           "nodes = [21, 41]\n");
  std::string out;
  try {
    verify(m, out);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("bad.toml:1"), std::string::npos) << msg;
    EXPECT_NE(msg.find("efgg"), std::string::npos) << msg;
    EXPECT_NE(msg.find("efg"), std::string::npos) << msg;  // the valid names are listed
  }
}

TEST_F(Commands, ReportIsWrittenAndAFailedRunKeepsThePreviousOne) {
  std::string out;
  ASSERT_EQ(verify(manifest("[1.8, 2.2]"), out, false, true), 0) << out;
  const fs::path index = dir_ / "report" / "index.md";
  ASSERT_TRUE(fs::exists(index));
  std::stringstream text;
  text << std::ifstream(index).rdbuf();
  const std::string md = text.str();
  EXPECT_NE(md.find("## laplace-tanh"), std::string::npos);
  EXPECT_NE(md.find("](problems/laplace-tanh.md)"), std::string::npos) << md;
  std::stringstream page_text;
  page_text << std::ifstream(dir_ / "report" / "problems" / "laplace-tanh.md").rdbuf();
  EXPECT_NE(page_text.str().find("Published values beside ours"), std::string::npos);
  EXPECT_NE(page_text.str().find("004 II Table 1"), std::string::npos);
  EXPECT_TRUE(fs::exists(dir_ / "report" / "vtk" / "laplace-tanh" / "lt-fem" / "study.pvd"));

  // A run that fails on input must not touch the previous report.
  const fs::path bad = write("bad.toml", "[[case]]\nid = \"x\"\nproblem = \"nope\"\n"
                                         "method = \"fem\"\nnodes = [21, 41]\n");
  EXPECT_THROW(verify(bad, out, false, true), InputError);
  std::stringstream again;
  again << std::ifstream(index).rdbuf();
  EXPECT_EQ(again.str(), md);
}

TEST_F(Commands, CompareWritesOneReportWithEveryMethod) {
  CompareOptions o;
  o.problem = "laplace-tanh";
  o.methods = {"fem", "rkpm:kernel=gaussian,j=1"};
  o.nodes = {21, 41, 81};
  o.report = (dir_ / "cmp").string();
  o.vtk = false;
  std::ostringstream out, progress;
  EXPECT_EQ(command_compare(catalogue_, o, out, progress), 0);
  EXPECT_NE(progress.str().find("[2/2] rkpm j=1,kernel=gaussian: resolution 3/3: 81 nodes"),
            std::string::npos)
      << progress.str();
  std::stringstream text;
  text << std::ifstream(dir_ / "cmp" / "index.md").rdbuf();
  EXPECT_NE(text.str().find("| fem "), std::string::npos);
  EXPECT_NE(text.str().find("| rkpm j=1,kernel=gaussian "), std::string::npos);
}

/// The built-in catalogue (the analyses the hand-made studies name).
const Catalogue& built_in() {
  static const Catalogue c;
  return c;
}

/// A study assembled by hand: the table must print what it is given, rates included.
StudyResult synthetic_study(int components, long steps) {
  StudyResult s;
  s.label = "m";
  const double h[] = {0.1, 0.05, 0.025};
  for (int i = 0; i < 3; ++i) {
    CaseResult r;
    r.h = h[i];
    r.particles = 10 << i;
    r.components = components;
    // The analysis that would have run it: the runner records it in every case.
    r.analysis = steps > 0 ? "transient" : "static-solve";
    if (steps > 0) r.data<TransientData>().steps = steps;
    r.errors.l2 = r.errors.l2_rel = std::pow(h[i], 2);          // rate 2
    r.errors.h1_semi = r.errors.h1_semi_rel = std::pow(h[i], 1);  // rate 1
    r.errors.energy = r.errors.energy_rel = std::pow(h[i], 1.5);  // rate 1.5
    r.cpu.setup = 0.25;
    s.cases.push_back(r);
  }
  s.rates = study_rates(s.cases, false);
  return s;
}

TEST(ConvergenceTable, OneRowPerResolutionWithPairwiseAndFittedRates) {
  const std::string t = convergence_table(built_in(), synthetic_study(1, 0));
  // Units in every header; 1D: the H1 seminorm, not an energy column.
  for (const char* h : {"nodes [1]", "h [length]", "L2 rel [1]", "L2 rate [1]", "H1-semi rel [1]",
                        "H1-semi rate [1]", "CPU [s]"})
    EXPECT_NE(t.find(h), std::string::npos) << h << "\n" << t;
  EXPECT_EQ(t.find("energy"), std::string::npos) << t;
  // Row 2: 20 nodes, h 0.05, L2 2.5e-3 with rate 2.00, H1 5e-2 with rate 1.00.
  EXPECT_TRUE(std::regex_search(t, std::regex(R"(\|\s+20 \|\s+5\.000e-02 \|)"))) << t;
  EXPECT_TRUE(std::regex_search(t, std::regex(R"(2\.500e-03 \|\s+2\.00 \|)"))) << t;
  EXPECT_TRUE(std::regex_search(t, std::regex(R"(5\.000e-02 \|\s+1\.00 \|)"))) << t;
  // Last row: least-squares rates and the total CPU time.
  EXPECT_NE(t.find("least squares"), std::string::npos) << t;
  EXPECT_NE(t.find("0.750"), std::string::npos) << t;
}

TEST(ConvergenceTable, ElasticityShowsTheEnergyErrorAndTransientOnlyItsMainError) {
  const std::string e = convergence_table(built_in(), synthetic_study(2, 0));
  EXPECT_NE(e.find("energy rel [1]"), std::string::npos) << e;
  EXPECT_NE(e.find("1.50"), std::string::npos) << e;
  EXPECT_EQ(e.find("H1"), std::string::npos) << "the energy error may not be labelled H1:\n" << e;
  const std::string d = convergence_table(built_in(), synthetic_study(2, 100));
  EXPECT_EQ(d.find("energy"), std::string::npos) << d;
  EXPECT_EQ(d.find("H1"), std::string::npos) << d;
  EXPECT_NE(d.find("L2 rel [1]"), std::string::npos) << d;
}

TEST(ConvergenceTable, AnalysesShowTheirMeasuredValuesNotZeroErrors) {
  StudyResult s = synthetic_study(1, 0);
  for (auto& r : s.cases) {
    r.analysis = "dispersion";
    r.detail.reset();
    r.data<FigureData>().setup = "lattice";
    r.headline["critical dt"] = 0.125;
  }
  const std::string t = convergence_table(built_in(), s);
  EXPECT_NE(t.find("critical dt"), std::string::npos) << t;
  EXPECT_NE(t.find("0.125"), std::string::npos) << t;
  EXPECT_EQ(t.find("L2"), std::string::npos) << "an analysis has no error norm:\n" << t;
}

TEST_F(Commands, StudyPrintsTheConvergenceTable) {
  CompareOptions o;
  o.problem = "laplace-tanh";
  o.methods = {"fem"};
  o.nodes = {21, 41, 81};
  std::ostringstream out, progress;
  ASSERT_EQ(command_compare(catalogue_, o, out, progress), 0);
  const std::string t = out.str();
  for (const char* n : {"least squares", "H1-semi rate [1]"})
    EXPECT_NE(t.find(n), std::string::npos) << n << "\n" << t;
  for (const char* n : {R"(\|\s+21 \|)", R"(\|\s+41 \|)", R"(\|\s+81 \|)"})
    EXPECT_TRUE(std::regex_search(t, std::regex(n))) << n << "\n" << t;
}

/// Issue 25 item 9: study and compare judge the problem's findings on the studies they ran
/// (matched by method and parameters), not only on manifest cases; a finding that needs a
/// study that did not run says what did run.
TEST_F(Commands, CompareChecksTheFindingsOnTheStudiesItRan) {
  CompareOptions o;
  o.problem = "cantilever";
  o.methods = {"efg-ci", "kbm-si"};
  o.nodes = {5, 9, 17};
  std::ostringstream out, progress;
  ASSERT_EQ(command_compare(catalogue_, o, out, progress), 0);
  const std::string t = out.str();
  ASSERT_NE(t.find("Findings of the papers, checked on the studies above"), std::string::npos) << t;
  // efg-ci and kbm-si ran: the findings about them have a verdict, never "not run".
  for (const char* claim : {"EFG with cell integration gives the best results",
                            "KBM with stress points: displacement rate close to 2"}) {
    const auto at = t.find(claim);
    ASSERT_NE(at, std::string::npos) << claim << "\n" << t;
    const auto line = t.rfind('\n', at);
    EXPECT_EQ(t.substr(line + 1, at - line - 1).find("not run"), std::string::npos)
        << claim << "\n" << t;
  }
  // A finding about a method that did not run names what ran.
  EXPECT_NE(t.find("no study of rlm or kbm-ni (ran: efg-ci at 3 resolutions; kbm-si at 3 "
                   "resolutions)"),
            std::string::npos)
      << t;
}

TEST_F(Commands, CompareRefusesUnknownParametersListingValidOnes) {
  CompareOptions o;
  o.problem = "laplace-tanh";
  o.methods = {"rkpm:jj=1"};
  std::ostringstream out, progress;
  try {
    command_compare(catalogue_, o, out, progress);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("jj"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("kernel"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(progress.str().empty()) << "nothing may run before the input is checked";
}

TEST_F(Commands, ManifestCtestRegistersEveryCaseWithLabels) {
  const fs::path m = manifest("[1.8, 2.2]");
  const fs::path script = dir_ / "tests.cmake";
  command_manifest_ctest(m.string(), "/bin/mfv", script.string());
  std::stringstream text;
  text << std::ifstream(script).rdbuf();
  EXPECT_NE(text.str().find("add_test([==[lt/fem]==] [==[/bin/mfv]==] verify"),
            std::string::npos)
      << text.str();
  EXPECT_NE(text.str().find("--case [==[lt/fem]==] --no-report"), std::string::npos);
  EXPECT_NE(text.str().find("LABELS [==[regression;laplace-tanh;fem]==]"), std::string::npos);
}

TEST(SplitMethodSpec, NameAndParameters) {
  EXPECT_EQ(split_method_spec("rkpm:j=1,kernel=gaussian"),
            (std::pair<std::string, std::string>{"rkpm", "j=1,kernel=gaussian"}));
  EXPECT_EQ(split_method_spec("fem"), (std::pair<std::string, std::string>{"fem", ""}));
  EXPECT_THROW(split_method_spec(":j=1"), InputError);
}

}  // namespace
}  // namespace mfv
