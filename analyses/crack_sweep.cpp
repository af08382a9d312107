/// The `crack-sweep` analysis: stability of the explicit extended EFG (003, Samaniego et al.,
/// "Contributions to the stability analysis of explicit enriched meshfree methods") on an
/// EnrichedBarProblem:
///
/// 1. Sweep: a crack moved from one node to the next (relative position s ∈ [0, 1]) through a
///    1D bar of 10 particles 1 m apart (E = 200 GPa, ρ = 7850, DMAX = 2.3, cubic spline,
///    linear basis, 003 §4) or a 2D patch (a crack through it, or from the bottom edge to a
///    tip at relative y = 0.9 inside the middle row of cells, 003 §4.3.1); for each DMAX and
///    mass scheme (consistent eq 13, MLS1 eqs 14-16, MLS2 eqs 19-22) the ratio
///    Δt_crack / Δt_no-crack, Δt = 2/√λ_max (eq 12).
/// 2. α of eq 30 (003 §4.3.3, eqs 23-30): λ_max of the integration cell's K_cell φ = λ M_cell φ
///    (eq 29: λ = E/(ρΔx²) λ(M_dmax, K_dmax)) for an interior cell of a long uniform bar,
///    row-sum and MLS1 lumping; with the trimming heuristic only the shape functions whose
///    middle half of the support [0.25 s, 0.75 s] covers the cell count (even DMAX).
///    λ_max DMAX² rises with DMAX toward a limit; α (the headline) is that limit, computed on
///    DMAX = 8, 16, 32, ... until two successive values agree to kAlphaConverged, and the
///    closed form of the limit (stability/closed_forms.hpp, cell_alpha_limit) is printed beside
///    it. The least-squares fit of λ = α/DMAX² over support radii 2-8 is kept for scale
///    ("fit 2-8"): it depends on the range fitted, which 003 does not give.
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include <fmt/format.h>

#include "analyses/figures.hpp"
#include "methods/approximations/enriched.hpp"
#include "methods/core/clock.hpp"
#include "methods/core/errors.hpp"
#include "methods/kernels/kernel_choice.hpp"
#include "problems/enriched_bar.hpp"
#include "stability/closed_forms.hpp"
#include "stability/enriched_mass.hpp"

namespace mfv {

namespace {

constexpr const char* kSchemeNames[] = {"consistent", "row-sum", "MLS1", "MLS2"};
const MassScheme kSweepSchemes[] = {MassScheme::consistent, MassScheme::mls1, MassScheme::mls2};

const char* scheme_name(MassScheme s) { return kSchemeNames[static_cast<int>(s)]; }

double support_factor(const std::string& convention) {
  return convention == "diameter" ? 0.5 : convention == "2h" ? 2.0 : 1.0;
}

/// Two successive DMAX of the doubling sequence whose λ_max DMAX² differ by less than this
/// (relative) end it: the value is then within about that of the limit (the difference
/// falls at least as fast as 1/DMAX, so the remaining gap is at most about one more step).
constexpr double kAlphaConverged = 2e-3;
/// The doubling sequence starts here and stops here at the latest (support radii in Δx).
constexpr double kAlphaFirstRadius = 8, kAlphaLastRadius = 512;

/// One α fit: per-DMAX λ (in E/(ρΔx²)) of the row-sum and MLS1 cell problems.
struct AlphaFit {
  std::vector<double> dmax, row_sum, mls1;
  double alpha_row_sum = NAN, alpha_mls1 = NAN;
};

/// α of λ = α / DMAX² (eq 30 with E = ρ = Δx = 1), least squares in the relative misfit
/// (α/DMAX² − λ)/λ so that every DMAX counts alike (003 does not say how it fitted).
double fit_alpha(const std::vector<double>& dmax, const std::vector<double>& lambda) {
  double num = 0, den = 0;
  for (std::size_t i = 0; i < dmax.size(); ++i) {
    if (!std::isfinite(lambda[i]) || !(lambda[i] > 0)) continue;
    const double c = 1 / (dmax[i] * dmax[i] * lambda[i]);
    num += c;
    den += c * c;
  }
  return den > 0 ? num / den : NAN;
}

class CrackSweep final : public FigureAnalysis {
 public:
  bool accepts(const Problem& problem) const override {
    return dynamic_cast<const EnrichedBarProblem*>(&problem) != nullptr;
  }
  void run(const AnalysisContext& c, CaseResult& r) const override {
    const EnrichedBarDefinition& p =
        definition_of<EnrichedBarProblem>(c, "crack-sweep", "a bar to sweep a crack through (an EnrichedBarProblem)")
            .definition();
    if (c.spec.method != "xefg")
      throw InputError(fmt::format("enriched-bar analyses the extended EFG: run it with -m xefg "
                                   "(got method '{}')",
                                   c.spec.method));
    const Params mp = c.plugins.methods.resolve("xefg", c.spec.method_params);
    if (mp.text("crack") != "none")
      throw InputError("enriched-bar moves the crack itself: leave the method's crack=none "
                       "(set the swept interval with the problem's 'interval')");
    const double dmax0 = mp.number("dmax");
    std::vector<double> dmaxes;
    // Defaults (0) keep a 2D run to seconds: one DMAX and six positions.
    const int ndmax = p.sweep.integer("dmax_count") > 0 ? p.sweep.integer("dmax_count") : p.dim == 1 ? 3 : 1;
    for (int k = 0; k < ndmax; ++k)
      dmaxes.push_back(dmax0 + k * p.sweep.number("dmax_step"));
    const int npos = p.sweep.integer("positions") > 0 ? p.sweep.integer("positions") : p.dim == 1 ? 21 : 6;
    const Domain dom = p.domain();
    const ParticleSet base = p.dim == 1 ? uniform_line(dom, p.n)
                                       : rectangle_lattice(dom, p.n, p.n, Placement::boundary);
    double t_assembly = 0, t_solve = 0;
    const bool mls1_point = p.sweep.text("mls1") == "point";
    const bool mls2_region = p.sweep.text("mls2") == "region";
    std::vector<int> active;
    for (int i = 0; i < 3; ++i)
      if (p.sweep.text("mass") == "all" || p.sweep.text("mass") == scheme_name(kSweepSchemes[i]))
        active.push_back(i);

    // Δt of every mass scheme for a method variant.
    const auto steps = [&](const Params& q, int& enriched) {
      const double a = cpu_seconds();
      const auto m = c.plugins.methods.create("xefg", q);
      const Discretization d = m->discretize(dom, base, 1);
      enriched = d.enriched_unknowns;
      if (r.method_description.empty()) r.method_description = d.description;
      const Eigen::MatrixXd K = enriched_stiffness(d, p.material);
      std::vector<Eigen::MatrixXd> M(3);
      for (int i : active)
        M[i] = kSweepSchemes[i] == MassScheme::mls2 && mls2_region
                   ? enriched_mass_mls2_region(d, p.material)
                   : enriched_mass(d, p.material, kSweepSchemes[i], mls1_point);
      const double b = cpu_seconds();
      std::vector<double> dt(3, NAN);
      for (int i : active)
        dt[i] = critical_step(K, M[i], kSweepSchemes[i] != MassScheme::consistent);
      t_assembly += b - a;
      t_solve += cpu_seconds() - b;
      return dt;
    };

    r.dim = p.dim;
    r.components = p.dim;
    r.h = 1;
    r.particles = base.size();
    FigureData& an = r.emplace<FigureData>();
    const double x0 = p.interval;
    const double y_tip = p.tip_y();
    an.setup = fmt::format(
        "{}: {} particles 1 m apart, E = {:g} Pa, rho = {:g} kg/m3{}; crack swept from x = {} "
        "to x = {} in {} steps; DMAX = {}; xefg: {}. Ratios are dt(crack)/dt(no crack) with the "
        "same mass scheme and DMAX.",
        p.dim == 1 ? "1D bar" : "2D patch", p.dim == 1 ? p.n : p.n * p.n, p.material.E, p.material.rho,
        p.dim == 2 ? fmt::format(", nu = {}, plane {}, tip at y = {}", p.material.nu,
                                p.material.plane_strain ? "strain" : "stress", y_tip)
                  : "",
        x0, x0 + 1, npos - 1, fmt::join(dmaxes, ", "), mp.to_string());

    // 1. Sweeps: through crack (1D and 2D) and, in 2D, the edge crack with its tip.
    std::vector<std::string> cases{"through"};
    if (p.dim == 2) cases.push_back("edge");
    FigureData::Table sweep{"dt-sweep",
                              {"tip", "dmax", "position", "dt consistent", "dt MLS1", "dt MLS2",
                               "ratio consistent", "ratio MLS1", "ratio MLS2",
                               "enriched columns"},
                              {}};
    for (const std::string& kind : cases) {
      const std::string suffix = kind == "edge" ? " tip" : "";
      const std::string fig = kind == "edge" ? "dt-ratio-tip" : "dt-ratio";
      an.figures.push_back({fig,
                            kind == "edge"
                                ? fmt::format("dt ratio, crack tip at y = {} ({} enrichment)",
                                              y_tip, p.sweep.text("tip"))
                                : "dt ratio, crack through the " +
                                      std::string(p.dim == 1 ? "bar" : "patch"),
                            "relative crack position between two nodes",
                            "dt(crack) / dt(no crack)", false, "linespoints"});
      an.figures.push_back({kind == "edge" ? "dt-tip" : "dt", "critical time step" + suffix, "relative crack position",
                            "dt (s)", false, "linespoints"});
      for (double dm : dmaxes) {
        Params q = c.spec.method_params;
        q.set("dmax", dm);
        int en = 0;
        const std::vector<double> ref = steps(q, en);
        std::vector<FigureData::Curve> ratio(3), abs(3);
        for (int i = 0; i < 3; ++i) {
          ratio[i] = {fig, fmt::format("{} DMAX={}", scheme_name(kSweepSchemes[i]), dm), {}, {}};
          abs[i] = {an.figures.back().id, ratio[i].label, {}, {}};
        }
        for (int k = 0; k < npos; ++k) {
          const double s = npos > 1 ? static_cast<double>(k) / (npos - 1) : 0.5;
          q.set("crack", kind.c_str());
          q.set("crack_x", x0 + s);
          if (kind == "edge") {
            q.set("crack_tip", y_tip);
            q.set("tip", p.sweep.text("tip").c_str());
          }
          const std::vector<double> dt = steps(q, en);
          std::vector<double> row{kind == "edge" ? 1.0 : 0.0, dm, s};
          for (int i = 0; i < 3; ++i) row.push_back(dt[i]);
          for (int i = 0; i < 3; ++i) row.push_back(dt[i] / ref[i]);
          for (int i : active) {
            const double rr = dt[i] / ref[i];
            ratio[i].x.push_back(s);
            ratio[i].y.push_back(rr);
            abs[i].x.push_back(s);
            abs[i].y.push_back(dt[i]);
          }
          row.push_back(en);
          sweep.rows.push_back(row);
        }
        for (int i : active) {
          const double lo = *std::min_element(ratio[i].y.begin(), ratio[i].y.end());
          const auto at = std::min_element(ratio[i].y.begin(), ratio[i].y.end()) - ratio[i].y.begin();
          const std::string scheme = scheme_name(kSweepSchemes[i]);
          if (dm == dmax0) {
            r.headline[fmt::format("min dt ratio {}{}", scheme, suffix)] = lo;
            // s = 0: the crack through a node, 003's "worst case".
            r.headline[fmt::format("dt ratio at node {}{}", scheme, suffix)] = ratio[i].y.front();
            if (kind == "through") r.headline[fmt::format("dt no crack {}", scheme)] = ref[i];
          }
          an.verdicts.push_back(fmt::format(
              "{}{}, DMAX={}: dt ratio from {:.3f} (s = {:.2f}) to {:.3f}; dt without crack {:.4g} s",
              scheme, kind == "edge" ? " (tip)" : "", dm, lo, ratio[i].x[at],
              *std::max_element(ratio[i].y.begin(), ratio[i].y.end()), ref[i]));
          an.curves.push_back(std::move(ratio[i]));
          an.curves.push_back(std::move(abs[i]));
        }
      }
    }
    an.tables.push_back(std::move(sweep));

    // 2. The α fit of eq 30 (1D cells), for every support convention.
    FigureData::Table alpha{"alpha",
                              {"support factor", "dmax", "trimmed", "lambda row-sum",
                               "lambda MLS1", "alpha row-sum", "alpha MLS1", "lambda bar row-sum"},
                              {}};
    const std::string conv = mp.text("support");
    an.figures.push_back({"alpha", "eq 30 fit: lambda_max DMAX^2 rho dx^2 / E (" + conv + ")",
                          "DMAX", "alpha", false, "linespoints"});
    for (const std::string cv : {"radius", "diameter", "2h"}) {
      const double f = support_factor(cv);
      for (bool trimmed : {false, true}) {
        std::vector<double> list;
        if (trimmed) {
          for (int dm = 2; dm <= 8; dm += 2) list.push_back(dm);
        } else {
          // The same support radii (2..8 Δx) in every convention.
          for (int k = 0; k <= 12; ++k) list.push_back((2 + 0.5 * k) / f);
        }
        AlphaFit fit;
        for (double dm : list) {
          double lr, l1, lbar;
          cell_eigenvalues(c, mp, cv, dm, trimmed, lr, l1, lbar, t_assembly, t_solve);
          if (!std::isfinite(lr) && !std::isfinite(l1)) continue;
          fit.dmax.push_back(dm);
          fit.row_sum.push_back(lr);
          fit.mls1.push_back(l1);
          alpha.rows.push_back({f, dm, trimmed ? 1.0 : 0.0, lr, l1, lr * dm * dm, l1 * dm * dm,
                                lbar});
        }
        fit.alpha_row_sum = fit_alpha(fit.dmax, fit.row_sum);
        fit.alpha_mls1 = fit_alpha(fit.dmax, fit.mls1);
        const std::string t = trimmed ? " trimmed" : "";
        if (cv == conv) {
          r.headline["alpha row-sum" + t + " fit 2-8"] = fit.alpha_row_sum;
          r.headline["alpha MLS1" + t + " fit 2-8"] = fit.alpha_mls1;
          for (int s = 0; s < 2; ++s) {
            FigureData::Curve cu{"alpha", fmt::format("{}{}", s ? "MLS1" : "row-sum", t), {}, {}};
            for (std::size_t i = 0; i < fit.dmax.size(); ++i) {
              cu.x.push_back(fit.dmax[i]);
              cu.y.push_back((s ? fit.mls1[i] : fit.row_sum[i]) * fit.dmax[i] * fit.dmax[i]);
            }
            an.curves.push_back(std::move(cu));
          }
        }
        an.verdicts.push_back(fmt::format(
            "alpha fitted over support radii 2-8 ({} convention, support radius {} DMAX dx{}): "
            "row-sum {:.3f}, MLS1 {:.3f} (003: row-sum {}; Belytschko et al. 2000: 13.30)",
            cv, f, trimmed ? ", trimmed to the middle half of each support, even DMAX" : "",
            fit.alpha_row_sum, fit.alpha_mls1, trimmed ? "7.1, MLS1 10" : "12.46"));
      }
    }
    an.tables.push_back(std::move(alpha));

    // 3. The large-DMAX limit of λ_max DMAX² in the method's convention: 003 "solving the
    //    eigenvalue problem for different even values of D_max" obtains one α, which its fit
    //    can only give if λ DMAX² has settled; our per-DMAX values rise toward a limit.
    FigureData::Table limit{"alpha-limit",
                            {"trimmed", "dmax", "support radius", "alpha row-sum", "alpha MLS1"},
                            {}};
    const double f = support_factor(conv);
    const auto W = make_kernel(c.plugins.kernels, mp);
    for (bool trimmed : {false, true}) {
      const std::string t = trimmed ? " trimmed" : "";
      // The row sum converges with and without trimming; MLS1 only trimmed (its untrimmed
      // λ DMAX² grows without bound: the closed form's integrand is not integrable).
      struct Scheme {
        std::string name;
        bool converges;
        double last = NAN, value = NAN;
        bool done = false;
      };
      std::vector<Scheme> schemes{{"row-sum", true}, {"MLS1", trimmed}};
      for (double R = kAlphaFirstRadius; R <= kAlphaLastRadius; R *= 2) {
        const double dm = R / f;
        double lr, l1, lbar;
        cell_eigenvalues(c, mp, conv, dm, trimmed, lr, l1, lbar, t_assembly, t_solve,
                         /*whole_bar=*/false);
        const double a[2] = {lr * dm * dm, l1 * dm * dm};
        limit.rows.push_back({trimmed ? 1.0 : 0.0, dm, R, a[0], a[1]});
        bool all = true;
        for (int k = 0; k < 2; ++k) {
          Scheme& sc = schemes[k];
          if (sc.converges && !sc.done) {
            if (std::abs(a[k] - sc.last) <= kAlphaConverged * std::abs(a[k])) {
              sc.value = a[k];
              sc.done = true;
            }
            sc.last = a[k];
          }
          all = all && (!sc.converges || sc.done);
        }
        if (all) break;
      }
      const double fr = 1 / (f * f);  // α in the convention: λ DMAX² with DMAX = R/f
      const double closed[2] = {
          fr * closed_form::cell_alpha_limit(*W, closed_form::CellLumping::row_sum, trimmed),
          fr * closed_form::cell_alpha_limit(*W, closed_form::CellLumping::mls1, trimmed)};
      for (int k = 0; k < 2; ++k) {
        const Scheme& sc = schemes[k];
        if (!sc.converges) continue;
        // NaN when the sequence did not settle by kAlphaLastRadius: no limit is claimed.
        r.headline["alpha " + sc.name + t] = sc.value;
        r.headline["alpha " + sc.name + t + " closed form"] = closed[k];
        an.verdicts.push_back(fmt::format(
            "alpha {}{} as DMAX grows ({} convention): {} (successive DMAX within {:g} %); "
            "closed form of the limit {:.4f}",
            sc.name, t, conv,
            sc.done ? fmt::format("{:.4f}", sc.value) : std::string("not settled"),
            100 * kAlphaConverged, closed[k]));
      }
    }
    an.tables.push_back(std::move(limit));
    r.cpu.assembly = t_assembly;
    r.cpu.solve = t_solve;
  }


 private:
  /// λ_max (units E/(ρΔx²)) of the row-sum and MLS1 cell problems of an interior cell of a
  /// long uniform bar, and of the whole bar with row-sum lumping.
  void cell_eigenvalues(const AnalysisContext& c, const Params& mp, const std::string& conv,
                        double dmax, bool trimmed, double& row_sum, double& mls1, double& bar,
                        double& t_assembly, double& t_solve, bool whole_bar = true) const {
    const double a = cpu_seconds();
    row_sum = mls1 = bar = NAN;
    const double R = support_factor(conv) * dmax;  // support radius in Δx
    const int n = 2 * static_cast<int>(std::ceil(R)) + 8;
    const Domain dom = Domain::interval(0, n - 1);
    Params q = c.spec.method_params;
    q.set("dmax", dmax);
    q.set("support", conv.c_str());
    const auto m = c.plugins.methods.create("xefg", q);
    Discretization d;
    try {
      d = m->discretize(dom, uniform_line(dom, n), 1);
    } catch (const SingularError&) {
      return;  // a support too small for the linear basis: no point on the curve
    }
    BarMaterial unit;
    unit.E = unit.rho = 1;
    const int cell = n / 2 - 1;  // between nodes cell and cell + 1
    std::vector<int> nodes;
    for (int qd = 0; qd < d.quadrature.size(); ++qd)
      if (d.quadrature.cell[qd] == cell)
        for (int k = d.trial_q.offsets[qd]; k < d.trial_q.offsets[qd + 1]; ++k)
          nodes.push_back(d.trial_q.index[k]);
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    if (trimmed) {
      // Keep a node when the middle half of its support, x_I ± R/2, covers the whole cell.
      const double tol = 1e-9;
      std::erase_if(nodes, [&](int I) {
        const double xi = d.particles.x(0, I);
        return !(xi - R / 2 <= cell + tol && xi + R / 2 >= cell + 1 - tol);
      });
    }
    const int k = static_cast<int>(nodes.size());
    std::vector<int> local(d.particles.size(), -1);
    for (int i = 0; i < k; ++i) local[nodes[i]] = i;
    Eigen::MatrixXd Mc = Eigen::MatrixXd::Zero(k, k), Kc = Eigen::MatrixXd::Zero(k, k);
    for (int qd = 0; qd < d.quadrature.size(); ++qd) {
      if (d.quadrature.cell[qd] != cell) continue;
      const double w = d.quadrature.weights[qd];
      for (int i = d.trial_q.offsets[qd]; i < d.trial_q.offsets[qd + 1]; ++i)
        for (int j = d.trial_q.offsets[qd]; j < d.trial_q.offsets[qd + 1]; ++j) {
          const int li = local[d.trial_q.index[i]], lj = local[d.trial_q.index[j]];
          if (li < 0 || lj < 0) continue;
          Mc(li, lj) += w * d.trial_q.value[i] * d.trial_q.value[j];
          Kc(li, lj) += w * d.trial_q.grad[i] * d.trial_q.grad[j];
        }
    }
    Eigen::MatrixXd Kbar, Mbar;
    if (whole_bar) {
      Kbar = enriched_stiffness(d, unit);
      Mbar = enriched_mass(d, unit, MassScheme::row_sum);
    }
    const double b = cpu_seconds();
    if (k >= 2) {
      const Eigen::VectorXd rs = Mc.rowwise().sum();
      const Eigen::VectorXd dg = Mc.diagonal() * (1.0 / Mc.diagonal().sum());  // M_h = Δx = 1
      row_sum = largest_eigenvalue(Kc, Eigen::MatrixXd(rs.asDiagonal()), true);
      mls1 = largest_eigenvalue(Kc, Eigen::MatrixXd(dg.asDiagonal()), true);
    }
    if (whole_bar) bar = largest_eigenvalue(Kbar, Mbar, true);
    t_assembly += b - a;
    t_solve += cpu_seconds() - b;
  }

};

}  // namespace

void register_crack_sweep(AnalysisRegistry& r) {
  r.add("crack-sweep",
        "critical-step ratio of the extended EFG as a crack is moved through a node interval, "
        "per DMAX and mass scheme, and the alpha fit of the cell eigenvalue (003 §4)",
        {}, [](const Params&) { return std::make_unique<CrackSweep>(); });
}

}  // namespace mfv
