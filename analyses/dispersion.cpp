/// The `dispersion` analysis: the von Neumann stability analysis of 000 §3–4 run on any
/// registered method (stability/dispersion.hpp) for a DispersionProblem's lattice:
/// ω²(κ, θ) from the method's own linearized internal force and a verdict (stable /
/// spurious mode at κ / tensile-unstable above κ). Frequencies are printed as ω Δx/(c π)
/// and wave numbers as κ Δx/π, with c² = E/ρ in 1D and c² = μ/ρ in 2D (000 Figs 2–12).
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "analyses/figures.hpp"
#include "methods/core/clock.hpp"
#include "methods/core/errors.hpp"
#include "problems/dispersion.hpp"
#include "methods/kernels/kernel.hpp"
#include "methods/kernels/kernel_choice.hpp"
#include "stability/closed_forms.hpp"
#include "stability/lattice.hpp"

namespace mfv {

using namespace dispersion_headline;

namespace {

std::string degrees(double a) { return fmt::format("{:g}°", a); }

/// 000's closed forms (stability/closed_forms.hpp) for the corrected-derivative method run as
/// kbm-ni (nodal) or kbm-si (stress points): ω² branches at a wave number, ascending, in units
/// of (c π/Δx)² (Δx = ρ = 1, St Venant–Kirchhoff E = 1: C̄ = E + σ at F = I, eq 3.4).
class ClosedFormModel {
 public:
  ClosedFormModel(const AnalysisContext& c, const DispersionDefinition& p) : p_(p) {
    const std::string& m = c.spec.method;
    if (m != "kbm-ni" && m != "kbm-si")
      throw InputError(fmt::format("route=closed-form evaluates 000's closed forms of the "
                                   "corrected-derivative method: run it with -m kbm-ni or kbm-si "
                                   "(got {})",
                                   m));
    if (p.consistent_mass)
      throw InputError("route=closed-form has 000's lumped mass only: drop mass=consistent");
    const Params mp = c.plugins.methods.resolve(m, c.spec.method_params);
    if (mp.number("radius") > 0)
      throw InputError("route=closed-form needs the support as dmax (h = D_mx Δx), not radius");
    W_ = make_kernel(c.plugins.kernels, mp);
    dmx_ = mp.number("dmax");
    stress_points_ = m == "kbm-si";
    if (p.dim() == 1) {
      if (stress_points_ && p.frame == KernelFrame::eulerian)
        throw InputError("000 writes no 1D closed form for stress points with an Eulerian "
                         "kernel: use route=engine");
      return;
    }
    const bool triangles = stress_points_ && mp.text("layout") == "triangle-centres";
    if (stress_points_ && triangles != (p.lattice == LatticeKind::hexagonal))
      throw InputError("000's 2D closed forms put stress points at quadrilateral centres of the "
                       "rectangular lattice and triangle centres of the hexagonal one");
    s2_.lattice = p.lattice == LatticeKind::rectangular ? closed_form::Lattice2D::rectangular
                                                         : closed_form::Lattice2D::hexagonal;
    s2_.stress_points = stress_points_;
    s2_.frame = p.frame == KernelFrame::lagrangian ? closed_form::Frame::lagrangian
                                                   : closed_form::Frame::eulerian;
    s2_.dmx = dmx_;
    s2_.mu = 1 / (2 * (1 + p.nu));
    s2_.lambda = p.nu / ((1 + p.nu) * (1 - 2 * p.nu));  // plane strain, E = 1
    s2_.stress(0, 0) = p.sigma * p.modulus();
    if (p.biaxial) s2_.stress(1, 1) = p.sigma * p.modulus();
  }
  /// Branches at κ = kn π/Δx along θ (radians), in (c π/Δx)².
  std::vector<double> omega2(double kn, double theta) const {
    namespace cf = closed_form;
    const double pi = std::numbers::pi, k = kn * pi, unit = p_.modulus() * pi * pi;
    if (p_.dim() == 1) {
      const double sg = p_.sigma;
      const double w = p_.frame == KernelFrame::eulerian
                           ? cf::omega2_eulerian_nodal_1d(*W_, dmx_, 1, k, 1, sg, 1)
                       : stress_points_ ? cf::omega2_lagrangian_stress_points_1d(*W_, dmx_, 1, k, 1 + sg, 1)
                                        : cf::omega2_lagrangian_nodal_1d(*W_, dmx_, 1, k, 1 + sg, 1);
      return {w / unit};
    }
    const auto w = cf::omega2_2d(*W_, s2_, k, theta);
    return {w[0] / unit, w[1] / unit};
  }

  /// The verdict of stability/dispersion.hpp's stability_verdict, sampled the same way.
  StabilityVerdict verdict(const std::vector<double>& thetas, int points, bool tension) const {
    const double pi = std::numbers::pi;
    StabilityVerdict v = scan_stability(
        thetas, points, tension,
        [&](double theta) { return brillouin_boundary(p_.lattice, 1.0, theta) / pi; },
        [&](double kn, double theta) { return omega2(kn, theta)[0]; });
    v.text = "000's closed forms: " + v.text;
    return v;
  }

 private:
  const DispersionDefinition& p_;
  std::unique_ptr<Kernel> W_;
  double dmx_ = 0;
  bool stress_points_ = false;
  closed_form::Setup2D s2_;
};

class Dispersion final : public FigureAnalysis {
 public:
  bool accepts(const Problem& problem) const override {
    return dynamic_cast<const DispersionProblem*>(&problem) != nullptr;
  }
  void run(const AnalysisContext& c, CaseResult& r) const override {
    const DispersionDefinition& p =
        definition_of<DispersionProblem>(c, "dispersion", "a lattice (a DispersionProblem)")
            .definition();
    const double pi = std::numbers::pi;
    const int points = c.spec.nodes;
    if (points < 3 || points > 100000)
      throw InputError(fmt::format("dispersion samples {} wave numbers per direction (the case's "
                                   "nodes, or --points); use 3 to 100000, e.g. 101",
                                   points));
    if (p.closed_form) return run_closed_form(c, p, r);
    const double t0 = cpu_seconds();
    const BlochRow row = bloch_row(c.method, p.setup(c.plugins.materials, p.sigma));
    const double t1 = cpu_seconds();
    std::vector<double> thetas;
    for (double a : p.angles) thetas.push_back(a * pi / 180);
    const StabilityVerdict v = stability_verdict(row, thetas, points, p.modulus(), 1.0, p.sigma > 0);
    r.particles = row.patch_particles;
    r.h = 1;
    r.dim = p.dim();
    r.components = p.dim();
    r.method_description = row.description;
    FigureData& a = r.emplace<FigureData>();
    a.setup = fmt::format(
        "{} lattice, Δx = 1, patch of {} particles (half width {}), neighbours within {:.2f} Δx, "
        "{} kernel, St Venant-Kirchhoff E = 1{}, ρ = 1, prestress σ̄ = {:g}{} (σ/{}), {} mass, "
        "{} force evaluations (central differences, step 1e-6 Δx; {})",
        to_string(p.lattice), row.patch_particles, row.half_width, row.influence_radius,
        p.frame == KernelFrame::lagrangian ? "Lagrangian" : "Eulerian",
        p.dim() == 2 ? fmt::format(" ν = {:g} plane strain", p.nu) : "", p.sigma,
        p.dim() == 2 ? (p.biaxial ? " biaxial" : " uniaxial (xx)") : "", p.dim() == 1 ? "E" : "μ",
        p.consistent_mass ? "consistent" : "lumped", row.force_evaluations,
        row.translated ? "K_0J from the centre's perturbation by translation invariance, checked "
                         "directly at two neighbours"
                       : "K_0J from each neighbour's perturbation");
    a.verdicts.push_back(v.text);
    a.figures.push_back({"dispersion",
                         fmt::format("Dispersion, {} kernel, σ̄ = {:g}",
                                     p.frame == KernelFrame::lagrangian ? "Lagrangian" : "Eulerian",
                                     p.sigma),
                         "κ Δx / π", "ω Δx / (c π)  (negative: −|ω| of an unstable mode)", false,
                         "lines"});
    FigureData::Table table{"dispersion", {"theta_deg", "kappa_over_pi_dx"}, {}};
    for (int b = 0; b < p.dim(); ++b) table.columns.push_back(fmt::format("omega2_branch{}", b + 1));
    table.columns.push_back("max_abs_imag_omega2");
    for (double angle : p.angles) {
      const DispersionBranch br = dispersion_branch(row, angle * pi / 180, points, p.modulus(), 1.0);
      for (int b = 0; b < p.dim(); ++b) {
        FigureData::Curve cv{"dispersion",
                               p.dim() == 1 ? "ω" : fmt::format("θ = {} branch {}", degrees(angle), b + 1),
                               {}, {}};
        for (std::size_t i = 0; i < br.kappa.size(); ++i) {
          const double w2 = br.omega2[i][b];
          cv.x.push_back(br.kappa[i]);
          cv.y.push_back(w2 >= 0 ? std::sqrt(w2) : -std::sqrt(-w2));
        }
        a.curves.push_back(std::move(cv));
      }
      for (std::size_t i = 0; i < br.kappa.size(); ++i) {
        std::vector<double> line{angle, br.kappa[i]};
        for (double w2 : br.omega2[i]) line.push_back(w2);
        line.push_back(br.imaginary[i]);
        table.rows.push_back(std::move(line));
      }
    }
    a.tables.push_back(std::move(table));
    if (p.map) {
      // The operator is affine in the prestress: two rows give the whole (σ̄, κ) plane.
      const BlochRow zero = bloch_row(c.method, p.setup(c.plugins.materials, 0.0));
      const BlochRow unit = bloch_row(c.method, p.setup(c.plugins.materials, 1.0));
      a.figures.push_back({"stable-domain",
                           "Stable domain: stable between the curves (000 Figs 5-6)", "κ Δx / π",
                           "σ̄", false, "lines"});
      FigureData::Table mt{"stable-domain", {"theta_deg", "kappa_over_pi_dx", "sigma_lower", "sigma_upper"}, {}};
      // The map in two numbers: the prestress range stable at every κ and direction. A bound
      // that is NaN at a κ (no threshold within ±map_limit) does not constrain it; none at
      // all: stable to the limit.
      double compression = -p.map_limit, tension = p.map_limit;
      for (double angle : p.angles) {
        const ThresholdCurve tc =
            stress_threshold(zero, unit, angle * pi / 180, points, p.map_limit, p.modulus(), 1.0);
        const std::string at = p.dim() == 1 ? "" : fmt::format(" θ = {}", degrees(angle));
        a.curves.push_back({"stable-domain", "lower bound" + at, tc.kappa, tc.lower});
        a.curves.push_back({"stable-domain", "upper bound" + at, tc.kappa, tc.upper});
        for (std::size_t i = 0; i < tc.kappa.size(); ++i) {
          mt.rows.push_back({angle, tc.kappa[i], tc.lower[i], tc.upper[i]});
          if (std::isfinite(tc.lower[i])) compression = std::max(compression, tc.lower[i]);
          if (std::isfinite(tc.upper[i])) tension = std::min(tension, tc.upper[i]);
        }
      }
      a.tables.push_back(std::move(mt));
      r.headline[kCompressionBound] = compression;
      r.headline[kTensionBound] = tension;
    }
    eq318_headlines(c, p, a, r);
    verdict_headlines(v, r);
    r.cpu.assembly = t1 - t0;
    r.cpu.solve = cpu_seconds() - t1;
  }

 private:
  /// The verdict's headlines, the same for the engine's route and the closed forms'.
  static void verdict_headlines(const StabilityVerdict& v, CaseResult& r) {
    r.headline[kUnstable] = v.unstable ? 1 : 0;
    r.headline[kSpurious] = v.spurious ? 1 : 0;
    r.headline[kMinRatio] = v.min_ratio;
    r.headline[kCutoff] = v.cutoff_omega;
    if (v.unstable) r.headline[kOnset] = v.onset;
    if (v.spurious) r.headline[kSpuriousKappa] = v.spurious_kappa;
  }

  /// 000 eq 3.18, what its Fig. 3 plots, beside the method's own linearization: only for the
  /// method it describes (corrected derivatives, nodal integration, h = D_mx Δx) on the line.
  static void eq318_headlines(const AnalysisContext& c, const DispersionDefinition& p,
                              FigureData& a, CaseResult& r) {
    if (c.spec.method == "kbm-ni" && p.lattice == LatticeKind::line &&
        p.frame == KernelFrame::eulerian && p.sigma > 0) {
      const Params mp = c.plugins.methods.resolve(c.spec.method, c.spec.method_params);
      if (!(mp.number("radius") > 0)) {
        const auto W = make_kernel(c.plugins.kernels, mp);
        const double dmx = mp.number("dmax");
        namespace cf = closed_form;
        const struct {
          cf::Normalization n;
          const char *scan, *arccos, *name;
        } readings[] = {
            {cf::Normalization::frozen, kOnsetFrozen, kOnsetFrozenArccos,
             "frozen normalization (eqs 3.16, 4.12)"},
            {cf::Normalization::shepard, kOnsetShepard, kOnsetShepardArccos,
             "Shepard function's w'' (eq 2.7)"}};
        for (const auto& rd : readings) {
          const double k = cf::onset_wavenumber_eulerian_1d(*W, dmx, p.sigma, rd.n);
          if (std::isfinite(k)) r.headline[rd.scan] = k;
          double k3 = NAN;
          if (dmx > 1 && dmx <= 2) {
            k3 = cf::onset_wavenumber_eulerian_three_point(*W, dmx, p.sigma, rd.n);
            if (std::isfinite(k3)) r.headline[rd.arccos] = k3;
          }
          a.verdicts.push_back(fmt::format(
              "000 eq 3.18 ({}): tensile onset {} π/Δx{}", rd.name,
              std::isfinite(k) ? fmt::format("{:.4f}", k) : std::string("none"),
              std::isfinite(k3) ? fmt::format(" (arccos of the three-point form: {:.4f})", k3)
                                : std::string()));
        }
      }
    }
  }

  /// route=closed-form: the same headlines from 000's closed forms (ClosedFormModel).
  static void run_closed_form(const AnalysisContext& c, const DispersionDefinition& p,
                              CaseResult& r) {
    const double pi = std::numbers::pi;
    const int points = c.spec.nodes;
    const double t0 = cpu_seconds();
    const ClosedFormModel model(c, p);
    std::vector<double> thetas;
    for (double a : p.angles) thetas.push_back(a * pi / 180);
    const StabilityVerdict v = model.verdict(thetas, points, p.sigma > 0);
    r.particles = 1;
    r.h = 1;
    r.dim = p.dim();
    r.components = p.dim();
    r.method_description = c.spec.method + " as 000's closed forms (stability/closed_forms.hpp)";
    FigureData& a = r.emplace<FigureData>();
    a.setup = fmt::format(
        "{} lattice, Δx = 1, {} kernel, St Venant-Kirchhoff E = 1{}, ρ = 1, prestress σ̄ = {:g}; "
        "ω² from 000's closed forms (eqs 3.12, 3.18 with the normalization frozen, 3.23, and the "
        "2D dynamical matrix of eqs 4.6-4.26), not from the method's force",
        to_string(p.lattice), p.frame == KernelFrame::lagrangian ? "Lagrangian" : "Eulerian",
        p.dim() == 2 ? fmt::format(" ν = {:g} plane strain", p.nu) : "", p.sigma);
    a.verdicts.push_back(v.text);
    a.figures.push_back({"dispersion", "Dispersion (000's closed forms)", "κ Δx / π",
                         "ω Δx / (c π)  (negative: −|ω| of an unstable mode)", false, "lines"});
    for (double angle : p.angles) {
      const double kmax = brillouin_boundary(p.lattice, 1.0, angle * pi / 180) / pi;
      for (int b = 0; b < p.dim(); ++b) {
        FigureData::Curve cv{"dispersion",
                             p.dim() == 1 ? "ω" : fmt::format("θ = {} branch {}", degrees(angle), b + 1),
                             {}, {}};
        for (int i = 0; i < points; ++i) {
          const double kn = kmax * i / (points - 1);
          const double w2 = model.omega2(kn, angle * pi / 180)[b];
          cv.x.push_back(kn);
          cv.y.push_back(w2 >= 0 ? std::sqrt(w2) : -std::sqrt(-w2));
        }
        a.curves.push_back(std::move(cv));
      }
    }
    eq318_headlines(c, p, a, r);
    verdict_headlines(v, r);
    r.cpu.solve = cpu_seconds() - t0;
  }
};

}  // namespace

void register_dispersion_analysis(AnalysisRegistry& r) {
  r.add("dispersion",
        "Bloch-wave dispersion of the method's linearized force on a lattice problem: "
        "omega(kappa, theta), spurious modes, tensile instability (000 §3-4)",
        {}, [](const Params&) { return std::make_unique<Dispersion>(); });
}

}  // namespace mfv
