/// `time-step`: the critical time step of central differences for any registered method,
/// Δt_crit = 2/√λ_max of K φ = λ M φ with K the explicit engine's own tangent stiffness
/// (stability/critical_step.hpp) and M the lumped or the consistent mass.
///
/// geometry=bar: the 004 III §6 bar (E = 3e7 psi, ρ = 7.24e-4 slug/in³, A = 1 in², L = 100 in,
/// 21 nodes 5 in apart: FEM Δt = l/c = 2.455e-5 s), fixed at x = 0 (ends=fixed) or free.
/// geometry=block: a 2:1 plane-strain rectangle lattice (E = 1, ν = 0.25, ρ = 1, L = 1), left
/// side fixed or all free, for the 2D methods. Δt is also printed over Δx/c (c the
/// dilatational wave speed): linear FEM gives 1 (lumped) and 1/√3 (consistent) in 1D.
///
/// For rkpm the analysis adds the GRK table of 004 III §5.2 (our Δt for j = −1, 0, 1 beside the
/// paper's analytic and numeric columns), Δt against the dilation index j, and the kernel
/// stability count of 004 III §5.1 (nodes under a Gaussian window, eq 5.1.3).
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "problems/time_step.hpp"

namespace mfv {

using namespace time_step_headline;

double grk_critical_step_eq525(double r, double dx, double c) {
  const bool ok = std::isfinite(r) && std::isfinite(dx) && std::isfinite(c) && r > 0 && dx > 0 &&
                  c > 0;
  if (!ok) return NAN;
  const double l = dx;  // the element length of the FEM step l/c the paper compares with
  return std::sqrt(2.0) * (l / c) * std::sqrt(std::sqrt(2 * std::numbers::pi) * r / dx);
}

TimeStepProblem::TimeStepProblem(const Params& p) {
  def_.block = p.text("geometry") == "block";
  def_.mass = p.text("mass");
  def_.fixed = p.text("ends") == "fixed";
  def_.frame = kernel_frame_from(p.text("frame"));
  def_.sweep = p.text("sweep") == "on";
}

std::vector<PublishedValue> TimeStepProblem::published() const {
    std::vector<PublishedValue> out;
    const Params bar = Params::parse("geometry=bar,ends=fixed");
    out.push_back({"004 III §5.2", kLumped, "fem", Params{}, 21, 2.455e-5,
                   "FEM Δt = l/c quoted beside the GRK table", bar});
    for (const auto& row : kGrkTable) {
      Params mp;
      mp.set("j", row[0]);
      mp.set("kernel", "gaussian");
      mp.set("rule", "eq6.10");
      out.push_back({"004 III §5.2 table (numeric)", kLumped, "rkpm", mp, 21, row[2],
                     "'numeric' column: eigenvalue of K − λM, mass not stated", bar});
      out.push_back({"004 III §5.2 table (analytic, eq 5.2.5)", kLumped, "rkpm", mp, 21, row[1],
                     "'analytic' column, eq 5.2.5 (a one-node estimate)", bar});
    }
    return out;
}

std::vector<std::string> TimeStepProblem::published_notes() const {
    return {
        "004 III §5.2 does not say which mass its 'numeric' critical steps use, how the fixed "
        "end is imposed on the non-interpolating GRK functions, nor the quadrature of K (we use "
        "the rkpm plugin's Gauss cells). Its eq 5.2.5 ('analytic') is printed with garbled "
        "factors in our copy (l, r, dx and Φ' vs Φ). Column eq525_ours evaluates it under a "
        "stated reading (problems/time_step.hpp: eqs 5.2.3–5.2.4 with the r² kept and the "
        "interior continuous sum of eq 5.2.7), which gives √2·2^((j+1)/2) l/c; the printed "
        "column is 2^((j+1)/2) l/c, a factor √2 (λ_max doubled) below it at every j. Both "
        "columns are printed beside our lumped- and consistent-mass eigenvalues, never "
        "substituted.",
        "The paper's numeric Δt grows faster with j than its analytic one (j = 1: 5.651e-5 vs "
        "4.912e-5); a wider window lowers the highest frequency the discretization carries, and "
        "how far depends on the window truncation and the boundary correction, which the paper "
        "leaves open.",
        "The §5.1 kernel stability count n = 1 + √(−2 ln R/π)·2^{j+1} is reproduced exactly; "
        "R is the window height at the edge of its significant support over its peak "
        "(e^{−4}, e^{−9}: support edge at 2r, 3r), not the 2 and 3 standard deviations the "
        "labels suggest.",
    };
}

void register_time_step(ProblemRegistry& r) {
  ParamSchema s{
      ParamSpec::choice("geometry", "bar", {"bar", "block"},
                        "bar: the 004 III §6 bar (1D, 21 nodes, 5 in); block: 2:1 plane-strain "
                        "rectangle lattice (2D methods)"),
      ParamSpec::choice("mass", "both", {"lumped", "consistent", "both"},
                        "mass matrix: lumped (particle masses), consistent (Galerkin methods), "
                        "both"),
      ParamSpec::choice("ends", "fixed", {"fixed", "free"},
                        "fixed: x = 0 (bar) or the left side (block) held; free: no support"),
      ParamSpec::choice("frame", "lagrangian", {"lagrangian", "eulerian"},
                        "kernel frame of the engine whose force is linearized"),
      ParamSpec::choice("sweep", "on", {"on", "off"},
                        "rkpm: Δt against j from -1.5 to 1.5 (adds 7 analyses)"),
  };
  r.add("time-step",
        "critical time step 2/omega_max of central differences for any method: K from the "
        "explicit engine's force, lumped or consistent mass; the 004 III §5 GRK table and "
        "window count",
        s, [](const Params& p) { return std::make_unique<TimeStepProblem>(p); });
}

}  // namespace mfv
