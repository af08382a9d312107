/// Code verification by manufactured solutions (issue 46): a study's observed orders against
/// the order its method declares (Method::formal_order), per norm.
///   observed  the slope of the finest pair (the asymptotic order) beside the least-squares one
///   verdict   "at formal order" (|observed − formal| ≤ kOrderTolerance), "above
///             (superconvergent)", "below", "does not converge" (reports/convergence.hpp's
///             trend is not "converges"), or "no formal order declared" (the method's reason).
#pragma once
#include <string>
#include <vector>

#include "analyses/case.hpp"
#include "methods/methods/method.hpp"

namespace mfv {

struct Registries;

inline constexpr double kOrderTolerance = 0.3;

struct NormOrder {
  std::string norm;          ///< "L2", and "H1-semi" (scalar) or "energy" (vector fields)
  double formal = NAN;       ///< declared; NaN: none
  double observed = NAN;     ///< finest pair
  double least_squares = NAN;
  std::string verdict;
};

struct OrderJudgement {
  FormalOrder formal;
  std::vector<NormOrder> norms;  ///< L2, then the gradient's norm
  /// "formal L2 2 / H1 1 (source): observed L2 2.01 (least squares 1.99) at formal order; …"
  std::string text() const;
};

/// The study's method (created from its first case's spec) and its observed orders.
OrderJudgement judge_order(const Registries& catalogue, const StudyResult& s);

}  // namespace mfv
