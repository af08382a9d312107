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

namespace mfv {

using namespace dispersion_headline;

namespace {

std::string degrees(double a) { return fmt::format("{:g}°", a); }

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
        "{} force evaluations (central differences, step 1e-6 Δx)",
        to_string(p.lattice), row.patch_particles, row.half_width, row.influence_radius,
        p.frame == KernelFrame::lagrangian ? "Lagrangian" : "Eulerian",
        p.dim() == 2 ? fmt::format(" ν = {:g} plane strain", p.nu) : "", p.sigma,
        p.dim() == 2 ? (p.biaxial ? " biaxial" : " uniaxial (xx)") : "", p.dim() == 1 ? "E" : "μ",
        p.consistent_mass ? "consistent" : "lumped", row.force_evaluations);
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
      for (double angle : p.angles) {
        const ThresholdCurve tc =
            stress_threshold(zero, unit, angle * pi / 180, points, p.map_limit, p.modulus(), 1.0);
        const std::string at = p.dim() == 1 ? "" : fmt::format(" θ = {}", degrees(angle));
        a.curves.push_back({"stable-domain", "lower bound" + at, tc.kappa, tc.lower});
        a.curves.push_back({"stable-domain", "upper bound" + at, tc.kappa, tc.upper});
        for (std::size_t i = 0; i < tc.kappa.size(); ++i)
          mt.rows.push_back({angle, tc.kappa[i], tc.lower[i], tc.upper[i]});
      }
      a.tables.push_back(std::move(mt));
    }
    r.headline[kUnstable] = v.unstable ? 1 : 0;
    r.headline[kSpurious] = v.spurious ? 1 : 0;
    r.headline[kMinRatio] = v.min_ratio;
    r.headline[kCutoff] = v.cutoff_omega;
    if (v.unstable) r.headline[kOnset] = v.onset;
    if (v.spurious) r.headline[kSpuriousKappa] = v.spurious_kappa;
    r.cpu.assembly = t1 - t0;
    r.cpu.solve = cpu_seconds() - t1;
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
