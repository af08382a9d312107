/// Manufactured solutions (problems/manufactured.hpp): the hand-derived sources against
/// finite differences of the exact fields, and the problems against a method of known order.
#include <cmath>

#include <gtest/gtest.h>

#include "apps/catalogue.hpp"
#include "problems/manufactured.hpp"
#include "verify/runner.hpp"

namespace mfv {
namespace {

TEST(Manufactured, SineQuadraticSourceIsMinusKTimesTheSecondDerivative) {
  for (double kappa : {1.0, 3.0, 7.5})
    for (double k : {1.0, 0.2}) {
      const mms::SineQuadratic1D m{kappa, k};
      const double h = 1e-4;
      for (double x : {0.0, 0.3, 1.1, 2.0}) {
        const double d2 = (m.u(x + h) - 2 * m.u(x) + m.u(x - h)) / (h * h);
        EXPECT_NEAR(m.source(x), -k * d2, 1e-5 * (1 + kappa * kappa)) << kappa << " " << x;
        EXPECT_NEAR(m.du(x), (m.u(x + h) - m.u(x - h)) / (2 * h), 1e-7 * (1 + kappa * kappa));
      }
    }
}

TEST(Manufactured, LinearElementsConvergeAtTheirFormalOrderOnThePoissonProblem) {
  const Catalogue c;
  CaseSpec spec;
  spec.problem = "mms-poisson-1d";
  spec.method = "fem";
  const StudyResult s = run_study(c, spec, {11, 21, 41, 81});
  EXPECT_NEAR(s.rates.rate("L2"), 2.0, 0.1);
  EXPECT_NEAR(s.rates.rate("H1-semi"), 1.0, 0.1);
}

}  // namespace
}  // namespace mfv
