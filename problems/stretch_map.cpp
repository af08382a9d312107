/// `stretch-map`: the stable domains of 001 Fig. 1 in the space of the principal stretches
/// (λ1, λ2) of the hyperelastic `rubber` material (001 eq 18, 000 eq 5.1), for the PDE
/// (strong ellipticity, stability/material_stability.hpp) and for any 2D method with a
/// Lagrangian and an Eulerian kernel. Each state is the uniform deformation F0 = diag(λ1, λ2)
/// of an infinite lattice; the method's explicit engine is moved there (Lagrangian: total
/// Lagrangian F; Eulerian: tables at the deformed positions) and its internal force is
/// linearized by central differences (stability/dispersion.hpp). The stress is the
/// material's at F0 (no separate prestress). A state is discretely stable when ω² ≥ 0 for
/// every sampled wave vector; a spurious zero (ω² = 0 away from κ = 0) counts as stable.
/// Units: Δx = 1, the paper's c1, c2, λ and ρ = 125.4; ω² normalized by (c π/Δx)² with
/// c² = μ0/ρ, μ0 = c1 + c2 (the small-strain shear modulus).
#include <cmath>
#include <numbers>
#include <sstream>

#include <fmt/format.h>

#include "methods/core/errors.hpp"
#include "problems/problem.hpp"
#include "stability/dispersion.hpp"
#include "stability/material_stability.hpp"
#include "verify/catalogue.hpp"
#include "verify/runner.hpp"

namespace mfv {

namespace {

constexpr int kBreakdown = -2;  ///< no discrete model: the kernel support lost its particles
constexpr const char* kStates = "states";
constexpr const char* kPdeStable = "PDE-stable states";
constexpr const char* kLagStable = "Lagrangian-stable states";
constexpr const char* kEulStable = "Eulerian-stable states";
constexpr const char* kPdeNotLag = "states PDE-stable but Lagrangian-unstable";
constexpr const char* kPdeNotEul = "states PDE-stable but Eulerian-unstable";
constexpr const char* kLagNotPde = "states PDE-unstable but Lagrangian-stable";
constexpr const char* kEulNotPde = "states PDE-unstable but Eulerian-stable";
constexpr const char* kLagBreak = "states without a Lagrangian discretization";
constexpr const char* kEulBreak = "states without an Eulerian discretization";
constexpr const char* kLagAgree = "fraction of states where Lagrangian agrees with PDE";
constexpr const char* kEulAgree = "fraction of states where Eulerian agrees with PDE";

class StretchMap final : public Problem {
 public:
  explicit StretchMap(const Params& p)
      : lattice_(lattice_kind_from(p.text("lattice"))),
        lambda_min_(p.number("lambda_min")),
        lambda_max_(p.number("lambda_max")),
        grid_(p.integer("grid")),
        lagrangian_(p.text("frames") != "eulerian"),
        eulerian_(p.text("frames") != "lagrangian"),
        angles_(parse_angles_degrees(p.text("angles"))),
        points_(p.integer("points")),
        density_(p.number("density")),
        material_params_(Params::parse(fmt::format("c1={},c2={},lambda={}", p.number("c1"),
                                                   p.number("c2"), p.number("lambda")))),
        mu0_(p.number("c1") + p.number("c2")) {
    if (lattice_ == LatticeKind::line)
      throw InputError("stretch-map needs a 2D lattice (two principal stretches): use "
                       "lattice=rectangular or lattice=hexagonal");
    if (!(lambda_min_ > 0))
      throw InputError(fmt::format("lambda_min = {} must be positive (a stretch)", lambda_min_));
    if (!(lambda_max_ > lambda_min_))
      throw InputError(fmt::format("lambda_max = {} must exceed lambda_min = {}", lambda_max_,
                                   lambda_min_));
    if (grid_ < 2) throw InputError(fmt::format("grid = {} must be at least 2", grid_));
    if (points_ < 3) throw InputError(fmt::format("points = {} must be at least 3", points_));
  }

  Domain domain() const override { return Domain::rectangle(-1, -1, 1, 1); }
  int components() const override { return 2; }
  AssembledSystem assemble(const Discretization&) const override {
    throw std::logic_error("stretch-map is an analysis: the runner calls analyse");
  }
  bool analysis() const override { return true; }
  std::string resolution_name() const override { return "states per stretch axis (the grid parameter)"; }
  std::vector<int> resolutions(Level) const override { return {grid_}; }

  void analyse(const AnalysisContext& c, CaseResult& r) const override;
  std::vector<std::string> published_notes() const override;
  std::vector<Finding> findings() const override;

 private:
  double stretch(int i) const { return lambda_min_ + (lambda_max_ - lambda_min_) * i / (grid_ - 1); }

  LatticeKind lattice_;
  double lambda_min_, lambda_max_;
  int grid_;
  bool lagrangian_, eulerian_;
  std::vector<double> angles_;
  int points_;
  double density_;
  Params material_params_;
  double mu0_;
};

void StretchMap::analyse(const AnalysisContext& c, CaseResult& r) const {
  const double pi = std::numbers::pi;
  const double t0 = cpu_seconds();
  const std::shared_ptr<const Material> material =
      c.catalogue.materials.create("rubber", material_params_);
  std::vector<double> thetas;
  for (double a : angles_) thetas.push_back(a * pi / 180);
  struct Frame {
    bool on;
    KernelFrame kind;
    const char* name;
  };
  const Frame frames[2] = {{lagrangian_, KernelFrame::lagrangian, "lagrangian"},
                           {eulerian_, KernelFrame::eulerian, "eulerian"}};
  // stable[f][i][j]: frame f at (λ1, λ2) = (stretch(i), stretch(j)); -1 = not computed.
  std::vector<std::vector<int>> pde(grid_, std::vector<int>(grid_, 0));
  std::vector<std::vector<std::vector<int>>> disc(
      2, std::vector<std::vector<int>>(grid_, std::vector<int>(grid_, -1)));
  double setup_time = 0;
  BlochRow sample;
  int evaluations = 0;
  // The square lattice (and its cell-centre stress points) is symmetric under x ↔ y and the
  // material is isotropic, so (λ2, λ1) has the verdicts of (λ1, λ2): half the rows suffice.
  // The hexagonal lattice has no such symmetry.
  const bool mirror = lattice_ == LatticeKind::rectangular;
  for (int i = 0; i < grid_; ++i)
    for (int j = 0; j < grid_; ++j) {
      if (mirror && j < i) {
        pde[i][j] = pde[j][i];
        for (int f = 0; f < 2; ++f) disc[f][i][j] = disc[f][j][i];
        continue;
      }
      Eigen::Matrix2d F = Eigen::Matrix2d::Zero();
      F(0, 0) = stretch(i);
      F(1, 1) = stretch(j);
      pde[i][j] = pde_stable(*material, F) ? 1 : 0;
      for (int f = 0; f < 2; ++f) {
        if (!frames[f].on) continue;
        DispersionSetup s;
        s.lattice = lattice_;
        s.spacing = 1;
        s.frame = frames[f].kind;
        s.material = material;
        s.density = density_;
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
        if (sample.offset.empty()) sample = row;
        const StabilityVerdict v = stability_verdict(row, thetas, points_, mu0_, density_, false);
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
  AnalysisData& an = r.analysis;
  std::string angles;
  for (double a : angles_) angles += fmt::format("{}{:g}°", angles.empty() ? "" : ", ", a);
  an.setup = fmt::format(
      "{} lattice, Δx = 1, patch of {} particles (half width {}), neighbours within {:.2f} Δx; "
      "{}; F0 = diag(λ1, λ2), λ1, λ2 on a {}×{} grid in [{:g}, {:g}] (plane strain, the stress "
      "is the material's at F0, no separate prestress); ρ = {:g}; frames: {}; discrete "
      "stability: ω² ≥ 0 at {} wave numbers from 0 to the zone boundary along θ = {} (a "
      "spurious zero counts as stable); PDE: strong ellipticity over 720 directions; {} force "
      "evaluations",
      to_string(lattice_), sample.patch_particles, sample.half_width, sample.influence_radius,
      material->description(2), grid_, grid_, lambda_min_, lambda_max_, density_,
      lagrangian_ && eulerian_ ? "Lagrangian and Eulerian kernels"
      : lagrangian_            ? "Lagrangian kernel"
                               : "Eulerian kernel",
      points_, angles, evaluations);

  // Table codes: 1 stable, 0 unstable, -1 no discretization, NaN frame not run.
  auto code = [](int d) { return d == -1 ? NAN : d == kBreakdown ? -1.0 : double(d); };
  AnalysisData::Table table{"stretch-map", {"lambda1", "lambda2", "pde", "lagrangian", "eulerian"}, {}};
  for (int i = 0; i < grid_; ++i)
    for (int j = 0; j < grid_; ++j)
      table.rows.push_back({stretch(i), stretch(j), double(pde[i][j]),
                            code(disc[0][i][j]), code(disc[1][i][j])});
  an.tables.push_back(std::move(table));

  // PDE map.
  {
    an.figures.push_back({"pde", "Strong ellipticity of the rubber material (001 Fig. 1, PDE)",
                          "λ1", "λ2", false, "points"});
    AnalysisData::Curve st{"pde", "PDE stable", {}, {}}, un{"pde", "PDE unstable", {}, {}};
    for (int i = 0; i < grid_; ++i)
      for (int j = 0; j < grid_; ++j) {
        auto& cv = pde[i][j] ? st : un;
        cv.x.push_back(stretch(i));
        cv.y.push_back(stretch(j));
      }
    for (auto* cv : {&st, &un})
      if (!cv->x.empty()) an.curves.push_back(std::move(*cv));
  }

  const int states = grid_ * grid_;
  int pde_stable_count = 0;
  for (int i = 0; i < grid_; ++i)
    for (int j = 0; j < grid_; ++j) pde_stable_count += pde[i][j];
  r.headline[kStates] = states;
  r.headline[kPdeStable] = pde_stable_count;
  for (int f = 0; f < 2; ++f) {
    if (!frames[f].on) continue;
    const std::string Name = f == 0 ? "Lagrangian" : "Eulerian";
    const std::string id = std::string("map-") + frames[f].name;
    an.figures.push_back({id,
                          fmt::format("Stable states, {} kernel, against the PDE (001 Fig. 1)", Name),
                          "λ1", "λ2", false, "points"});
    AnalysisData::Curve both{id, "stable (PDE and discrete)", {}, {}},
        only_pde{id, "PDE stable, discrete unstable", {}, {}},
        only_disc{id, "PDE unstable, discrete stable", {}, {}},
        neither{id, "unstable (PDE and discrete)", {}, {}},
        none{id, "no discrete model (support lost its particles)", {}, {}};
    int stable = 0, pde_not = 0, disc_not = 0, broken = 0;
    for (int i = 0; i < grid_; ++i)
      for (int j = 0; j < grid_; ++j) {
        const bool p = pde[i][j], d = disc[f][i][j] == 1;
        auto& cv = disc[f][i][j] == kBreakdown ? none
                   : p && d                    ? both
                   : p                         ? only_pde
                   : d                         ? only_disc
                                               : neither;
        cv.x.push_back(stretch(i));
        cv.y.push_back(stretch(j));
        if (disc[f][i][j] == kBreakdown) {
          ++broken;
          continue;
        }
        stable += d;
        pde_not += p && !d;
        disc_not += d && !p;
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

std::vector<std::string> StretchMap::published_notes() const {
  return {
      "001 Fig. 1 (reproduced from its ref. [47]) gives the stable domains as drawn boundaries "
      "only: it does not state the particle lattice, the kernel or its support size, the "
      "stress-point arrangement, the range of stretches, the wave numbers and directions "
      "scanned, or whether the plane-strain or a plane-stress reading of eq 18 is meant. We "
      "use a rectangular lattice with stress points at the cell centres, MLS (kbm-si) with a "
      "quartic spline of support 1.5 Δx unless told otherwise, plane strain (F33 = 1), and a "
      "state grid in [lambda_min, lambda_max]². Only the qualitative finding is compared.",
      "The PDE reference is strong ellipticity of the linearized momentum equation at F0 "
      "(the acoustic tensor positive definite in every direction); a discrete state is stable "
      "when no sampled Bloch wave has ω² < 0, so an ω² = 0 (spurious) mode is not counted as "
      "an instability."};
}

std::vector<const StudySummary*> with_frame(const std::vector<StudySummary>& all,
                                            const char* key) {
  std::vector<const StudySummary*> out;
  for (const auto& s : all) {
    if (s.headlines.empty()) continue;
    const auto& h = s.headlines.back();
    if (h.count(key) && h.count(kStates) && h.count(kPdeStable)) out.push_back(&s);
  }
  return out;
}

std::vector<Finding> StretchMap::findings() const {
  std::vector<Finding> f;
  f.push_back(
      {"001 §3.1, Fig. 1(a)",
       "MLS with stress points and a Lagrangian kernel: the stable domain in (λ1, λ2) almost "
       "coincides with the PDE's",
       "every Lagrangian study disagrees with the PDE on at most 10% of its states",
       [](const std::vector<StudySummary>& all) -> Verdict {
         int yes = 0, no = 0;
         std::string ours;
         for (const auto* s : with_frame(all, kLagAgree)) {
           const auto& h = s->headlines.back();
           const double agree = h.at(kLagAgree);
           (agree >= 0.9 ? yes : no) += 1;
           ours += fmt::format("{}{}: agrees on {:.0f}% of {:g} states ({:g} PDE-stable but "
                               "unstable, {:g} PDE-unstable but stable)",
                               ours.empty() ? "" : "; ", s->label, 100 * agree, h.at(kStates),
                               h.at(kPdeNotLag), h.at(kLagNotPde));
         }
         if (yes + no == 0) return {"not run", "no stretch-map study with the Lagrangian frame"};
         return {no == 0 ? "reproduced" : yes == 0 ? "not reproduced" : "partly", ours};
       }, "lagrangian-pde"});
  f.push_back(
      {"001 §3.1, Fig. 1(b)",
       "Eulerian kernel: a substantial region of states where the PDE is stable and the "
       "discretization is not",
       "every Eulerian study has at least 10% of its PDE-stable states (those with a discrete "
       "model) discretely unstable",
       [](const std::vector<StudySummary>& all) -> Verdict {
         int yes = 0, no = 0;
         std::string ours;
         for (const auto* s : with_frame(all, kPdeNotEul)) {
           const auto& h = s->headlines.back();
           // PDE-stable states that have an Eulerian discrete model: the discretely stable
           // ones less those the PDE calls unstable, plus the PDE-stable unstable ones.
           const double bad = h.at(kPdeNotEul);
           const double ps = h.at(kEulStable) - h.at(kEulNotPde) + bad;
           const double frac = ps > 0 ? bad / ps : 0;
           (frac >= 0.1 ? yes : no) += 1;
           ours += fmt::format("{}{}: {:g} of the {:g} PDE-stable states with a discrete model "
                               "unstable ({:.0f}%){}",
                               ours.empty() ? "" : "; ", s->label, bad, ps, 100 * frac,
                               h.count(kEulBreak) && h.at(kEulBreak) > 0
                                   ? fmt::format(", no discrete model at {:g} states",
                                                 h.at(kEulBreak))
                                   : "");
         }
         if (yes + no == 0) return {"not run", "no stretch-map study with the Eulerian frame"};
         return {no == 0 ? "reproduced" : yes == 0 ? "not reproduced" : "partly", ours};
       }, "eulerian-unstable-region"});
  return f;
}

}  // namespace

void register_stretch_map(ProblemRegistry& r) {
  ParamSchema s{
      ParamSpec::choice("lattice", "rectangular", {"rectangular", "hexagonal"},
                        "infinite uniform 2D lattice"),
      ParamSpec::choice("frames", "both", {"both", "lagrangian", "eulerian"},
                        "kernel frames mapped (001 Fig. 1: both)"),
      ParamSpec::number("lambda_min", 0.5, "smallest principal stretch of the grid (> 0)"),
      ParamSpec::number("lambda_max", 2.5, "largest principal stretch of the grid"),
      capped(ParamSpec::count("grid", 9, 2, "stretches per axis (grid × grid states; at most 201)"), 201),
      ParamSpec::choice("angles", "0:30:45:60:90", {},
                        "wave directions theta in degrees, colon-separated"),
      capped(ParamSpec::count("points", 41, 3, "wave numbers per direction, 0 to the zone boundary (at most 100000)"), 100000),
      ParamSpec::positive("density", 125.4, "kg/m^3 (001 §3.1)"),
      ParamSpec::positive("c1", 1.265e5, "rubber c1, N/m^2 (001 eq 18)"),
      ParamSpec::positive("c2", 1.012e4, "rubber c2, N/m^2"),
      ParamSpec::positive("lambda", 1.012e7, "rubber lambda, N/m^2"),
  };
  r.add("stretch-map",
        "stable domains in the principal-stretch plane (lambda1, lambda2) of the rubber "
        "material: PDE (strong ellipticity) against any 2D method with Lagrangian and Eulerian "
        "kernels (001 §3.1, Fig. 1)",
        s, [](const Params& p) { return std::make_unique<StretchMap>(p); });
}

}  // namespace mfv
