/// The readable report: the shared convergence judgement (verify/convergence.hpp), the
/// cantilever findings that use it, and the problem pages with their one-screen summaries.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "verify/catalogue.hpp"
#include "verify/convergence.hpp"

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
  if (c.expected != Trend::converges)
    EXPECT_EQ(j.label().find("converges"), std::string::npos) << j.label();
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

}  // namespace
}  // namespace mfv
