/// The `stretch-map` analysis: the stable domains of 001 Fig. 1 in the space of the
/// principal stretches (λ1, λ2) of the hyperelastic `rubber` material (001 eq 18, 000 eq 5.1),
/// for the PDE (strong ellipticity, stability/material_stability.hpp) and for any 2D method
/// with a Lagrangian and an Eulerian kernel. Each state is the uniform deformation
/// F0 = diag(λ1, λ2) of an infinite lattice; the method's explicit engine is moved there
/// (Lagrangian: total Lagrangian F; Eulerian: tables at the deformed positions) and its
/// internal force is linearized by central differences (stability/dispersion.hpp). The stress
/// is the material's at F0 (no separate prestress). A state is discretely stable when ω² ≥ 0
/// for every sampled wave vector; a spurious zero (ω² = 0 away from κ = 0) counts as stable.
/// Units: Δx = 1, the paper's c1, c2, λ and ρ = 125.4; ω² normalized by (c π/Δx)² with
/// c² = μ0/ρ, μ0 = c1 + c2 (the small-strain shear modulus).
#include <cmath>
#include <numbers>
#include <sstream>

#include <fmt/format.h>

#include "analyses/figures.hpp"
#include "methods/core/clock.hpp"
#include "methods/core/errors.hpp"
#include "problems/stretch_map.hpp"
#include "stability/dispersion.hpp"
#include "stability/material_stability.hpp"

namespace mfv {

using namespace stretch_map_headline;

namespace {

class StretchMap final : public FigureAnalysis {
 public:
  bool accepts(const Problem& problem) const override {
    return dynamic_cast<const StretchMapProblem*>(&problem) != nullptr;
  }
  void run(const AnalysisContext& c, CaseResult& r) const override {
  const StretchMapDefinition& p =
        definition_of<StretchMapProblem>(c, "stretch-map", "stretched states (a StretchMapProblem)")
            .definition();
    const double pi = std::numbers::pi;
    const double t0 = cpu_seconds();
    const std::shared_ptr<const Material> material =
        c.plugins.materials.create("rubber", p.material_params);
    std::vector<double> thetas;
    for (double a : p.angles) thetas.push_back(a * pi / 180);
    struct Frame {
      bool on;
      KernelFrame kind;
      const char* name;
    };
    const Frame frames[2] = {{p.lagrangian, KernelFrame::lagrangian, "lagrangian"},
                             {p.eulerian, KernelFrame::eulerian, "eulerian"}};
    // stable[f][i][j]: frame f at (λ1, λ2) = (p.stretch(i), p.stretch(j)); -1 = not computed.
    std::vector<std::vector<int>> pde(p.grid, std::vector<int>(p.grid, 0));
    std::vector<std::vector<std::vector<int>>> disc(
        2, std::vector<std::vector<int>>(p.grid, std::vector<int>(p.grid, -1)));
    double setup_time = 0;
    BlochRow sample;
    int evaluations = 0, rows = 0, translated = 0;
    // The square lattice (and its cell-centre stress points) is symmetric under x ↔ y and the
    // material is isotropic, so (λ2, λ1) has the verdicts of (λ1, λ2): half the rows suffice.
    // The hexagonal lattice has no such symmetry.
    const bool mirror = p.lattice == LatticeKind::rectangular;
    for (int i = 0; i < p.grid; ++i)
      for (int j = 0; j < p.grid; ++j) {
        if (mirror && j < i) {
          pde[i][j] = pde[j][i];
          for (int f = 0; f < 2; ++f) disc[f][i][j] = disc[f][j][i];
          continue;
        }
        Eigen::Matrix2d F = Eigen::Matrix2d::Zero();
        F(0, 0) = p.stretch(i);
        F(1, 1) = p.stretch(j);
        pde[i][j] = pde_stable(*material, F) ? 1 : 0;
        for (int f = 0; f < 2; ++f) {
          if (!frames[f].on) continue;
          DispersionSetup s;
          s.lattice = p.lattice;
          s.spacing = 1;
          s.frame = frames[f].kind;
          s.material = material;
          s.density = p.density;
          s.deformation = F;
          const double a = cpu_seconds();
          BlochRow row;
          try {
            row = bloch_row(c.method, s);
          } catch (const SingularError&) {
            // The kernel's support, fixed in the frame it is written in, holds too few
            // particles of the deformed lattice (Eulerian kernel under large stretch): the
            // discrete model does not exist there.
            setup_time += cpu_seconds() - a;
            disc[f][i][j] = kBreakdown;
            continue;
          }
          setup_time += cpu_seconds() - a;
          evaluations += row.force_evaluations;
          rows += 1;
          translated += row.translated ? 1 : 0;
          if (sample.offset.empty()) sample = row;
          const StabilityVerdict v = stability_verdict(row, thetas, p.points, p.mu0, p.density, false);
          disc[f][i][j] = v.unstable ? 0 : 1;
        }
      }
    if (sample.offset.empty())
      throw SingularError(fmt::format("{} has no discretization at any state of the grid",
                                      c.spec.method));

    r.particles = sample.patch_particles;
    r.h = 1;
    r.dim = 2;
    r.components = 2;
    r.method_description = sample.description;
    FigureData& an = r.emplace<FigureData>();
    std::string angles;
    for (double a : p.angles) angles += fmt::format("{}{:g}°", angles.empty() ? "" : ", ", a);
    an.setup = fmt::format(
        "{} lattice, Δx = 1, patch of {} particles (half width {}), neighbours within {:.2f} Δx; "
        "{}; F0 = diag(λ1, λ2), λ1, λ2 on a {}×{} grid in [{:g}, {:g}] (plane strain, the stress "
        "is the material's at F0, no separate prestress); ρ = {:g}; frames: {}; discrete "
        "stability: ω² ≥ 0 at {} wave numbers from 0 to the zone boundary along θ = {} (a "
        "spurious zero counts as stable); PDE: strong ellipticity over 720 directions; {} force "
        "evaluations ({} of {} rows by translation: K_0J from the centre's perturbation, checked "
        "directly at two neighbours)",
        to_string(p.lattice), sample.patch_particles, sample.half_width, sample.influence_radius,
        material->description(2), p.grid, p.grid, p.lambda_min, p.lambda_max, p.density,
        p.lagrangian && p.eulerian ? "Lagrangian and Eulerian kernels"
        : p.lagrangian            ? "Lagrangian kernel"
                                 : "Eulerian kernel",
        p.points, angles, evaluations, translated, rows);

    // Table codes: 1 stable, 0 unstable, -1 no discretization, NaN frame not run.
    auto code = [](int d) { return d == -1 ? NAN : d == kBreakdown ? -1.0 : double(d); };
    FigureData::Table table{"stretch-map", {"lambda1", "lambda2", "pde", "lagrangian", "eulerian"}, {}};
    for (int i = 0; i < p.grid; ++i)
      for (int j = 0; j < p.grid; ++j)
        table.rows.push_back({p.stretch(i), p.stretch(j), double(pde[i][j]),
                              code(disc[0][i][j]), code(disc[1][i][j])});
    an.tables.push_back(std::move(table));

    // PDE map.
    {
      an.figures.push_back({"pde", "Strong ellipticity of the rubber material (001 Fig. 1, PDE)",
                            "λ1", "λ2", false, "points"});
      FigureData::Curve st{"pde", "PDE stable", {}, {}}, un{"pde", "PDE unstable", {}, {}};
      for (int i = 0; i < p.grid; ++i)
        for (int j = 0; j < p.grid; ++j) {
          auto& cv = pde[i][j] ? st : un;
          cv.x.push_back(p.stretch(i));
          cv.y.push_back(p.stretch(j));
        }
      for (auto* cv : {&st, &un})
        if (!cv->x.empty()) an.curves.push_back(std::move(*cv));
    }

    const int states = p.grid * p.grid;
    int pde_stable_count = 0;
    for (int i = 0; i < p.grid; ++i)
      for (int j = 0; j < p.grid; ++j) pde_stable_count += pde[i][j];
    r.headline[kStates] = states;
    r.headline[kPdeStable] = pde_stable_count;
    for (int f = 0; f < 2; ++f) {
      if (!frames[f].on) continue;
      const std::string Name = f == 0 ? "Lagrangian" : "Eulerian";
      const std::string id = std::string("map-") + frames[f].name;
      an.figures.push_back({id,
                            fmt::format("Stable states, {} kernel, against the PDE (001 Fig. 1)", Name),
                            "λ1", "λ2", false, "points"});
      FigureData::Curve both{id, "stable (PDE and discrete)", {}, {}},
          only_pde{id, "PDE stable, discrete unstable", {}, {}},
          only_disc{id, "PDE unstable, discrete stable", {}, {}},
          neither{id, "unstable (PDE and discrete)", {}, {}},
          none{id, "no discrete model (support lost its particles)", {}, {}};
      int stable = 0, pde_not = 0, disc_not = 0, broken = 0;
      for (int i = 0; i < p.grid; ++i)
        for (int j = 0; j < p.grid; ++j) {
          const bool pd = pde[i][j], d = disc[f][i][j] == 1;
          auto& cv = disc[f][i][j] == kBreakdown ? none
                     : pd && d                   ? both
                     : pd                        ? only_pde
                     : d                         ? only_disc
                                                 : neither;
          cv.x.push_back(p.stretch(i));
          cv.y.push_back(p.stretch(j));
          if (disc[f][i][j] == kBreakdown) {
            ++broken;
            continue;
          }
          stable += d;
          pde_not += pd && !d;
          disc_not += d && !pd;
        }
      for (auto* cv : {&both, &only_pde, &only_disc, &neither, &none})
        if (!cv->x.empty()) an.curves.push_back(std::move(*cv));
      r.headline[f == 0 ? kLagStable : kEulStable] = stable;
      r.headline[f == 0 ? kPdeNotLag : kPdeNotEul] = pde_not;
      r.headline[f == 0 ? kLagNotPde : kEulNotPde] = disc_not;
      r.headline[f == 0 ? kLagBreak : kEulBreak] = broken;
      r.headline[f == 0 ? kLagAgree : kEulAgree] =
          states > broken ? double(states - broken - pde_not - disc_not) / (states - broken) : 0.0;
      an.verdicts.push_back(fmt::format(
          "{} kernel: {} of {} states stable ({} PDE-stable); {} PDE-stable but discretely "
          "unstable, {} PDE-unstable but discretely stable{}",
          Name, stable, states, pde_stable_count, pde_not, disc_not,
          broken ? fmt::format("; no discrete model at {} states (the kernel support, fixed in "
                               "the current configuration, holds too few particles)",
                               broken)
                 : ""));
    }
    r.cpu.assembly = setup_time;
    r.cpu.solve = cpu_seconds() - t0 - setup_time;
  }
};

}  // namespace

void register_stretch_map_analysis(AnalysisRegistry& r) {
  r.add("stretch-map",
        "stable domains in the principal-stretch plane: strong ellipticity of the material "
        "against the method's Lagrangian and Eulerian lattice dispersion (001 Fig. 1)",
        {}, [](const Params&) { return std::make_unique<StretchMap>(); });
}

}  // namespace mfv
