/// CPU time judged against the machine that runs it (verify/timing.hpp, issue 42): a machine
/// uniformly slower than the baseline's passes; one case far slower than the rest of the run
/// is named as a timing regression, and fails the run only under the timing gate.
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "apps/commands.hpp"
#include "verify/baseline.hpp"
#include "verify/timing.hpp"

namespace mfv {
namespace {

namespace fs = std::filesystem;

/// `n` cases whose CPU is `slowdown` × the baseline's (with a ±10 % spread, as a quiet
/// machine gives); the baseline's seconds run from 0.5 s to 50 s.
std::vector<CaseTiming> uniform_run(int n, double slowdown) {
  std::vector<CaseTiming> v;
  for (int i = 0; i < n; ++i) {
    const double base = 0.5 + 49.5 * i / std::max(1, n - 1);
    const double spread = 1 + 0.1 * std::sin(1.7 * i);
    v.push_back({"case-" + std::to_string(i), base, slowdown * base * spread});
  }
  return v;
}

TEST(MachineFactor, IsTheRunsMedianRatioWhenEnoughCasesHaveABaselineTime) {
  const MachineFactor f = machine_factor(uniform_run(40, 2.2), 0.2, 0.1);
  ASSERT_TRUE(f.known());
  EXPECT_NEAR(f.factor, 2.2, 0.1);
  EXPECT_EQ(f.rule, "median of 40 cases");
  EXPECT_NEAR(f.reference, 2.0, 1e-12) << "the reference workload's ratio is reported beside it";
}

TEST(MachineFactor, FallsBackToTheReferenceWorkloadForAFewCasesAndIsUnknownWithoutIt) {
  const auto few = uniform_run(kMinFactorCases - 1, 3.0);
  const MachineFactor r = machine_factor(few, 0.3, 0.1);
  ASSERT_TRUE(r.known());
  EXPECT_EQ(r.rule, "reference workload");
  EXPECT_NEAR(r.factor, 3.0, 1e-12);
  const MachineFactor none = machine_factor(few, 0.3, NAN);
  EXPECT_FALSE(none.known());
  EXPECT_NE(none.why_unknown.find("reference workload"), std::string::npos) << none.why_unknown;
  EXPECT_TRUE(judge_timing(few, none).empty()) << "no factor: nothing judged";
  EXPECT_NE(timing_status({}, none, false).find("not judged"), std::string::npos);
}

TEST(MachineFactor, LeavesShortCasesOutOfTheMedian) {
  std::vector<CaseTiming> v = uniform_run(10, 2.0);
  // Twenty start-up-dominated cases 10× slower: below the floor, they cannot move the median.
  for (int i = 0; i < 20; ++i) v.push_back({"short-" + std::to_string(i), 0.01, 0.1});
  const MachineFactor f = machine_factor(v, NAN, NAN);
  EXPECT_EQ(f.median_cases, 10);
  EXPECT_NEAR(f.factor, 2.0, 0.15);
}

// The "Done when": a baseline whose CPU seconds are all 4× smaller passes, while one
// case 8× slower than the rest is named as a timing regression with both ratios.
TEST(TimingVerdicts, AUniformlySlowerMachinePassesAndOneCaseFarSlowerIsNamed) {
  std::vector<CaseTiming> run = uniform_run(389, 4.0);
  MachineFactor f = machine_factor(run, NAN, NAN);
  std::vector<TimingVerdict> v = judge_timing(run, f);
  ASSERT_EQ(v.size(), 389u);
  for (const auto& t : v) EXPECT_FALSE(t.slower || t.faster) << t.message;
  const std::string pass = timing_status(v, f, false);
  EXPECT_NE(pass.find("every one within 3×"), std::string::npos) << pass;
  EXPECT_NE(pass.find("4."), std::string::npos) << "the factor is printed: " << pass;

  run[200].current = 8 * 4.0 * run[200].baseline;  // 8× the rest of the run
  f = machine_factor(run, NAN, NAN);
  v = judge_timing(run, f);
  int slower = 0;
  for (const auto& t : v)
    if (t.slower) {
      ++slower;
      EXPECT_EQ(t.id, "case-200");
      EXPECT_NEAR(t.ratio, 32, 1e-9);
      EXPECT_NEAR(t.relative, 8, 0.5);
      EXPECT_NE(t.message.find("32.0× the baseline"), std::string::npos) << t.message;
      EXPECT_NE(t.message.find("the run's machine factor"), std::string::npos) << t.message;
    }
  EXPECT_EQ(slower, 1);
  const std::string ungated = timing_status(v, f, false);
  EXPECT_NE(ungated.find("case-200"), std::string::npos) << ungated;
  EXPECT_NE(ungated.find("not gated"), std::string::npos) << ungated;
  EXPECT_NE(timing_status(v, f, true).find("the timing gate fails the run"), std::string::npos);
}

TEST(TimingVerdicts, AFasterCaseIsANoteAndAShortCasesNoiseIsNeither) {
  std::vector<CaseTiming> run = uniform_run(20, 1.0);
  run.push_back({"fast", 40, 4});
  run.push_back({"short", 0.01, 0.5});  // 50× but 0.5 s: inside the floor
  const MachineFactor f = machine_factor(run, NAN, NAN);
  for (const auto& t : judge_timing(run, f)) {
    EXPECT_FALSE(t.slower) << t.message;
    EXPECT_EQ(t.faster, t.id == "fast") << t.id;
  }
  // With no floor the short case is judged too.
  bool short_slower = false;
  for (const auto& t : judge_timing(run, f, 0))
    if (t.id == "short") short_slower = t.slower;
  EXPECT_TRUE(short_slower);
}

TEST(TimingVerdicts, RatiosPrintWithTwoDecimalsBelowTen) {
  EXPECT_EQ(fmt_ratio(3.04), "3.04×");
  EXPECT_EQ(fmt_ratio(2.996), "3.00×");
  EXPECT_EQ(fmt_ratio(12.34), "12.3×");
  EXPECT_EQ(fmt_ratio(NAN), "–");
}

TEST(TimingVerdicts, CpuComparesAtTheSameThreadCountsWhateverTheModel) {
  EXPECT_TRUE(cpu_comparable(machine_note("AMD EPYC", 2, 2), machine_note("Intel Xeon, 2.6GHz", 2, 2)));
  EXPECT_FALSE(cpu_comparable(machine_note("AMD EPYC", 2, 2), machine_note("AMD EPYC", 2, 1)));
  EXPECT_FALSE(cpu_comparable(machine_note("AMD EPYC", 2, 2), machine_note("AMD EPYC", 4, 2)));
  EXPECT_FALSE(cpu_comparable("", ""));
  EXPECT_TRUE(same_machine(machine_note("X", 2, 2), machine_note("X", 2, 2)));
  EXPECT_FALSE(same_machine(machine_note("X", 2, 2), machine_note("Y", 2, 2)));
}

TEST(ReferenceWorkload, IsRepeatableOnAQuietCore) {
  const double a = reference_workload_seconds(3), b = reference_workload_seconds(3);
  ASSERT_GT(a, 0);
  EXPECT_LT(std::abs(a - b) / std::min(a, b), 1.0) << a << " vs " << b;
}

TEST(MachineLoad, ReadsTheLoadAverageAndAStealFraction) {
  const MachineLoad a = read_machine_load();
  volatile double x = 0;
  for (int i = 0; i < 20000000; ++i) x = x + std::sqrt(static_cast<double>(i));
  const MachineLoad b = read_machine_load();
  EXPECT_GE(a.load_average, 0);
  const double s = steal_fraction(a, b);
  if (std::isfinite(s)) {
    EXPECT_GE(s, 0);
    EXPECT_LE(s, 1);
  }
}

/// mfv verify end to end: three cases whose baseline is rewritten with CPU seconds 4× smaller
/// (and a reference workload 4× faster) pass; the same with one case 8× slower than that
/// names it, still passes, and fails with --timing-gate (or [suite] timing_gate = true).
class TimingCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    static std::atomic<int> n{0};
    dir_ = fs::temp_directory_path() /
           ("mfv-timing-" + std::to_string(::getpid()) + "-" + std::to_string(n++));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path manifest(const std::string& suite_extra) {
    std::string text = "[suite]\nname = \"t\"\nbaseline = \"baseline.toml\"\n"
                       "timing_floor_seconds = 0\n" + suite_extra;
    for (const char* id : {"a", "b", "c"})
      text += fmt::format("[[case]]\nid = \"cantilever/{}\"\nproblem = \"cantilever\"\n"
                          "method = \"efg-ci\"\nnodes = [5, 9]\n",
                          id);
    std::ofstream(dir_ / "suite.toml") << text;
    return dir_ / "suite.toml";
  }
  int verify(const fs::path& m, std::string& out, bool update = false, bool gate = false) {
    VerifyOptions o;
    o.manifest = m.string();
    o.update_baseline = update;
    o.timing_gate = gate;
    o.no_report = true;
    std::ostringstream s, progress;
    const int rc = command_verify(catalogue_, o, s, progress);
    out = s.str();
    return rc;
  }
  /// The recorded baseline with every CPU time and the reference workload divided by
  /// `factor`, and the CPU of `slow` (if named) by 8 more.
  void faster_baseline(double factor, const std::string& slow = "") {
    Baseline b = load_baseline(dir_ / "baseline.toml");
    ASSERT_TRUE(std::isfinite(b.reference_seconds));
    b.reference_seconds /= factor;
    for (auto& [id, c] : b.cases) c.cpu_seconds /= factor * (id == slow ? 8 : 1);
    std::ofstream(dir_ / "baseline.toml") << baseline_to_toml(b);
  }
  const Catalogue catalogue_;
  fs::path dir_;
};

TEST_F(TimingCommand, AUniformSlowdownPassesAndOneSlowCaseFailsOnlyUnderTheGate) {
  const fs::path m = manifest("");
  std::string out;
  ASSERT_EQ(verify(m, out, true), 0) << out;
  faster_baseline(4);
  ASSERT_EQ(verify(m, out), 0) << out;
  EXPECT_NE(out.find("PASS: all 3 case(s)"), std::string::npos) << out;
  EXPECT_NE(out.find("every one within 3×"), std::string::npos) << out;
  EXPECT_NE(out.find("(reference workload)"), std::string::npos) << out;
  EXPECT_EQ(verify(m, out, false, true), 0) << "the gate passes a uniform slowdown:\n" << out;

  ASSERT_EQ(verify(m, out, true), 0) << out;
  faster_baseline(4, "cantilever/b");
  EXPECT_EQ(verify(m, out), 0) << "timing is reported, not gated:\n" << out;
  EXPECT_NE(out.find("timing: 1 case(s) more than 3× slower"), std::string::npos) << out;
  EXPECT_NE(out.find("cantilever/b"), std::string::npos) << out;
  EXPECT_NE(out.find("× the machine factor |"), std::string::npos)
      << "the case's column says it: " << out;
  EXPECT_EQ(verify(m, out, false, true), 1) << out;
  EXPECT_NE(out.find("FAIL: 1 of 3 case(s) of suite 't' failed: 1 timing"), std::string::npos)
      << out;
  // The manifest's gate does what the flag does.
  const fs::path gated = manifest("timing_gate = true\n");
  EXPECT_EQ(verify(gated, out), 1) << out;
}

TEST_F(TimingCommand, ACaseNotInTheBaselineIsNewUnlessTheBaselineIsRequired) {
  const fs::path m = manifest("");
  std::string out;
  EXPECT_EQ(verify(m, out), 0) << out;
  EXPECT_NE(out.find("new: record it with --update-baseline"), std::string::npos) << out;
  EXPECT_NE(out.find("(3 new, not yet in the baseline)"), std::string::npos) << out;
  VerifyOptions o;
  o.manifest = m.string();
  o.no_report = true;
  o.require_baseline = true;
  std::ostringstream s, progress;
  EXPECT_EQ(command_verify(catalogue_, o, s, progress), 1) << s.str();
  EXPECT_NE(s.str().find("failed: 3 baseline"), std::string::npos) << s.str();
}

}  // namespace
}  // namespace mfv
