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
#include "problems/stretch_map.hpp"

namespace mfv {

using namespace stretch_map_headline;

StretchMapProblem::StretchMapProblem(const Params& p) {
  def_.lattice = lattice_kind_from(p.text("lattice"));
  def_.lambda_min = p.number("lambda_min");
  def_.lambda_max = p.number("lambda_max");
  def_.grid = p.integer("grid");
  def_.lagrangian = p.text("frames") != "eulerian";
  def_.eulerian = p.text("frames") != "lagrangian";
  def_.angles = p.numbers("angles");
  def_.points = p.integer("points");
  def_.density = p.number("density");
  def_.material_params = Params::parse(fmt::format("c1={},c2={},lambda={}", p.number("c1"),
                                                   p.number("c2"), p.number("lambda")));
  def_.mu0 = p.number("c1") + p.number("c2");
  if (def_.lattice == LatticeKind::line)
    throw InputError("stretch-map needs a 2D lattice (two principal stretches): use "
                     "lattice=rectangular or lattice=hexagonal");
  if (!(def_.lambda_min > 0))
    throw InputError(fmt::format("lambda_min = {} must be positive (a stretch)", def_.lambda_min));
  if (!(def_.lambda_max > def_.lambda_min))
    throw InputError(fmt::format("lambda_max = {} must exceed lambda_min = {}", def_.lambda_max,
                                 def_.lambda_min));
  if (def_.grid < 2) throw InputError(fmt::format("grid = {} must be at least 2", def_.grid));
  if (def_.points < 3) throw InputError(fmt::format("points = {} must be at least 3", def_.points));
}


std::vector<std::string> StretchMapProblem::published_notes() const {
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

namespace {

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

}  // namespace

std::vector<Finding> StretchMapProblem::findings() const {
  std::vector<Finding> f;
  f.push_back(
      {"001 §3.1, Fig. 1(a)",
       "MLS with stress points and a Lagrangian kernel: the stable domain in (λ1, λ2) almost "
       "coincides with the PDE's",
       "every Lagrangian study disagrees with the PDE on at most 10% of its states",
       [](const std::vector<StudySummary>& all) -> Verdict {
         int yes = 0, no = 0;
         std::string ours;
         std::vector<FindingNumber> numbers;
         for (const auto* s : with_frame(all, kLagAgree)) {
           const auto& h = s->headlines.back();
           const double agree = h.at(kLagAgree);
           // One map per study: its uncertainty is the converged check's (a finer grid).
           numbers.push_back({s->label + ": fraction agreeing with the PDE", {NAN}, {agree}});
           (agree >= 0.9 ? yes : no) += 1;
           ours += fmt::format("{}{}: agrees on {:.0f}% of {:g} states ({:g} PDE-stable but "
                               "unstable, {:g} PDE-unstable but stable)",
                               ours.empty() ? "" : "; ", s->label, 100 * agree, h.at(kStates),
                               h.at(kPdeNotLag), h.at(kLagNotPde));
         }
         if (yes + no == 0) return {"not run", "no stretch-map study with the Lagrangian frame"};
         return {no == 0 ? "reproduced" : yes == 0 ? "not reproduced" : "partly", ours, numbers};
       }, "lagrangian-pde"});
  // 001 Fig. 1(b): "dashed and solid lines bound the stable domains for Lagrangian and
  // Eulerian kernels" and "for the Eulerian kernel we can see a substantial domain (indicated
  // by grayscale in Fig. 1) where the material should be stable but the discrete model is
  // not": inside the PDE's stable domain the figure shows two regions, the Eulerian kernel's
  // own stable domain (bounded by a line: a region, not a point) and the grey one. On a grid of
  // states each is a substantial part (at least 10 %) of the PDE-stable states that have a
  // discrete model. A map whose Eulerian kernel is stable only at the stress-free identity
  // has the grey region but no Eulerian domain: partly.
  f.push_back(
      {"001 §3.1, Fig. 1(b)",
       "Eulerian kernel: a substantial region of states where the PDE is stable and the "
       "discretization is not, beside the Eulerian kernel's own stable domain",
       "of the PDE-stable states with a discrete model, at least 10% Eulerian-unstable (the "
       "grey region) and at least 10% Eulerian-stable (the domain bounded by the solid line); "
       "the grey region alone: partly",
       [](const std::vector<StudySummary>& all) -> Verdict {
         int yes = 0, half = 0, no = 0;
         std::string ours;
         std::vector<FindingNumber> numbers;
         for (const auto* s : with_frame(all, kPdeNotEul)) {
           const auto& h = s->headlines.back();
           // PDE-stable states that have an Eulerian discrete model: the discretely stable
           // ones less those the PDE calls unstable, plus the PDE-stable unstable ones.
           const double bad = h.at(kPdeNotEul);
           const double good = h.at(kEulStable) - h.at(kEulNotPde);
           const double ps = good + bad;
           const double grey = ps > 0 ? bad / ps : 0, domain = ps > 0 ? good / ps : 0;
           const bool g = grey >= 0.1, d = domain >= 0.1;
           (g && d ? yes : g ? half : no) += 1;
           numbers.push_back({s->label + ": grey fraction", {NAN}, {grey}});
           numbers.push_back({s->label + ": Eulerian-stable fraction", {NAN}, {domain}});
           ours += fmt::format("{}{}: of the {:g} PDE-stable states with a discrete model {:g} "
                               "Eulerian-unstable ({:.0f}%), {:g} Eulerian-stable ({:.0f}%){}",
                               ours.empty() ? "" : "; ", s->label, ps, bad, 100 * grey, good,
                               100 * domain,
                               h.count(kEulBreak) && h.at(kEulBreak) > 0
                                   ? fmt::format(", no discrete model at {:g} states",
                                                 h.at(kEulBreak))
                                   : "");
         }
         if (yes + half + no == 0)
           return {"not run", "no stretch-map study with the Eulerian frame"};
         return {half + no == 0 ? "reproduced" : yes + half == 0 ? "not reproduced" : "partly",
                 ours, numbers};
       }, "eulerian-unstable-region"});
  return f;
}

void register_stretch_map(ProblemRegistry& r) {
  ParamSchema s{
      ParamSpec::choice("lattice", "rectangular", {"rectangular", "hexagonal"},
                        "infinite uniform 2D lattice"),
      ParamSpec::choice("frames", "both", {"both", "lagrangian", "eulerian"},
                        "kernel frames mapped (001 Fig. 1: both)"),
      ParamSpec::number("lambda_min", 0.5, "smallest principal stretch of the grid (> 0)"),
      ParamSpec::number("lambda_max", 2.5, "largest principal stretch of the grid"),
      capped(ParamSpec::count("grid", 9, 2, "stretches per axis (grid × grid states; at most 201)"), 201),
      ParamSpec::numbers("angles", {0, 30, 45, 60, 90}, "wave directions theta in degrees"),
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
        s, [](const Params& p) { return std::make_unique<StretchMapProblem>(p); });
}

}  // namespace mfv
