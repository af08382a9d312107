#include "reports/convergence.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <gsl/gsl_fit.h>


namespace mfv {

double fitted_rate(const std::vector<double>& h, const std::vector<double>& e) {
  std::vector<double> lx, ly;
  for (std::size_t i = 0; i < h.size() && i < e.size(); ++i)
    if (h[i] > 0 && e[i] > 0 && std::isfinite(e[i])) {
      lx.push_back(std::log(h[i]));
      ly.push_back(std::log(e[i]));
    }
  if (lx.size() < 2) return NAN;
  double c0, c1, cov00, cov01, cov11, sumsq;
  gsl_fit_linear(lx.data(), 1, ly.data(), 1, lx.size(), &c0, &c1, &cov00, &cov01, &cov11, &sumsq);
  return c1;
}

std::vector<double> pairwise_rates(const std::vector<double>& h, const std::vector<double>& e) {
  std::vector<double> out;
  for (std::size_t i = 1; i < h.size() && i < e.size(); ++i)
    out.push_back(std::log(e[i] / e[i - 1]) / std::log(h[i] / h[i - 1]));
  return out;
}


namespace {

std::string rates_text(const std::vector<double>& r) {
  std::string s;
  // + 0.0 turns a −0 (a flat pair: ln 1 / ln(h ratio)) into 0.
  for (double x : r) s += fmt::format("{}{:.2f}", s.empty() ? "" : ", ", x + 0.0);
  return s;
}

}  // namespace

const char* trend_name(Trend t) {
  switch (t) {
    case Trend::converges: return "converges";
    case Trend::stagnates: return "stagnates";
    case Trend::diverges: return "diverges";
    case Trend::erratic: return "erratic";
    case Trend::undetermined: break;
  }
  return "undetermined";
}

std::string ConvergenceJudgement::label() const {
  if (trend == Trend::converges) return fmt::format("converges (rate {:.2f})", fitted_rate);
  return fmt::format("{} ({})", trend_name(trend), reason);
}

ConvergenceJudgement judge_convergence(const std::vector<double>& e, const std::vector<double>& h) {
  ConvergenceJudgement j;
  j.fitted_rate = NAN;
  if (e.size() != h.size()) {
    j.reason = fmt::format("{} errors for {} spacings", e.size(), h.size());
    return j;
  }
  if (e.size() < 2) {
    j.reason = "fewer than two resolutions";
    return j;
  }
  for (std::size_t i = 0; i < e.size(); ++i) {
    if (!(h[i] > 0) || !std::isfinite(h[i])) {
      j.reason = fmt::format("spacing h = {} is not positive and finite", h[i]);
      return j;
    }
    if (!(e[i] > 0) || !std::isfinite(e[i])) {
      j.reason = fmt::format("error at h = {:.3g} is {}", h[i], e[i]);
      return j;
    }
    if (i > 0 && !(h[i] < h[i - 1])) {
      j.reason = fmt::format("spacings do not decrease ({:.3g} after {:.3g})", h[i], h[i - 1]);
      return j;
    }
  }
  j.pairwise = pairwise_rates(h, e);
  j.fitted_rate = fitted_rate(h, e);
  const double finest = e.back(), coarsest = e.front();
  const auto min_at = std::min_element(e.begin(), e.end()) - e.begin();
  const double smallest = e[min_at], largest = *std::max_element(e.begin(), e.end());
  const double last = j.pairwise.back();
  const std::string rates = fmt::format("pairwise rates {}", rates_text(j.pairwise));

  if (finest == smallest && last >= kConvergesMinRate && j.fitted_rate >= kConvergesMinRate) {
    j.trend = Trend::converges;
    j.reason = fmt::format("{}; the finest error is the smallest", rates);
  } else if (finest > coarsest && (finest == largest || last < 0)) {
    j.trend = Trend::diverges;
    j.reason = fmt::format("{}; finest error {:.3g}× the coarsest", rates, finest / coarsest);
  } else if (std::abs(last) < kConvergesMinRate && finest <= kStagnationBand * smallest) {
    j.trend = Trend::stagnates;
    j.reason = fmt::format("{}; the last below {} in size", rates, kConvergesMinRate);
  } else {
    j.trend = Trend::erratic;
    j.reason = finest > smallest
                   ? fmt::format("{}; finest error {:.3g}× the smallest (at h = {:.3g})", rates,
                                 finest / smallest, h[min_at])
                   : fmt::format("{}; fitted rate {:.2f}", rates, j.fitted_rate);
  }
  return j;
}

}  // namespace mfv
