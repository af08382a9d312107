/// `laplace-tanh`: u'' + 2s² sech²(s(x-3)) tanh(s(x-3)) = 0 on [0, 6], u = tanh(s(x-3)),
/// essential conditions at both ends (004 II §7, eqs 7.1a-d); published: Table 1 peak u'(3),
/// with findings per window reading of the Gaussian RKPM columns (literal eq 7.4, derived).
/// Finding (004 II §7, Fig. 3): SPH Galerkin gets u' wrong at the ends x = 0, 6, where the
/// exact u' = s sech²(3s) is ≈ 0; the corrected kernel (RKPM, eq 6.1) gets it right.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "problems/finding_tally.hpp"
#include "problems/problem.hpp"

namespace mfv {

namespace {

/// 004 II Table 1, Gaussian RKPM columns (j = 0.5 … 3) at 21, 41, 81, 161, 241 nodes.
constexpr int kTableNodes[5] = {21, 41, 81, 161, 241};
constexpr double kTableJ[6] = {0.5, 1.0, 1.5, 2.0, 2.5, 3.0};
constexpr double kTableRkpm[5][6] = {{3.5100, 3.8315, 4.6672, 5.3217, 5.4837, 5.1865},
                                     {6.3599, 6.7798, 7.6968, 8.3095, 8.5252, 8.5419},
                                     {8.7556, 9.0684, 9.6081, 9.8416, 9.8864, 9.9010},
                                     {9.6788, 9.7992, 9.9605, 9.9984, 9.9995, 9.9996},
                                     {9.8580, 9.9155, 9.9861, 9.9998, 9.9999, 9.9999}};
constexpr const char* kPeakName = "peak du/dx at x=3";
/// Table 1 prints five digits of peaks near 10, where FEM is 2 % short at 241 nodes: a 5 %
/// tolerance could not tell the readings apart, 1 % can.
constexpr double kTable1Tolerance = 0.01;
/// A column matches when every row is within this of the table: 0.25% of the exact peak 10,
/// about the coarse-row spread of the wide-window columns under the derived reading.
constexpr double kColumnTolerance = 0.025;

/// The derivative a study's shape functions used: exact (004 II eq 6.2, the default) or
/// diffuse (the DEM derivative, eq 6.6).
std::string derivative_of(const StudySummary& s) {
  if (s.resolved.has("derivative")) return s.resolved.text("derivative");
  return s.params.has("derivative") ? s.params.text("derivative") : "exact";
}

/// Per Table 1 column, the largest |ours − paper| of the Gaussian rkpm studies run with
/// window rule `rule` and derivative `derivative` (Table 1 does not say which; §7: "the two
/// formulas for the derivatives give virtually identical results") over the table's
/// resolutions; verdict from how many columns match.
Finding table1_finding(const std::string& rule, const std::string& derivative,
                       const std::string& id, const std::string& claim) {
  return {"004 II §7, Table 1", claim,
          fmt::format("per column j, max |ours - paper| over the rows we ran <= {} (a column "
                      "needs at least the 21/41/81-node rows), {} derivative",
                      kColumnTolerance, derivative),
          [rule, derivative](const std::vector<StudySummary>& all) -> Verdict {
            int matched = 0, columns = 0;
            std::string text;
            std::vector<FindingNumber> numbers;
            for (int c = 0; c < 6; ++c)
              for (const auto& s : all) {
                if (s.method != "rkpm" || !s.params.has("rule") || s.params.text("rule") != rule ||
                    !s.params.has("j") || s.params.number("j") != kTableJ[c] ||
                    (s.params.has("kernel") && s.params.text("kernel") != "gaussian") ||
                    derivative_of(s) != derivative)
                  continue;
                // The resolutions are the table's rows from 21 nodes on, coarsest first (the
                // full suite adds 481 and 961 after them).
                const int n = static_cast<int>(s.headlines.size());
                const bool full = n == 7 && s.finest_nodes == 961;
                if (!full && (n < 3 || n > 5 || s.finest_nodes != kTableNodes[n - 1])) continue;
                const int rows = full ? 5 : n;
                double worst = 0;
                for (int r = 0; r < rows; ++r) {
                  const auto it = s.headlines[r].find(kPeakName);
                  const double ours = it == s.headlines[r].end() ? NAN : it->second;
                  const double d = std::abs(ours - kTableRkpm[r][c]);
                  worst = std::isfinite(d) ? std::max(worst, d) : INFINITY;
                }
                ++columns;
                numbers.push_back(finding::headline_per_resolution(s, kPeakName));
                matched += worst <= kColumnTolerance;
                text += fmt::format("{}j={}: max |diff| {:.4f}{}", text.empty() ? "" : "; ",
                                    kTableJ[c], worst, worst <= kColumnTolerance ? "" : " (fails)");
                break;
              }
            if (columns == 0)
              return {"not run", fmt::format("no Gaussian rkpm study with rule={}, derivative={}",
                                             rule, derivative)};
            const std::string status = matched == 6 ? "reproduced under a stated reading"
                                       : matched > 0 ? "partly"
                                                     : "not reproduced";
            return {status,
                    fmt::format("{} of {} columns within {}: {}", matched, columns,
                                kColumnTolerance, text),
                    numbers};
          },
          id};
}

constexpr const char* kEndSlopeError = "max |du/dx error| at x=0,6";
/// The FEM column's closed form: linear elements are nodally exact for this 1D problem (the
/// Green's function of −u'' lies in the element space), so their u'(3) is the slope of the
/// exact u between the nodes of the element at x = 3 (right of it when 3 is a node; the left
/// slope is the same, u being odd about 3): tanh(s Δx)/Δx at 21 … 241 nodes. An independent
/// check of the FEM rows (computed from the exact solution, not from the run).
constexpr const char* kFemClosedForm = "peak du/dx at x=3, nodally exact linear FEM (closed form)";

/// max over the ends x_b = 0, 6 of |u_h'(x_b) − u'(x_b)|: the boundary gradient of Fig. 3.
double end_slope_error(const Discretization& d, const Eigen::VectorXd& u, double s) {
  Eigen::MatrixXd x(1, 2);
  x << 0.0, 6.0;
  const Eigen::VectorXd du = d.trial_at(x, 1).interpolate_derivative(u);
  double worst = 0;
  for (int b = 0; b < 2; ++b) {
    const double t = std::tanh(s * (x(0, b) - 3));
    worst = std::max(worst, std::abs(du[b] - s * (1 - t * t)));
  }
  return worst;
}

/// The headlines of `s` at Δx = 0.075 (81 nodes, Fig. 3); null if the study has no such run.
const std::map<std::string, double>* at_fig3_spacing(const StudySummary& s) {
  const std::map<std::string, double>* best = nullptr;
  double gap = INFINITY;
  for (std::size_t i = 0; i < s.h.size() && i < s.headlines.size(); ++i)
    if (std::abs(s.h[i] - 0.075) < gap) gap = std::abs(s.h[i] - 0.075), best = &s.headlines[i];
  return gap < 1e-9 ? best : nullptr;
}

/// 004 II §7, Fig. 3: SPH Galerkin (no correction) gets u' wrong at the boundaries for both
/// windows; RKPM's corrected kernel (eq 6.1) does not. Decided at 81 nodes from the headline
/// kEndSlopeError of the sph-galerkin and rkpm studies.
Finding sph_galerkin_boundary_gradient(double s) {
  const double wrong_at = 0.02 * s, right_at = 1e-3 * s;
  return {"004 II §7, Fig. 3",
          "SPH Galerkin (Gaussian window, 81 nodes) gets u' wrong at the boundaries; the "
          "corrected kernel (RKPM) gets it right",
          fmt::format("at 81 nodes, max |u_h' − u'| at x = 0, 6 (exact u' ≈ 0) is at least {:g} "
                      "(2% of the peak u') for every sph-galerkin study, at least two windows "
                      "(Fig. 3: a = 1.128 Δx and 5.642 Δx), and at most {:g} (0.1%) for at least "
                      "one rkpm study (the suite runs SPH's narrow window a = 1.128 Δx as "
                      "laplace-tanh/rkpm-fig3-narrow); every rkpm study is listed",
                      wrong_at, right_at),
          [=](const std::vector<StudySummary>& all) -> Verdict {
            int sph = 0, wrong = 0, rk = 0, right = 0;
            std::string sph_text, rk_text;
            std::vector<FindingNumber> numbers;
            for (const auto& st : all) {
              if (st.method != "sph-galerkin" && st.method != "rkpm") continue;
              const auto* h = at_fig3_spacing(st);
              if (!h || !h->count(kEndSlopeError)) continue;
              const double e = h->at(kEndSlopeError);
              // Decided at 81 nodes: the number's levels are the study's up to that one.
              {
                FindingNumber n = finding::headline_per_resolution(st, kEndSlopeError);
                const auto at = static_cast<std::size_t>(h - st.headlines.data()) + 1;
                n.h.resize(std::min(at, n.h.size()));
                n.values.resize(n.h.size());
                numbers.push_back(std::move(n));
              }
              std::string& text = st.method == "rkpm" ? rk_text : sph_text;
              text += fmt::format("{}{} {:.3g}", text.empty() ? "" : ", ", st.label, e);
              if (st.method == "rkpm") {
                ++rk;
                right += std::isfinite(e) && e <= right_at;
              } else {
                ++sph;
                wrong += std::isfinite(e) && e >= wrong_at;
                if (h->count("peak du/dx at x=3"))
                  text += fmt::format(" (peak u'(3) {:.4g})", h->at("peak du/dx at x=3"));
              }
            }
            if (sph == 0) return {"not run", "no sph-galerkin study at 81 nodes"};
            if (rk == 0) return {"not run", "no rkpm study at 81 nodes to compare"};
            const std::string text = fmt::format(
                "max |u_h' − u'| at x = 0, 6, 81 nodes: sph-galerkin {}; rkpm ({} of {} at most "
                "{:g}) {}",
                sph_text, right, rk, right_at, rk_text);
            // Fig. 3 shows two windows: one study alone reproduces only part of the claim.
            if (wrong == sph && sph >= 2 && right > 0) return {"reproduced", text, numbers};
            return {wrong > 0 ? "partly" : "not reproduced", text, numbers};
          },
          "sph-galerkin-boundary-gradient"};
}

class LaplaceTanh final : public ScalarProblem {
 public:
  explicit LaplaceTanh(double s) : s_(s) {}

  Domain domain() const override { return Domain::interval(0, 6); }

  void exact(const Eigen::MatrixXd& x, Eigen::VectorXd& u, Eigen::VectorXd& du) const override {
    u.resize(x.cols());
    du.resize(x.cols());
    for (Eigen::Index i = 0; i < x.cols(); ++i) {
      const double t = std::tanh(s_ * (x(0, i) - 3));
      u[i] = t;
      du[i] = s_ * (1 - t * t);
    }
  }

  AssembledSystem assemble(const Discretization& d) const override {
    // -u'' = f with f = 2s² sech² tanh.
    auto f = [s = s_](double x) {
      const double t = std::tanh(s * (x - 3));
      return 2 * s * s * (1 - t * t) * t;
    };
    AssembledSystem sys = assemble_scalar_1d(d, {}, f);
    sys.constraint_points.resize(1, 2);
    sys.constraint_points << 0.0, 6.0;
    sys.constraint_values.resize(2);
    sys.constraint_values << -std::tanh(3 * s_), std::tanh(3 * s_);
    return sys;
  }

  std::vector<int> resolutions(Level level) const override {
    if (level == Level::quick) return {21, 41, 81};
    return {21, 41, 81, 161, 241};  // 004 II §7: Δx = 0.3 ... 0.025
  }

  std::map<std::string, double> headline(const Discretization& d,
                                         const Eigen::VectorXd& u) const override {
    Eigen::MatrixXd x(1, 1);
    x(0, 0) = 3.0;
    const ShapeTable t = d.trial_at(x, 1);
    std::map<std::string, double> out{{kPeak, t.interpolate_derivative(u)[0]},
                                      {kEndSlopeError, end_slope_error(d, u, s_)}};
    if (const double h = d.particles.spacing; h > 0) {
      const double x0 = std::floor(3 / h + 1e-9) * h;
      out[kFemClosedForm] = (std::tanh(s_ * (x0 + h - 3)) - std::tanh(s_ * (x0 - 3))) / h;
    }
    return out;
  }

  std::map<std::string, double> headline_exact() const override {
    return {{kPeak, s_}, {kEndSlopeError, 0.0}};
  }

  std::vector<PublishedValue> published() const override {
    if (s_ != 10) return {};
    // 004 II Table 1 (the last row is printed "Δx = 0.005"; §7 and the node list give 0.025).
    const double fem[5] = {3.3168, 6.0343, 8.4687, 9.5562, 9.7967};
    std::vector<PublishedValue> out;
    for (int r = 0; r < 5; ++r) {
      for (int c = 0; c < 6; ++c) {
        Params p;
        p.set("kernel", "gaussian");
        p.set("j", kTableJ[c]);
        out.push_back({"004 II Table 1", kPeak, "rkpm", p, kTableNodes[r], kTableRkpm[r][c], "",
                       {}, kTable1Tolerance});
      }
      out.push_back({"004 II Table 1", kPeak, "fem", {}, kTableNodes[r], fem[r], "", {},
                     kTable1Tolerance});
    }
    return out;
  }

  std::vector<Finding> findings() const override {
    if (s_ != 10) return {};
    return {table1_finding("derived", "exact", "table1-derived",
                           "Table 1's Gaussian RKPM peaks, window a = 2^j dx/pi (the reading "
                           "derived from 004 II §4 and §6, see the notes), exact derivative "
                           "(eq 6.2)"),
            table1_finding("derived", "diffuse", "table1-derived-dem",
                           "Table 1's Gaussian RKPM peaks, window a = 2^j dx/pi, DEM "
                           "derivative (eq 6.6)"),
            table1_finding("eq7.4", "exact", "table1-literal",
                           "Table 1's Gaussian RKPM peaks, eq 7.4 read literally "
                           "(a = 2^(j+0.5) sigma, dx/(sigma sqrt(pi)) = 1/sqrt(2)), exact "
                           "derivative (eq 6.2)"),
            table1_finding("eq7.4", "diffuse", "table1-literal-dem",
                           "Table 1's Gaussian RKPM peaks, eq 7.4 read literally, DEM "
                           "derivative (eq 6.6)"),
            sph_galerkin_boundary_gradient(s_)};
  }

  std::vector<std::string> published_notes() const override {
    if (s_ != 10) return {};
    return {
        "**On Table 1: the window scale.** Read literally, eqs 6.8b and 7.4 (a = 2^(j+0.5) σ "
        "with Δx/(σ√π) = 1/√2, so a = (2/√π)·2^j Δx = 1.128·2^j Δx; rows `rule=eq7.4`) give "
        "windows so wide that the coarse peaks *fall* as j grows, the opposite of the table, "
        "and from j = 1.5 on the stiffness matrix is numerically singular (cond shown as inf). "
        "**Derived reading** (rows `rule=derived`): a = 2^j Δx/π. The Gaussian of eq 6.8a, "
        "a⁻¹Φ(z) = e^(−z²)/(a√π) (eq 6.9a confirms Φ' = −2zΦ), has the Fourier transform "
        "e^(−a²ω²/4) (eq 4.23b), whose radius by eq 4.6b is Δk̂ = 1, so its frequency band is "
        "[−1/a, 1/a] (eqs 4.15b, 4.17). No aliasing (eq 4.18) needs the band edge 1/a at or "
        "below the Nyquist wavenumber π/Δx, and §6 sets j = 0 \"right at the stability "
        "limit\": a_0 = Δx/π, a = 2^j a_0. In eq 6.8b's own form a = 2^(j+0.5) σ this is "
        "σ = a_0/√2, the standard deviation of the j = 0 window e^(−z²/a_0²), which is the "
        "paper's definition of σ; the printed Δx/(σ√π) = 1/√2 instead gives σ = √(2/π) Δx, "
        "2√π = 3.54 times larger (it is 004 I's dilation a0 = √(2/π) Δx, eq 6.10, not a "
        "standard deviation). The derived constant 1/π = 0.3183 lies 3.5% below the single "
        "scale fitted to the table (0.3297, `rule=fit`, scripts/fit_table1_scale.py), and the "
        "per-column fits of the j = 1.5 … 3 columns give 0.312–0.319. Measured (2026-11-23, "
        "scripts/fit_table1_scale.py): with the exact derivative (eq 6.2) j = 1.5 … 3 reproduce "
        "the table within 0.021 at 21 nodes and 0.003 from 41 nodes on, and the narrow windows "
        "j = 0.5 and 1 fall up to 0.30 and 0.14 short.",
        "**On Table 1: the derivative.** Table 1 does not say which derivative it used; §7 says "
        "\"the two formulas for the derivatives give virtually identical results\". With the "
        "DEM derivative (eq 6.6, `derivative=diffuse`) and the derived window, the j = 0.5, 1, "
        "1.5 and 2 columns land on the table to its last printed digit or two (j = 0.5: "
        "3.510050 6.359952 8.755668 9.678830 9.858018 against 3.5100 6.3599 8.7556 9.6788 "
        "9.8580; measured 2026-11-27), so the narrow-window gap of the exact derivative is the "
        "derivative, not the window. At j = 2.5 and 3 the exact derivative is the closer at 21 "
        "nodes (0.4 % against 0.7 % and 2.4 %). 20 Gauss points per cell instead of ten move "
        "every peak by less than 1e-6.",
        "The fitted reading (`rule=fit`, a = 0.3297·2^j Δx) is kept for comparison; it is a fit "
        "to the table's 21/41/81-node rows, not a prediction.",
        "The table's last row is printed \"Δx = 0.005\"; §7 and its node list give 0.025 "
        "(241 nodes), which is what we run.",
    };
  }

 private:
  static constexpr const char* kPeak = kPeakName;
  double s_;
};

}  // namespace

void register_laplace_tanh(ProblemRegistry& r) {
  r.add("laplace-tanh", "u'' + 2s^2 sech^2(s(x-3)) tanh(s(x-3)) = 0 on [0,6], u = tanh(s(x-3)) "
                        "(004 II §7)",
        {ParamSpec::positive("s", 10, "localization of the gradient")},
        [](const Params& p) { return std::make_unique<LaplaceTanh>(p.number("s")); });
}

}  // namespace mfv
