/// What the ring problems measure on a polar lattice (000 §5.2–5.3, 001 §9.5–9.6): the
/// rotational symmetry of σθθ, particle clustering, and shear bands fitted as logarithmic
/// spirals in log-polar coordinates. Pure functions of particle fields, so they are tested
/// on synthetic fields with known answers.
#pragma once
#include <vector>

#include <Eigen/Dense>

namespace mfv {

/// A per-row index and its worst row.
struct RowIndex {
  double worst = 0;
  int row = -1;
  std::vector<double> per_row;
};

/// Rotational symmetry of a field on rows of constant radius (001 Fig. 19): per row i the
/// spread around the row mean over the row's scale,
///   s_i = std_j(v_ij) / max(rms_j(v_ij), floor · rms(v)),
/// 0 for a rotationally symmetric field, near 1 when the row's values are concentrated at
/// discrete spots around a mean near zero. The floor (a fraction of the whole ring's RMS)
/// keeps a row whose values pass through zero from dividing by nothing. `values` holds
/// rows × per_row values, row-major (index j + per_row · i).
RowIndex symmetry_index(const Eigen::VectorXd& values, int rows, int per_row,
                        double floor = 0.1);

/// Particle clustering (000 Figs 14–15, 001 Fig. 18): per row, the largest over the smallest
/// distance between circumferential neighbours (j, j+1 cyclically) at the current
/// positions x (2 × rows·per_row): 1 for an evenly spaced row, large when particles bunch.
RowIndex clustering_index(const Eigen::MatrixXd& x, int rows, int per_row);

/// σθθ = t·σ·t, t = (−sin θ, cos θ) at the position's polar angle; sigma is a column-major
/// 2×2 Cauchy stress.
double hoop_stress(const Eigen::Vector2d& x, const double* sigma);
/// σrr = e·σ·e, e = (cos θ, sin θ).
double radial_stress(const Eigen::Vector2d& x, const double* sigma);

/// Shear bands fitted as logarithmic spirals. In ζ = ln(r/a), θ a spiral at angle ψ to the
/// radial direction is the straight line θ = θ0 ± ζ tan ψ (slip lines of a perfectly plastic
/// thick cylinder: ψ = π/4, slope ±1). The fit projects the plastic strain, detrended by its
/// mean over each radial bin (bands are what stands out of a row), along lines of slope s
/// onto θ0 = θ − sζ (a Radon transform on the periodic θ axis) and takes, for each sign of s,
/// the slope whose projected profile has the largest variance: the band families' slopes.
struct BandFit {
  double slope_plus = 0, slope_minus = 0;  ///< fitted dθ/dζ of each family (> 0, < 0)
  double angle_plus = 0, angle_minus = 0;  ///< ψ = atan|s| in degrees (π/4: 45)
  /// Variance of the projected profile at the fitted slope over its value at the best slope
  /// of the other sign; and the family's prominence, (C(s) − min C between 0 and s)/C(s).
  double prominence_plus = 0, prominence_minus = 0;
  /// Each family's projected variance over the stronger family's (1 for the stronger).
  double strength_plus = 0, strength_minus = 0;
  /// An interior peak (not at the search range's ends) with prominence ≥ 0.1 and strength
  /// ≥ 0.25.
  bool plus_present = false, minus_present = false;
  int bands = 0;                   ///< peaks of the stronger family's profile above half its max
  std::vector<double> positions;   ///< their θ0 in degrees, [0, 360)
  double contrast = 0;             ///< std of the detrended field over its mean (0: no bands)
};

/// zeta, theta, weight: one entry per sample point (ζ = ln(R/a) ≥ 0, θ in radians, the
/// effective plastic strain); radial_bins and theta_bins set the detrending rows and the
/// projection's resolution; slopes are searched in [−max_slope, max_slope] in steps of
/// slope_step.
BandFit fit_log_spiral_bands(const Eigen::VectorXd& zeta, const Eigen::VectorXd& theta,
                             const Eigen::VectorXd& weight, int radial_bins, int theta_bins,
                             double max_slope = 3.0, double slope_step = 0.01);

}  // namespace mfv
