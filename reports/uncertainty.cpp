#include "reports/uncertainty.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>

namespace mfv {

const char* convergence_class_name(ConvergenceClass c) {
  switch (c) {
    case ConvergenceClass::monotone: return "monotone";
    case ConvergenceClass::oscillatory: return "oscillatory";
    case ConvergenceClass::monotone_divergent: return "divergent";
    case ConvergenceClass::oscillatory_divergent: return "oscillatory divergent";
    case ConvergenceClass::exact: return "exact";
    case ConvergenceClass::two_levels: return "two levels";
    case ConvergenceClass::undetermined: return "undetermined";
  }
  return "undetermined";
}

std::string Uncertainty::text() const {
  if (!known()) return fmt::format("± – ({})", why_none.empty() ? "not estimated" : why_none);
  const double a = std::abs(absolute);
  const std::string u = a != 0 && (a < 1e-2 || a >= 1e4) ? fmt::format("{:.2g}", absolute)
                                                          : fmt::format("{:.3g}", absolute);
  if (!std::isfinite(order))
    return fmt::format("± {} ({})", u, method.empty() ? convergence_class_name(cls) : method);
  return fmt::format("± {} (p = {:.2f}{}, {})", u, order, assumed_order ? " assumed" : "",
                     convergence_class_name(cls));
}

namespace {

/// Eça–Hoekstra: φ_i = φ0 + α h_i^p by least squares, p by golden-section search on [0.05, 10]
/// (φ0 and α linear for each p); NaN when the fit is degenerate.
double least_squares_order(const std::vector<double>& h, const std::vector<double>& f) {
  const std::size_t n = h.size();
  auto residual = [&](double p) -> double {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double x = std::pow(h[i], p);
      sx += x;
      sy += f[i];
      sxx += x * x;
      sxy += x * f[i];
    }
    const double det = n * sxx - sx * sx;
    if (!(std::abs(det) > 0)) return INFINITY;
    const double alpha = (n * sxy - sx * sy) / det, phi0 = (sy - alpha * sx) / n;
    double r = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double e = f[i] - phi0 - alpha * std::pow(h[i], p);
      r += e * e;
    }
    return r;
  };
  double a = 0.05, b = 10;
  const double g = (std::sqrt(5.0) - 1) / 2;
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = residual(c), fd = residual(d);
  for (int it = 0; it < 100; ++it) {
    if (fc < fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - g * (b - a);
      fc = residual(c);
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + g * (b - a);
      fd = residual(d);
    }
  }
  const double p = 0.5 * (a + b);
  return std::isfinite(residual(p)) && p > 0.06 && p < 9.9 ? p : NAN;
}

}  // namespace

Uncertainty grid_uncertainty(std::vector<double> h, std::vector<double> f, double assumed_order) {
  Uncertainty u;
  // Finite pairs, finest first.
  std::vector<std::pair<double, double>> pts;
  for (std::size_t i = 0; i < std::min(h.size(), f.size()); ++i)
    if (std::isfinite(h[i]) && h[i] > 0 && std::isfinite(f[i])) pts.emplace_back(h[i], f[i]);
  std::sort(pts.begin(), pts.end());
  pts.erase(std::unique(pts.begin(), pts.end(),
                        [](const auto& a, const auto& b) { return a.first == b.first; }),
            pts.end());
  u.levels = static_cast<int>(pts.size());
  if (pts.size() < 2) {
    u.why_none = "fewer than two resolutions";
    return u;
  }
  const double h1 = pts[0].first, f1 = pts[0].second, h2 = pts[1].first, f2 = pts[1].second;
  u.value = f1;
  const double e21 = f2 - f1;
  const double scale = std::max({std::abs(f1), std::abs(f2), 1e-300});
  if (std::abs(e21) <= 1e-13 * scale) {
    u.cls = ConvergenceClass::exact;
    u.method = "unchanged at the finer level";
    u.order = NAN;
    u.extrapolated = f1;
    u.gci = 0;
    u.absolute = 0;
    return u;
  }
  const double r21 = h2 / h1;
  if (pts.size() == 2) {
    u.cls = ConvergenceClass::two_levels;
    if (!(assumed_order > 0)) {
      u.why_none = "two resolutions and no formal order to assume";
      return u;
    }
    const double rp = std::pow(r21, assumed_order);
    u.order = assumed_order;
    u.assumed_order = true;
    u.method = "GCI, 2 levels, F_s = 3";
    u.extrapolated = (rp * f1 - f2) / (rp - 1);
    u.gci = 3.0 * std::abs(e21 / (f1 != 0 ? f1 : scale)) / (rp - 1);
    u.absolute = u.gci * std::abs(f1 != 0 ? f1 : scale);
    return u;
  }
  const double h3 = pts[2].first, f3 = pts[2].second;
  const double e32 = f3 - f2, r32 = h3 / h2;
  const double R = e21 / e32;
  u.cls = !std::isfinite(R)   ? ConvergenceClass::monotone_divergent
          : R >= 1            ? ConvergenceClass::monotone_divergent
          : R <= -1           ? ConvergenceClass::oscillatory_divergent
          : R > 0             ? ConvergenceClass::monotone
                              : ConvergenceClass::oscillatory;
  if (pts.size() > 3) {
    std::vector<double> hs, fs;
    for (const auto& [x, y] : pts) {
      hs.push_back(x);
      fs.push_back(y);
    }
    u.order_least_squares = least_squares_order(hs, fs);
  }
  if (u.cls == ConvergenceClass::monotone_divergent ||
      u.cls == ConvergenceClass::oscillatory_divergent) {
    u.why_none = fmt::format("the changes grow under refinement ({}, ε21/ε32 = {:.3g})",
                             convergence_class_name(u.cls), R);
    return u;
  }
  // Celik et al. 2008, eqs 3-4: fixed point in p.
  const double s = e32 / e21 > 0 ? 1.0 : -1.0;
  double p = std::abs(std::log(std::abs(e32 / e21))) / std::log(r21);
  for (int it = 0; it < 100; ++it) {
    const double q = std::log((std::pow(r21, p) - s) / (std::pow(r32, p) - s));
    const double next = std::abs(std::log(std::abs(e32 / e21)) + q) / std::log(r21);
    if (!std::isfinite(next)) break;
    if (std::abs(next - p) < 1e-10) {
      p = next;
      break;
    }
    p = next;
  }
  u.order = p;
  u.method = "GCI, 3 levels (Celik et al. 2008)";
  if (!(p > 0) || !std::isfinite(p)) {
    u.why_none = "no positive observed order";
    return u;
  }
  const double rp = std::pow(r21, p);
  u.extrapolated = (rp * f1 - f2) / (rp - 1);
  const double base = f1 != 0 ? std::abs(f1) : scale;
  u.gci = 1.25 * std::abs(e21) / base / (rp - 1);
  u.absolute = u.gci * base;
  const double gci32 = 1.25 * std::abs(e32) / std::max(std::abs(f2), 1e-300) /
                       (std::pow(r32, p) - 1);
  u.asymptotic = gci32 / (rp * u.gci);
  return u;
}

bool within_uncertainty(double ours, const Uncertainty& u, double paper, double tolerance,
                        bool relative) {
  if (!u.known() || !std::isfinite(ours) || !std::isfinite(paper)) return false;
  const double band = u.absolute + (relative ? tolerance * std::abs(paper) : tolerance);
  return std::abs(paper - ours) <= band;
}

}  // namespace mfv
