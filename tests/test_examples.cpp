/// The worked examples of docs/architecture.md, compiled and run: a transient problem in one
/// file (tests/example_problem.cpp) and an analysis in one file (tests/example_analysis.cpp),
/// each added to the catalogue by one registration line.
#include <cmath>
#include <sstream>

#include <gtest/gtest.h>

#include "analyses/report_section.hpp"
#include "apps/catalogue.hpp"
#include "temp_files.hpp"
#include "verify/runner.hpp"

namespace mfv {

void register_standing_wave(ProblemRegistry&);
void register_volume_check(AnalysisRegistry&);

namespace {

/// The catalogue with the two examples: one registration line each.
const Catalogue& with_examples() {
  static const Catalogue c([] {
    Extensions e;
    e.problems.push_back(register_standing_wave);
    e.analyses.push_back(register_volume_check);
    return e;
  }());
  return c;
}

CaseSpec standing_wave(const std::string& method, int nodes, const std::string& analysis = "") {
  CaseSpec s;
  s.problem = "standing-wave";
  // The engine's parameters go to the transient analysis; volume-check has its own.
  if (analysis.empty()) s.problem_params = Params::parse("frames=0,threads=1");
  s.method = method;
  s.nodes = nodes;
  s.analysis = analysis;
  return s;
}

TEST(ExampleProblem, StandingWaveRunsUnderTheTransientAnalysis) {
  // Its default analysis is the first it declares; the engine's parameters (frames, threads)
  // go to the analysis.
  const CaseResult r = run_case(with_examples(), standing_wave("fem", 41));
  EXPECT_EQ(r.analysis, "transient");
  EXPECT_FALSE(r.data<TransientData>().instability.has_value());
  EXPECT_GT(r.data<TransientData>().steps, 10);
  // One period of the first mode on 41 linear elements (measured 2.9e-7).
  EXPECT_LT(r.errors.l2_rel, 1e-6);
  EXPECT_EQ(r.headline.at("velocity error"), r.errors.l2_rel);
  EXPECT_LT(r.headline.at("energy drift"), 1e-2);
}

TEST(ExampleProblem, ErrorFallsUnderRefinement) {
  // Measured: 2.7e-6 at 21 nodes, 2.9e-7 at 41; from 81 nodes on the material's own
  // nonlinearity (2.4e-7, see kV0) is the floor.
  const StudyResult s = run_study(with_examples(), standing_wave("fem", 0), {21, 41});
  ASSERT_EQ(s.cases.size(), 2u);
  EXPECT_LT(s.cases[1].errors.l2_rel, s.cases[0].errors.l2_rel / 4);  // at least second order
}

TEST(ExampleProblem, EveryMethodThatRunsInOneDimensionStaysStable) {
  // Every registered method that accepts a 1D bar runs it under the same analysis; the
  // Lagrangian kernel keeps each of them stable (their accuracy with the ends held through
  // the particle parameters differs: that is the methods', not the example's).
  int ran = 0;
  for (const auto& m : with_examples().methods.keys()) {
    CaseResult r;
    try {
      r = run_case(with_examples(), standing_wave(m, 41));
    } catch (const InputError&) {
      continue;  // a 2D-only method, or one that needs a crack
    }
    ++ran;
    EXPECT_FALSE(r.data<TransientData>().instability.has_value()) << m;
    EXPECT_TRUE(std::isfinite(r.errors.l2_rel) && r.errors.l2_rel < 1) << m << " " << r.errors.l2_rel;
  }
  EXPECT_GE(ran, 7);
}

TEST(ExampleAnalysis, VolumeCheckRunsOnTheProblemThatDeclaresIt) {
  const CaseResult r = run_case(with_examples(), standing_wave("fem", 21, "volume-check"));
  EXPECT_EQ(r.analysis, "volume-check");
  EXPECT_NEAR(r.headline.at("volume sum / measure"), 1.0, 1e-12);
  std::ostringstream out;
  EXPECT_EQ(with_examples().analyses.create("volume-check")->print_case(r, out), 0);
  EXPECT_NE(out.str().find("passed"), std::string::npos) << out.str();
}

TEST(ExampleAnalysis, ItsParametersComeThroughTheCaseAndAreChecked) {
  CaseSpec s = standing_wave("fem", 21, "volume-check");
  s.problem_params = Params::parse("tolerance=0");
  EXPECT_THROW(run_case(with_examples(), s), InputError);  // positive() refuses 0
}

TEST(ExampleAnalysis, AProblemThatDoesNotDeclareItIsRefused) {
  CaseSpec s;
  s.problem = "laplace-tanh";
  s.method = "fem";
  s.nodes = 11;
  s.analysis = "volume-check";
  try {
    run_case(with_examples(), s);
    FAIL() << "laplace-tanh ran under volume-check";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("its analyses: static-solve"), std::string::npos)
        << e.what();
  }
}

TEST(ExampleAnalysis, ItsReportPageIsWritten) {
  test::TempDir dir("mfv-test-example-analysis");
  std::vector<ReportSection> sections;
  StudyResult s = run_study(with_examples(), standing_wave("fem", 0, "volume-check"), {11, 21});
  add_to_sections(with_examples(), sections, std::move(s));
  ASSERT_EQ(sections.size(), 1u);
  EXPECT_EQ(sections.front().analysis, "volume-check");
  const std::string summary = write_problem_section(with_examples(), sections.front(), dir.path(),
                                                    false);
  EXPECT_NE(summary.find("passed"), std::string::npos) << summary;
}

}  // namespace
}  // namespace mfv
