#include "problems/plate_measures.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace mfv {

namespace {

/// η²(φ) of the clipped weights w about their mean m (total sum of squares `total`).
double correlation_ratio(const Eigen::MatrixXd& x, const Eigen::Vector2d& centre,
                         const Eigen::VectorXd& w, double m, double total, int bins,
                         double phi, std::vector<double>& n, std::vector<double>& sum) {
  const double c = std::cos(phi), s = std::sin(phi);
  const Eigen::Index np = x.cols();
  double lo = INFINITY, hi = -INFINITY;
  for (Eigen::Index i = 0; i < np; ++i) {
    const double p = c * (x(0, i) - centre[0]) - s * (x(1, i) - centre[1]);
    lo = std::min(lo, p);
    hi = std::max(hi, p);
  }
  std::fill(n.begin(), n.end(), 0.0);
  std::fill(sum.begin(), sum.end(), 0.0);
  const double width = (hi - lo) / bins;
  for (Eigen::Index i = 0; i < np; ++i) {
    const double p = c * (x(0, i) - centre[0]) - s * (x(1, i) - centre[1]);
    const int b = width > 0 ? std::clamp(static_cast<int>((p - lo) / width), 0, bins - 1) : 0;
    n[b] += 1;
    sum[b] += w[i];
  }
  double between = 0;
  for (int b = 0; b < bins; ++b)
    if (n[b] > 0) between += n[b] * std::pow(sum[b] / n[b] - m, 2);
  return between / total;
}

}  // namespace

PlateBandFit fit_band_angles(const Eigen::MatrixXd& x, const Eigen::VectorXd& weight, int bins,
                             double floor, double step_deg) {
  PlateBandFit fit;
  fit.angle_plus = fit.angle_minus = fit.angle = NAN;
  const Eigen::Index np = x.cols();
  if (np < 3 || weight.size() != np || bins < 2 || !(step_deg > 0) || !weight.allFinite())
    return fit;
  const double top = weight.maxCoeff();
  Eigen::VectorXd w = (weight.array() - floor * top).max(0.0).matrix();
  const double m = w.mean();
  const double total = (w.array() - m).square().sum();
  if (!(top > 0) || !(total > 0)) return fit;
  const Eigen::Vector2d centre = x.rowwise().mean();
  std::vector<double> n(bins), sum(bins);
  constexpr double kDeg = std::numbers::pi / 180;
  const int steps = static_cast<int>(std::round(90 / step_deg));
  for (int sign : {1, -1}) {
    double best = -1, best_angle = NAN;
    for (int k = 1; k <= steps; ++k) {
      const double deg = k * step_deg;
      const double eta = correlation_ratio(x, centre, w, m, total, bins, sign * deg * kDeg, n, sum);
      if (eta > best) {
        best = eta;
        best_angle = deg;
      }
    }
    (sign > 0 ? fit.angle_plus : fit.angle_minus) = best_angle;
    (sign > 0 ? fit.strength_plus : fit.strength_minus) = best;
  }
  const bool plus_stronger = fit.strength_plus >= fit.strength_minus;
  fit.angle = plus_stronger ? fit.angle_plus : fit.angle_minus;
  const double strongest = std::max(fit.strength_plus, fit.strength_minus);
  fit.families = (fit.strength_plus >= 0.5 * strongest) + (fit.strength_minus >= 0.5 * strongest);
  return fit;
}

std::vector<double> moving_average(const std::vector<double>& y, int window) {
  const int n = static_cast<int>(y.size());
  const int half = std::max(0, window / 2);
  std::vector<double> prefix(n + 1, 0.0), out(n);
  for (int i = 0; i < n; ++i) prefix[i + 1] = prefix[i] + y[i];
  for (int i = 0; i < n; ++i) {
    const int h = std::min({half, i, n - 1 - i});
    out[i] = (prefix[i + h + 1] - prefix[i - h]) / (2 * h + 1);
  }
  return out;
}

OscillationFit oscillation_growth(const std::vector<double>& t, const std::vector<double>& y,
                                  int window, double floor) {
  OscillationFit fit;
  fit.growth_rate = fit.growth_factor = fit.amplitude_ratio = fit.relative_amplitude = NAN;
  const int n = static_cast<int>(std::min(t.size(), y.size()));
  if (n < 8 || window < 3) return fit;
  const std::vector<double> trend = moving_average(y, window);
  const int from = window / 2, to = n - window / 2;  // [from, to): the trend is unbiased
  if (to - from < 4) return fit;
  std::vector<double> r(n);
  double rr = 0, tt = 0;
  for (int i = from; i < to; ++i) {
    r[i] = y[i] - trend[i];
    rr += r[i] * r[i];
    tt += trend[i] * trend[i];
  }
  fit.relative_amplitude = tt > 0 ? std::sqrt(rr / tt) : NAN;
  // Half-periods: runs of one sign of r; only runs closed by a sign change on both sides.
  int start = -1;
  for (int i = from + 1; i < to; ++i) {
    const bool change = (r[i] > 0) != (r[i - 1] > 0);
    if (!change) continue;
    if (start >= 0) {
      int peak = start;
      for (int j = start; j < i; ++j)
        if (std::abs(r[j]) > std::abs(r[peak])) peak = j;
      if (std::abs(r[peak]) > floor && std::abs(r[peak]) > 0) {
        fit.peak_t.push_back(t[peak]);
        fit.peak_a.push_back(std::abs(r[peak]));
      }
    }
    start = i;
  }
  const int k = static_cast<int>(fit.peak_t.size());
  fit.half_periods = k;
  if (k < 4) return fit;
  double st = 0, sl = 0, stt = 0, stl = 0;
  for (int i = 0; i < k; ++i) {
    const double l = std::log(fit.peak_a[i]);
    st += fit.peak_t[i];
    sl += l;
    stt += fit.peak_t[i] * fit.peak_t[i];
    stl += fit.peak_t[i] * l;
  }
  const double den = k * stt - st * st;
  if (!(den > 0)) return fit;
  fit.growth_rate = (k * stl - st * sl) / den;
  fit.growth_factor = std::exp(fit.growth_rate * (fit.peak_t.back() - fit.peak_t.front()));
  fit.amplitude_ratio =
      (fit.peak_a[k - 1] + fit.peak_a[k - 2]) / (fit.peak_a[0] + fit.peak_a[1]);
  return fit;
}

}  // namespace mfv
