/// One judgement of a refinement study — converges, stagnates, diverges or erratic — from the
/// pairwise rates and the finest error, not from the least-squares slope alone: a slope of
/// 1.9 can hide an error that fell 200× and then rose 40× at the finest resolution.
///
/// With errors e_i at spacings h_i (coarsest first), the pairwise rates are
/// r_i = ln(e_i / e_{i-1}) / ln(h_i / h_{i-1}) and the fitted rate the least-squares slope of
/// ln e against ln h (004 II eq 7.3). The criteria, in order, with r_min = kConvergesMinRate:
///   converges  the finest error is the smallest, the last pairwise rate ≥ r_min and the
///              fitted rate ≥ r_min;
///   diverges   the finest error is above the coarsest and either the largest or still
///              rising (last pairwise rate below 0);
///   stagnates  |last pairwise rate| < r_min and the finest error within kStagnationBand of the
///              smallest (it has levelled off);
///   erratic    anything else (rates that change sign, a finest error far above the smallest).
#pragma once
#include <string>
#include <vector>

namespace mfv {

/// A pairwise or fitted rate below this is no convergence.
inline constexpr double kConvergesMinRate = 0.5;
/// A stagnating study's finest error lies within this factor of its smallest.
inline constexpr double kStagnationBand = 2.0;

enum class Trend { converges, stagnates, diverges, erratic, undetermined };

/// "converges", "stagnates", "diverges", "erratic", "undetermined".
const char* trend_name(Trend t);

struct ConvergenceJudgement {
  Trend trend = Trend::undetermined;
  double fitted_rate = 0;            ///< least-squares slope (NaN when undetermined)
  std::vector<double> pairwise;      ///< r_i, one per successive pair
  /// Why, with the numbers: "pairwise rates 6.50, 9.20, -9.30; finest error 43× the smallest
  /// (at h = 1.5)". Undetermined: which input is missing ("fewer than two resolutions",
  /// "error at h = 0.5 is nan").
  std::string reason;
  bool converges() const { return trend == Trend::converges; }
  /// "converges (rate 2.01)", "erratic (…reason…)": the label a report prints.
  std::string label() const;
};

/// Least-squares slope of ln e against ln h (004 II eq 7.3, GSL gsl_fit_linear); NaN with
/// fewer than two usable (positive, finite) points.
double fitted_rate(const std::vector<double>& h, const std::vector<double>& e);
/// Slopes between successive pairs.
std::vector<double> pairwise_rates(const std::vector<double>& h, const std::vector<double>& e);

/// Judges the errors `e` at spacings `h` (same length, coarsest first, h > 0). A non-finite
/// or non-positive error, a non-positive h, fewer than two resolutions or lengths that differ
/// give Trend::undetermined with the reason — never "converges".
ConvergenceJudgement judge_convergence(const std::vector<double>& e, const std::vector<double>& h);

}  // namespace mfv
