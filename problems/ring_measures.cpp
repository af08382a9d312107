#include "problems/ring_measures.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "methods/core/errors.hpp"

namespace mfv {

namespace {

void check_rows(long size, int rows, int per_row, const char* what) {
  if (rows < 1 || per_row < 3 || size != static_cast<long>(rows) * per_row)
    throw InputError(fmt::format("{} needs rows ≥ 1 of per_row ≥ 3 values ({} × {}), got {}",
                                 what, rows, per_row, size));
}

}  // namespace

RowIndex symmetry_index(const Eigen::VectorXd& values, int rows, int per_row, double floor) {
  check_rows(values.size(), rows, per_row, "the symmetry index");
  const double rms_all = std::sqrt(values.squaredNorm() / static_cast<double>(values.size()));
  RowIndex out;
  out.per_row.resize(rows);
  for (int i = 0; i < rows; ++i) {
    const Eigen::VectorXd row = values.segment(static_cast<Eigen::Index>(i) * per_row, per_row);
    const double mean = row.mean();
    const double var = (row.array() - mean).square().mean();
    const double rms = std::sqrt(row.squaredNorm() / per_row);
    const double scale = std::max(rms, floor * rms_all);
    out.per_row[i] = scale > 0 ? std::sqrt(var) / scale : 0.0;
    if (!std::isfinite(out.per_row[i])) out.per_row[i] = NAN;
    if (out.row < 0 || !(out.per_row[i] <= out.worst)) {
      out.worst = out.per_row[i];
      out.row = i;
    }
  }
  return out;
}

RowIndex clustering_index(const Eigen::MatrixXd& x, int rows, int per_row) {
  check_rows(x.cols(), rows, per_row, "the clustering index");
  RowIndex out;
  out.per_row.resize(rows);
  for (int i = 0; i < rows; ++i) {
    double lo = INFINITY, hi = 0;
    for (int j = 0; j < per_row; ++j) {
      const int a = j + per_row * i, b = (j + 1) % per_row + per_row * i;
      const double g = (x.col(b) - x.col(a)).norm();
      lo = std::min(lo, g);
      hi = std::max(hi, g);
    }
    out.per_row[i] = lo > 0 ? hi / lo : INFINITY;
    if (!std::isfinite(hi)) out.per_row[i] = NAN;
    if (out.row < 0 || !(out.per_row[i] <= out.worst)) {
      out.worst = out.per_row[i];
      out.row = i;
    }
  }
  return out;
}

double hoop_stress(const Eigen::Vector2d& x, const double* s) {
  const double th = std::atan2(x.y(), x.x()), c = std::cos(th), n = std::sin(th);
  // t = (−sin, cos); σ column-major: s[0] = σxx, s[1] = σyx, s[2] = σxy, s[3] = σyy.
  return n * n * s[0] - n * c * (s[1] + s[2]) + c * c * s[3];
}

double radial_stress(const Eigen::Vector2d& x, const double* s) {
  const double th = std::atan2(x.y(), x.x()), c = std::cos(th), n = std::sin(th);
  return c * c * s[0] + n * c * (s[1] + s[2]) + n * n * s[3];
}

BandFit fit_log_spiral_bands(const Eigen::VectorXd& zeta, const Eigen::VectorXd& theta,
                             const Eigen::VectorXd& weight, int radial_bins, int theta_bins,
                             double max_slope, double slope_step) {
  const long n = zeta.size();
  if (theta.size() != n || weight.size() != n || n == 0)
    throw InputError(fmt::format("the band fit needs as many ζ, θ and weights (got {}, {}, {})",
                                 n, theta.size(), weight.size()));
  if (radial_bins < 1 || theta_bins < 4 || !(max_slope > 0) || !(slope_step > 0) ||
      max_slope / slope_step > 1e5)
    throw InputError(fmt::format("band fit: radial_bins {} ≥ 1, theta_bins {} ≥ 4, slopes "
                                 "(0, {}] in steps {} (at most 1e5 of them)",
                                 radial_bins, theta_bins, max_slope, slope_step));
  constexpr double two_pi = 2 * std::numbers::pi;
  BandFit fit;
  // Detrend by the mean of each radial bin: bands are what stands out of their row.
  const double zmax = std::max(zeta.maxCoeff(), 1e-300);
  std::vector<int> bin(n);
  std::vector<double> sum(radial_bins, 0.0), count(radial_bins, 0.0);
  for (long k = 0; k < n; ++k) {
    bin[k] = std::clamp(static_cast<int>(zeta[k] / zmax * radial_bins), 0, radial_bins - 1);
    sum[bin[k]] += weight[k];
    count[bin[k]] += 1;
  }
  Eigen::VectorXd w(n);
  for (long k = 0; k < n; ++k) w[k] = weight[k] - sum[bin[k]] / count[bin[k]];
  const double mean_all = weight.mean();
  fit.contrast = mean_all > 0 ? std::sqrt(w.squaredNorm() / n) / mean_all : 0.0;

  auto bin_of = [&](long k, double s) {
    double phi = std::fmod(theta[k] - s * zeta[k], two_pi);
    if (phi < 0) phi += two_pi;
    return std::min(theta_bins - 1, static_cast<int>(phi / two_pi * theta_bins));
  };
  auto profile = [&](double s, const Eigen::VectorXd& v) {
    std::vector<double> p(theta_bins, 0.0), c(theta_bins, 0.0);
    for (long k = 0; k < n; ++k) {
      const int b = bin_of(k, s);
      p[b] += v[k];
      c[b] += 1;
    }
    // An empty bin has no value (NaN), not zero: zeros would add variance that depends on
    // how the lattice's columns fall into the bins at each slope.
    for (int b = 0; b < theta_bins; ++b) p[b] = c[b] > 0 ? p[b] / c[b] : NAN;
    return p;
  };
  auto variance = [](const std::vector<double>& p) {
    double m = 0, v = 0, k = 0;
    for (double x : p)
      if (!std::isnan(x)) {
        m += x;
        ++k;
      }
    if (k == 0) return 0.0;
    m /= k;
    for (double x : p)
      if (!std::isnan(x)) v += (x - m) * (x - m);
    return v / k;
  };
  // The field a family's profile explains, spread back along its lines.
  auto back_project = [&](const std::vector<double>& p, double s) {
    Eigen::VectorXd v(n);
    for (long k = 0; k < n; ++k) v[k] = p[bin_of(k, s)];  // a point's own bin is not empty
    return v;
  };
  const int steps = static_cast<int>(std::floor(max_slope / slope_step + 1e-9));
  // C(±k·step) of the residual r for one sign; the best k ≥ 1.
  auto scan = [&](const Eigen::VectorXd& r, double sign, std::vector<double>& C) {
    C.assign(steps + 1, 0.0);
    int best = 1;
    for (int k = 0; k <= steps; ++k) {
      C[k] = variance(profile(sign * k * slope_step, r));
      if (k >= 1 && C[k] > C[best]) best = k;
    }
    return best;
  };
  // Crossing families bias each other's projections, so they are fitted in turn, each on
  // the field left after removing the other (three rounds settle to the slope step).
  std::vector<double> Cp, Cm;
  int kp = scan(w, 1.0, Cp), km = scan(w, -1.0, Cm);
  const bool plus_first = Cp[kp] >= Cm[km];
  Eigen::VectorXd other = Eigen::VectorXd::Zero(n);
  for (int round = 0; round < 3; ++round) {
    for (int f = 0; f < 2; ++f) {
      const bool plus = (f == 0) == plus_first;
      const double sign = plus ? 1.0 : -1.0;
      int& k = plus ? kp : km;
      std::vector<double>& C = plus ? Cp : Cm;
      k = scan(w - other, sign, C);
      other = back_project(profile(sign * k * slope_step, w - other), sign * k * slope_step);
    }
  }
  const double top = std::max(Cp[kp], Cm[km]);
  auto family = [&](const std::vector<double>& C, int k, double sign, double& slope,
                    double& prominence, bool& present) {
    slope = sign * k * slope_step;
    const double low = *std::min_element(C.begin(), C.begin() + k + 1);
    prominence = C[k] > 0 ? (C[k] - low) / C[k] : 0.0;
    present = k > 1 && k < steps && prominence >= 0.1 && C[k] >= 0.25 * top;
  };
  fit.strength_plus = top > 0 ? Cp[kp] / top : 0.0;
  fit.strength_minus = top > 0 ? Cm[km] / top : 0.0;
  family(Cp, kp, 1.0, fit.slope_plus, fit.prominence_plus, fit.plus_present);
  family(Cm, km, -1.0, fit.slope_minus, fit.prominence_minus, fit.minus_present);
  fit.angle_plus = std::atan(std::abs(fit.slope_plus)) * 180 / std::numbers::pi;
  fit.angle_minus = std::atan(std::abs(fit.slope_minus)) * 180 / std::numbers::pi;
  // Bands of the stronger family: cyclic local maxima of its profile above half the largest.
  const double strong = Cp[kp] >= Cm[km] ? fit.slope_plus : fit.slope_minus;
  std::vector<double> p;
  std::vector<int> at;  // the non-empty bins
  {
    const std::vector<double> all = profile(strong, w);
    for (int b = 0; b < theta_bins; ++b)
      if (!std::isnan(all[b])) {
        p.push_back(all[b]);
        at.push_back(b);
      }
  }
  const int m = static_cast<int>(p.size());
  const double peak = m > 0 ? *std::max_element(p.begin(), p.end()) : 0.0;
  if (peak > 0)
    for (int i = 0; i < m; ++i) {
      const double l = p[(i + m - 1) % m], r = p[(i + 1) % m];
      if (p[i] >= 0.5 * peak && p[i] > l && p[i] >= r) {
        ++fit.bands;
        fit.positions.push_back((at[i] + 0.5) * 360.0 / theta_bins);
      }
    }
  return fit;
}

}  // namespace mfv
