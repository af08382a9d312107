/// Manufactured solutions (problems/manufactured.cpp): each a smooth exact field with its
/// derivatives and the source of its operator derived by hand, so that tests can check the
/// derivation against finite differences (tests/test_manufactured.cpp) and the problems can
/// stay plain BoundaryValueProblems.
#pragma once
#include <cmath>

namespace mfv::mms {

/// u = sin(κx) + x² for −k u″ = f: f = k (κ² sin κx − 2).
struct SineQuadratic1D {
  double kappa = 3, k = 1;
  double u(double x) const { return std::sin(kappa * x) + x * x; }
  double du(double x) const { return kappa * std::cos(kappa * x) + 2 * x; }
  double source(double x) const { return k * (kappa * kappa * std::sin(kappa * x) - 2); }
};

}  // namespace mfv::mms
