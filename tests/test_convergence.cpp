/// Small refinement studies whose rates must fall inside bands (CTest label `convergence`),
/// and the published FEM column of 004 II Table 1, which linear elements reproduce exactly.
#include <cctype>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "test_support.hpp"
#include "verify/runner.hpp"

namespace mfv {
namespace {

struct RateCase {
  const char* problem;
  const char* method;
  const char* params;
  std::vector<int> nodes;
  double l2_low, l2_high, h1_low, h1_high;
};

class Rates : public ::testing::TestWithParam<RateCase> {};

TEST_P(Rates, InsideBand) {
  const RateCase& c = GetParam();
  CaseSpec spec{c.problem, {}, c.method, Params::parse(c.params), 0, 0};
  const StudyResult s = run_study(test_catalogue(), spec, c.nodes);
  EXPECT_GE(s.rates.rate("L2"), c.l2_low) << s.label;
  EXPECT_LE(s.rates.rate("L2"), c.l2_high) << s.label;
  EXPECT_GE(s.rates.rate("H1-semi"), c.h1_low) << s.label;
  EXPECT_LE(s.rates.rate("H1-semi"), c.h1_high) << s.label;
}

INSTANTIATE_TEST_SUITE_P(
    Studies, Rates,
    ::testing::Values(
        RateCase{"laplace-tanh", "fem", "", {81, 161, 321}, 1.9, 2.1, 0.95, 1.05},
        // EFG (linear basis, symmetric cubic window) superconverges on uniform particles: the
        // error of the quadratic term cancels by symmetry, giving O(h^4) in L2, O(h^3) in H1.
        RateCase{"laplace-tanh", "efg", "", {321, 641, 1281}, 3.8, 4.3, 2.8, 3.2},
        // 004 II: Gaussian-window RKPM converges far faster than FEM as the window widens.
        RateCase{"laplace-tanh", "rkpm", "j=1", {81, 121, 161}, 6.0, 30.0, 5.0, 30.0},
        RateCase{"advection-diffusion", "fem", "", {241, 481, 961}, 1.8, 2.2, 0.9, 1.1}),
    [](const ::testing::TestParamInfo<RateCase>& info) {
      std::string n = std::string(info.param.problem) + "_" + info.param.method + "_" +
                      info.param.params;
      for (char& ch : n)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      return n;
    });

TEST(PublishedValues, FemPeakGradientMatchesTable1) {
  // 004 II Table 1, FEM column: the slope of the element next to x = 3.
  const double published[] = {3.3168, 6.0343, 8.4687, 9.5562, 9.7967};
  const int nodes[] = {21, 41, 81, 161, 241};
  for (int i = 0; i < 5; ++i) {
    CaseSpec spec{"laplace-tanh", {}, "fem", {}, nodes[i], 0};
    const CaseResult r = run_case(test_catalogue(), spec);
    EXPECT_NEAR(r.headline.at("peak du/dx at x=3"), published[i], 6e-5) << nodes[i] << " nodes";
  }
}

}  // namespace
}  // namespace mfv
