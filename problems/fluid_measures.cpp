#include "problems/fluid_measures.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mfv::fluid {

Eigen::VectorXd pressure_of(const Eigen::MatrixXd& cauchy) {
  Eigen::VectorXd p(cauchy.cols());
  for (Eigen::Index I = 0; I < cauchy.cols(); ++I) p[I] = -0.5 * (cauchy(0, I) + cauchy(3, I));
  return p;
}

double hydrostatic_pressure_error(const Eigen::MatrixXd& x, const Eigen::VectorXd& p, double rho0,
                                  double g, double surface) {
  double num = 0, den = 0;
  for (Eigen::Index I = 0; I < x.cols(); ++I) {
    const double exact = rho0 * g * std::max(surface - x(1, I), 0.0);
    num += (p[I] - exact) * (p[I] - exact);
    den += exact * exact;
  }
  return den > 0 ? std::sqrt(num / den) : std::numeric_limits<double>::quiet_NaN();
}

double surge_front(const Eigen::MatrixXd& x, double spacing, double band) {
  if (band <= 0) band = spacing;
  double front = -std::numeric_limits<double>::infinity();
  for (Eigen::Index I = 0; I < x.cols(); ++I)
    if (x(1, I) < band) front = std::max(front, x(0, I));
  return std::isfinite(front) ? front + 0.5 * spacing : std::numeric_limits<double>::quiet_NaN();
}

double column_height(const Eigen::MatrixXd& x, double spacing, double band) {
  if (band <= 0) band = spacing;
  double top = -std::numeric_limits<double>::infinity();
  for (Eigen::Index I = 0; I < x.cols(); ++I)
    if (x(0, I) < band) top = std::max(top, x(1, I));
  return std::isfinite(top) ? top + 0.5 * spacing : std::numeric_limits<double>::quiet_NaN();
}

ExperimentSeries martin_moyce_front() {
  // Table 2 (n² = 2, a = 2.25 in): T = t √(2g/a), Z/a.
  return {"Z/a",
          {0.41, 0.84, 1.19, 1.43, 1.63, 1.83, 1.98, 2.20, 2.32, 2.51, 2.65, 2.83, 2.98, 3.11,
           3.33},
          {1.11, 1.22, 1.44, 1.67, 1.89, 2.11, 2.33, 2.56, 2.78, 3.00, 3.22, 3.44, 3.67, 3.89,
           4.11}};
}

ExperimentSeries martin_moyce_height() {
  // Table 6 (n² = 2, a = 2.25 in): τ = t √(g/a) and η = H/(n² a), converted to T = √2 τ and
  // H/a = 2 η; the table runs on to τ = 7.40, we keep the points within the front's range
  // (T ≤ 3.33, τ ≤ 2.36).
  const std::vector<double> tau = {0.56, 0.77, 0.93, 1.08, 1.28, 1.46, 1.66, 1.84, 2.00, 2.21};
  const std::vector<double> eta = {0.94, 0.89, 0.83, 0.78, 0.72, 0.67, 0.61, 0.56, 0.50, 0.44};
  ExperimentSeries s{"H/a", {}, {}};
  for (std::size_t k = 0; k < tau.size(); ++k) {
    s.T.push_back(std::sqrt(2.0) * tau[k]);
    s.value.push_back(2 * eta[k]);
  }
  return s;
}

std::string martin_moyce_citation() {
  return "J. C. Martin & W. J. Moyce (1952), An experimental study of the collapse of liquid "
         "columns on a rigid horizontal plane, Phil. Trans. R. Soc. Lond. A 244(882), 312–324 "
         "(Part IV of Martin & Moyce's series): Table 2 (surge front Z/a against T = n t √(g/a)) and "
         "Table 6 (column height H/(n² a) against τ = t √(g/a)), n² = 2, a = 2.25 in; as "
         "tabulated in Ocellaris (github.com/TormodLandet/Ocellaris, scripts/plot_dam_break.py, "
         "commit 44fd559f4e3634e46256051580fb4de72eeb8d39, mmTvec/mmZvec and mmYvec/mmHvec; not "
         "read from the paper itself; Lethe's transcription, github.com/chaos-polymtl/lethe, "
         "examples/multiphysics/dam-break/dam-break-2d.py, differs by at most 0.02 in T). "
         "PySPH's digitization of the paper's Fig. 3 for the same column (github.com/pypr/pysph, "
         "pysph/examples/db_exp_data.py, commit 483e4449f50719350fc2857e8163ea3aae637cc7, "
         "mm_data_2) agrees with it within 0.06 in Z/a over T ≤ 3.35";
}

double interpolate(const std::vector<double>& t, const std::vector<double>& v, double T) {
  // A time within round-off of the history's ends counts as reached (the last step lands on
  // the end time up to the step's rounding).
  const double slack = 1e-6 * (t.empty() ? 0.0 : std::abs(t.back()) + std::abs(t.front()));
  if (t.empty() || !(T >= t.front() - slack) || !(T <= t.back() + slack))
    return std::numeric_limits<double>::quiet_NaN();
  if (T <= t.front()) return v.front();
  const auto it = std::upper_bound(t.begin(), t.end(), T);
  if (it == t.end()) return v.back();
  const std::size_t k = it - t.begin();
  if (k == 0) return v.front();
  const double s = (T - t[k - 1]) / (t[k] - t[k - 1]);
  return v[k - 1] + s * (v[k] - v[k - 1]);
}

SeriesError series_error(const std::vector<double>& t, const std::vector<double>& v,
                         const ExperimentSeries& e, double shift) {
  SeriesError r;
  double sum = 0, worst = 0;
  for (std::size_t k = 0; k < e.T.size(); ++k) {
    const double ours = interpolate(t, v, e.T[k] - shift);
    if (!std::isfinite(ours)) continue;
    const double d = std::abs(ours - e.value[k]);
    sum += d * d;
    worst = std::max(worst, d);
    ++r.points;
  }
  if (r.points > 0) {
    r.rms = std::sqrt(sum / r.points);
    r.max = worst;
  }
  return r;
}

double best_shift(const std::vector<double>& t, const std::vector<double>& v,
                  const ExperimentSeries& e, double max_shift, int steps) {
  double best = std::numeric_limits<double>::quiet_NaN(), best_rms = INFINITY;
  const int full = series_error(t, v, e).points;
  for (int k = 0; k <= steps; ++k) {
    const double s = max_shift * k / steps;
    const SeriesError err = series_error(t, v, e, s);
    // Only shifts that keep every compared point: dropping points would flatter the fit.
    if (err.points < full || !(err.rms < best_rms)) continue;
    best_rms = err.rms;
    best = s;
  }
  return best;
}

}  // namespace mfv::fluid

#include "dynamics/explicit.hpp"

namespace mfv::fluid {

void frame_fields(const ExplicitDynamics& sim,
                  std::vector<std::pair<std::string, Eigen::MatrixXd>>& out) {
  const std::vector<int>& near = sim.particle_points();
  const int n = static_cast<int>(near.size());
  const Eigen::VectorXd p = pressure_of(sim.particle_cauchy_stress());
  const Eigen::VectorXd rho = sim.point_state("density");
  const Eigen::VectorXi nb = sim.point_neighbours();
  Eigen::MatrixXd pm(1, n), rm(1, n), nm(1, n);
  for (int I = 0; I < n; ++I) {
    pm(0, I) = p[I];
    rm(0, I) = rho.size() ? rho[near[I]] : std::numeric_limits<double>::quiet_NaN();
    nm(0, I) = nb.size() ? nb[near[I]] : 0;
  }
  out.emplace_back("pressure (Pa)", std::move(pm));
  out.emplace_back("density (kg/m3)", std::move(rm));
  out.emplace_back("neighbours", std::move(nm));
}

}  // namespace mfv::fluid
