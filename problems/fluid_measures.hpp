/// What the hydrostatic column and the dam break measure, and the experiment they are judged
/// against: the hydrostatic pressure error
///   e_p = ‖p − ρ0 g (H − y)‖₂ / ‖ρ0 g (H − y)‖₂   (over the points where p is known),
/// the dam break's surge front Z and residual column height H from the particle positions,
/// and Martin & Moyce's (1952) measurements of both for n² = 2 in the dimensionless times
/// T = n t √(g/a) = t √(2g/a) (front) and τ = t √(g/a) (height).
#pragma once
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>

namespace mfv::fluid {

/// The pressure of each column of a Cauchy stress matrix (4 × N, column-major 2 × 2):
/// p = −(σxx + σyy)/2 (the Tait fluid's stress is −p I).
Eigen::VectorXd pressure_of(const Eigen::MatrixXd& cauchy);

/// e_p of the pressures p at the points x (2 × N) against ρ0 g (surface − y); NaN when the
/// exact field is zero everywhere.
double hydrostatic_pressure_error(const Eigen::MatrixXd& x, const Eigen::VectorXd& p, double rho0,
                                  double g, double surface);

/// The surge front: the largest x of the particles touching the floor y = 0 (current y below
/// `band`, one spacing by default: the bottom row stands half a spacing above it), plus half a
/// spacing, the particle's own share of the lattice. NaN when no particle touches the floor.
/// Dummy wall particles hold a moving front further off (the dam break's walls=particles:
/// 1.3-1.9 spacings measured, Crespo et al. 2007's gap), so that run passes a wider band.
double surge_front(const Eigen::MatrixXd& x, double spacing, double band = 0);

/// The residual column height at the left wall x = 0: the largest y of the particles within
/// `band` of the wall (0: one spacing), plus half a spacing. NaN when no particle is there.
double column_height(const Eigen::MatrixXd& x, double spacing, double band = 0);

/// One digitization of an experiment: points (t_k, value_k), t increasing.
struct ExperimentSeries {
  std::string quantity;  ///< "Z/a", "H/a"
  std::vector<double> T, value;
};

/// Martin & Moyce (1952), n² = 2 (a column of height 2a), a = 2.25 in = 0.05715 m, Tables 2
/// and 6 as tabulated in Ocellaris (see dam_break.cpp for the citation); both series in
/// T = t √(2g/a) and values over a (the table's heights, over n² a against τ = t √(g/a), are
/// converted: H/a = 2 η, T = √2 τ).
ExperimentSeries martin_moyce_front();
ExperimentSeries martin_moyce_height();
/// The citation the reports print beside the series.
std::string martin_moyce_citation();

/// Linear interpolation of a history (t increasing) at time T; NaN outside [t.front(), t.back()].
double interpolate(const std::vector<double>& t, const std::vector<double>& v, double T);

/// Errors of a run's history (t, v) against an experiment at the experiment's points that the
/// run reached: RMS and max of |v(T_k) − value_k|, and how many points were compared.
struct SeriesError {
  double rms = NAN, max = NAN;
  int points = 0;
};
SeriesError series_error(const std::vector<double>& t, const std::vector<double>& v,
                         const ExperimentSeries& e, double shift = 0);

/// The time shift s (in T) minimizing the RMS of v(T_k − s) − value_k over shifts in
/// [0, max_shift] (a grid of `steps`): a diagnostic of how much of the error a late start of the
/// experiment explains, never a verdict.
double best_shift(const std::vector<double>& t, const std::vector<double>& v,
                  const ExperimentSeries& e, double max_shift, int steps = 200);

}  // namespace mfv::fluid

namespace mfv {
class ExplicitDynamics;
}

namespace mfv::fluid {

/// The VTK arrays of a fluid frame besides velocity and stress: pressure, density and the
/// neighbour count (trial-table entries) of each particle's integration point.
void frame_fields(const ExplicitDynamics& sim,
                  std::vector<std::pair<std::string, Eigen::MatrixXd>>& out);

}  // namespace mfv::fluid
