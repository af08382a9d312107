/// Discretization uncertainty of a computed number from its values under refinement (issue 44):
/// Roache's grid convergence index as ASME V&V 20 and Celik et al. (2008, J. Fluids Eng. 130,
/// 078001) state it, with the convergence class and, for more than three levels, the
/// Eça–Hoekstra least-squares order (2014, J. Comput. Phys. 262). The layer knows no
/// numerics: h is any refinement parameter (spacing, time step), φ any quantity.
///
/// Three finest levels h1 < h2 < h3 (values φ1, φ2, φ3), r21 = h2/h1, r32 = h3/h2,
/// ε21 = φ2 − φ1, ε32 = φ3 − φ2, s = sign(ε32/ε21):
///   observed order  p = |ln|ε32/ε21| + q(p)| / ln r21,  q(p) = ln((r21^p − s)/(r32^p − s))
///                   (fixed-point iteration; q = 0 when r21 = r32)
///   extrapolated    φ_ext = (r21^p φ1 − φ2)/(r21^p − 1)
///   GCI_fine        = F_s |(φ1 − φ2)/φ1| / (r21^p − 1),  F_s = 1.25
///   asymptotic      GCI32 / (r21^p GCI21), ≈ 1 in the asymptotic range
///   class           R = ε21/ε32: 0 < R < 1 monotone, −1 < R < 0 oscillatory convergence,
///                   R ≥ 1 monotone divergence, R ≤ −1 oscillatory divergence.
/// Two levels: the assumed (formal) order p and F_s = 3. The uncertainty U = GCI_fine |φ1|.
#pragma once
#include <cmath>
#include <string>
#include <vector>

namespace mfv {

enum class ConvergenceClass {
  monotone,               ///< 0 < R < 1
  oscillatory,            ///< −1 < R < 0
  monotone_divergent,     ///< R ≥ 1: the changes grow
  oscillatory_divergent,  ///< R ≤ −1
  exact,                  ///< the finer change is zero (to round-off): nothing to estimate
  two_levels,             ///< two levels: no class, an assumed order
  undetermined            ///< fewer than two finite levels
};
const char* convergence_class_name(ConvergenceClass c);

struct Uncertainty {
  int levels = 0;                   ///< finite levels used
  double value = NAN;               ///< φ at the finest level
  double order = NAN;               ///< observed (or, two levels, assumed) order p
  bool assumed_order = false;       ///< two levels: p was given, not observed
  double order_least_squares = NAN; ///< Eça–Hoekstra fit over every level (more than three)
  double extrapolated = NAN;        ///< Richardson-extrapolated value
  double gci = NAN;                 ///< GCI_fine, relative to |φ1|
  double absolute = NAN;            ///< U = GCI_fine |φ1|
  double asymptotic = NAN;          ///< GCI32 / (r^p GCI21); NaN with fewer than three levels
  ConvergenceClass cls = ConvergenceClass::undetermined;
  std::string why_none;             ///< when no uncertainty could be estimated: why
  /// How it was estimated: "GCI, 3 levels (Celik et al. 2008)", "GCI, 2 levels, F_s = 3",
  /// or a caller's own ("difference from an independent route").
  std::string method;
  bool known() const { return std::isfinite(absolute); }
  /// "± 4.1e-03 (p = 1.93, monotone)", or "± – (why)".
  std::string text() const;
};

/// From values `f` at refinement parameters `h` (any order; non-finite pairs dropped):
/// three or more levels as above on the three finest, two levels with `assumed_order` (NaN:
/// none can be estimated). Divergent classes and a non-positive order give no uncertainty.
Uncertainty grid_uncertainty(std::vector<double> h, std::vector<double> f,
                             double assumed_order = NAN);

/// Whether `paper` lies inside ours ± (U + tolerance·|paper|) (`relative` tolerance) or ±
/// (U + tolerance) (absolute); false when U is not known.
bool within_uncertainty(double ours, const Uncertainty& u, double paper, double tolerance,
                        bool relative);

}  // namespace mfv
