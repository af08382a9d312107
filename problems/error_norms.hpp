/// The error norms a problem's exact solution is measured in (004 II eq 7.2, 001 eqs 73–75):
/// what a static solve and a transient run report in common.
#pragma once
#include <cmath>

namespace mfv {

/// Error norms of u_h - u (004 II eq 7.2): absolute and relative to the exact solution's norm.
struct ErrorNorms {
  double l2 = 0, l2_rel = 0;            ///< ‖e‖_L2
  double h1_semi = 0, h1_semi_rel = 0;  ///< ‖e'‖_L2 (the paper's "H1 norm")
  double h1 = 0, h1_rel = 0;            ///< full H1: sqrt(‖e‖² + ‖e'‖²)
  /// Energy norm sqrt(∫ σ(e):ε(e)) (001 eqs 73–74 with the customary square root; in 1D
  /// the H1 seminorm).
  double energy = 0, energy_rel = 0;
  /// Every norm NaN: what a run reports for a norm it does not measure (a transient case has
  /// no H1 error) or a checkpoint it did not reach (a run stopped as unstable); printed
  /// "–" / "not reached", never 0.
  static ErrorNorms not_measured() {
    ErrorNorms e;
    e.l2 = e.l2_rel = e.h1_semi = e.h1_semi_rel = e.h1 = e.h1_rel = e.energy = e.energy_rel = NAN;
    return e;
  }
};

}  // namespace mfv
