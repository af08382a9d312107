/// The grid convergence index (reports/uncertainty.hpp): observed order, extrapolated value,
/// GCI and convergence class on sequences whose exact behaviour is known.
#include <cmath>

#include <gtest/gtest.h>

#include "reports/uncertainty.hpp"

namespace mfv {
namespace {

double f1_over_f2() { return (1 + 0.3 * 0.01) / (1 + 0.3 * 0.04); }

TEST(GridUncertainty, RecoversTheOrderAndTheLimitOfASmoothSequence) {
  // φ(h) = 1 + 0.3 h^2 at h = 0.4, 0.2, 0.1 (and a coarser one for the least-squares fit).
  std::vector<double> h{0.8, 0.4, 0.2, 0.1}, f;
  for (double x : h) f.push_back(1 + 0.3 * x * x);
  const Uncertainty u = grid_uncertainty(h, f);
  EXPECT_EQ(u.levels, 4);
  EXPECT_EQ(u.cls, ConvergenceClass::monotone);
  EXPECT_NEAR(u.order, 2.0, 1e-9);
  EXPECT_NEAR(u.order_least_squares, 2.0, 1e-3);
  EXPECT_NEAR(u.extrapolated, 1.0, 1e-12);
  EXPECT_NEAR(u.asymptotic, f1_over_f2(), 1e-9) << "exactly asymptotic: the ratio is φ1/φ2";
  // GCI_fine = 1.25 |φ1 − φ2| / |φ1| / (r^p − 1), r = 2, p = 2.
  const double f1 = 1 + 0.3 * 0.01, f2 = 1 + 0.3 * 0.04;
  EXPECT_NEAR(u.gci, 1.25 * (f2 - f1) / f1 / 3, 1e-12);
  EXPECT_NEAR(u.absolute, u.gci * f1, 1e-15);
  EXPECT_TRUE(within_uncertainty(f1, u, 1.0, 0, true)) << "the limit lies inside ± U";
  EXPECT_NE(u.text().find("p = 2.00, monotone"), std::string::npos) << u.text();
}

TEST(GridUncertainty, SolvesForTheOrderWithUnequalRefinementRatios) {
  std::vector<double> h{0.9, 0.5, 0.2}, f;  // r32 = 1.8, r21 = 2.5
  for (double x : h) f.push_back(2 - 0.5 * std::pow(x, 1.5));
  const Uncertainty u = grid_uncertainty(h, f);
  EXPECT_NEAR(u.order, 1.5, 1e-6);
  EXPECT_NEAR(u.extrapolated, 2.0, 1e-9);
}

TEST(GridUncertainty, NamesOscillationAndDivergence) {
  EXPECT_EQ(grid_uncertainty({0.4, 0.2, 0.1}, {1.4, 0.8, 1.1}).cls, ConvergenceClass::oscillatory);
  const Uncertainty d = grid_uncertainty({0.4, 0.2, 0.1}, {1.1, 1.3, 1.8});
  EXPECT_EQ(d.cls, ConvergenceClass::monotone_divergent);
  EXPECT_FALSE(d.known());
  EXPECT_NE(d.why_none.find("grow"), std::string::npos) << d.why_none;
  EXPECT_EQ(grid_uncertainty({0.4, 0.2, 0.1}, {1.0, 1.4, 0.6}).cls,
            ConvergenceClass::oscillatory_divergent);
}

TEST(GridUncertainty, TwoLevelsNeedAnAssumedOrderAndUseTheSafetyFactorThree) {
  EXPECT_FALSE(grid_uncertainty({0.2, 0.1}, {1.1, 1.02}).known());
  const Uncertainty u = grid_uncertainty({0.2, 0.1}, {1.1, 1.02}, 2.0);
  ASSERT_TRUE(u.known());
  EXPECT_TRUE(u.assumed_order);
  EXPECT_NEAR(u.gci, 3 * 0.08 / 1.02 / 3, 1e-12);
  EXPECT_EQ(grid_uncertainty({0.1}, {1.0}).why_none, "fewer than two resolutions");
  EXPECT_EQ(grid_uncertainty({0.2, 0.1}, {NAN, 1.0}).levels, 1) << "a NaN level is dropped";
}

TEST(GridUncertainty, AnUnchangedValueIsExactWithZeroUncertainty) {
  const Uncertainty u = grid_uncertainty({0.4, 0.2, 0.1}, {3.0, 3.0, 3.0});
  EXPECT_EQ(u.cls, ConvergenceClass::exact);
  EXPECT_EQ(u.absolute, 0);
  EXPECT_TRUE(within_uncertainty(3.0, u, 3.01, 0.01, true));
  EXPECT_FALSE(within_uncertainty(3.0, u, 3.1, 0.01, true));
}

}  // namespace
}  // namespace mfv
