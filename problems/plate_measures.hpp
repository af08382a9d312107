/// What the compressed plate measures (001 §9.4): the angle of a shear band to the
/// compression axis, fitted by a Radon projection of the effective plastic strain, and the
/// growth rate of the oscillation of a band particle's stress–strain curve (001 Fig. 15).
/// Pure functions of particle fields and time series, tested on synthetic data.
#pragma once
#include <vector>

#include <Eigen/Dense>

namespace mfv {

/// Shear bands as straight lines. A band at angle φ to the compression axis (y) runs along
/// d = (sin φ, cos φ); its points share the coordinate s = n·(x − x̄), n = (cos φ, −sin φ).
/// For each φ the weights (ε̄ − floor·max ε̄, clipped at 0: the band core) are binned in s
/// and the fit scores the correlation ratio
///   η²(φ) = Σ_b n_b (m_b − m)² / Σ_i (w_i − m)²
/// (between-bin over total variance; 1 when the weight is constant along lines of angle φ,
/// the Radon transform's peak). Each sign of φ is one family of slip lines; von Mises
/// plane strain has both at ±45° to the principal axes (Hill 1950, ch. VI).
struct PlateBandFit {
  double angle_plus = 0, angle_minus = 0;        ///< |φ| of the best φ > 0 and φ < 0, degrees
  double strength_plus = 0, strength_minus = 0;  ///< η² there
  double angle = 0;     ///< |φ| of the stronger family
  int families = 0;     ///< families whose η² is at least half the stronger one's
};

/// x: 2 × n reference positions; weight: ε̄ per point, capped by the caller at a band's own
/// level where bands cross or end in a concentration (else only that spot passes the floor); bins: the projection's resolution
/// (about the lattice's points per side); angles searched in steps of step_deg over
/// (0, 90] and [−90, 0).
PlateBandFit fit_band_angles(const Eigen::MatrixXd& x, const Eigen::VectorXd& weight, int bins,
                             double floor = 0.5, double step_deg = 0.5);

/// Centred moving average over `window` samples (shrunk symmetrically near the ends).
std::vector<double> moving_average(const std::vector<double>& y, int window);

/// The oscillation of y(t) about its trend (the moving average over `window` samples):
/// the residual r = y − trend is split at its sign changes into half-periods; the peak |r|
/// of each complete half-period (ignoring window/2 samples at each end, where the trend is
/// biased) is an envelope sample a_k at t_k, and
///   ln a_k ≈ ln a_0 + g t_k   (least squares)
/// gives the growth rate g (1/unit of t: > 0 grows, < 0 decays). Peaks below `floor` are
/// not an oscillation (round-off about a smooth curve) and are left out.
struct OscillationFit {
  double growth_rate = 0;      ///< g; NaN with fewer than 4 half-periods above the floor
  double growth_factor = 0;    ///< exp(g (t_last − t_first)) over the fitted peaks
  double amplitude_ratio = 0;  ///< mean of the last two peaks over the first two
  double relative_amplitude = 0;  ///< rms(r) over rms(trend) in the fitted range
  int half_periods = 0;
  std::vector<double> peak_t, peak_a;
};

OscillationFit oscillation_growth(const std::vector<double>& t, const std::vector<double>& y,
                                  int window, double floor = 0);

}  // namespace mfv
