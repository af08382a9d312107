/// The `dispersion` problem as a definition: an infinite line, rectangular or hexagonal
/// lattice under a uniform prestress σ̄, a kernel frame and the directions and mass to
/// analyse (000 §3–4). The `dispersion` analysis (analyses/dispersion.cpp) runs it on any
/// method. Units: Δx = 1, ρ = 1, St Venant–Kirchhoff with E = 1; σ̄ = σ/E in 1D and σ/μ in 2D.
#pragma once
#include <string>
#include <vector>

#include "methods/materials/material.hpp"
#include "problems/problem.hpp"
#include "stability/dispersion.hpp"

namespace mfv {

/// Headline values of a dispersion case: what the analysis measures and the findings read.
namespace dispersion_headline {
inline constexpr const char* kUnstable = "unstable";
inline constexpr const char* kSpurious = "spurious mode";
inline constexpr const char* kOnset = "onset kappa (pi/dx)";
inline constexpr const char* kSpuriousKappa = "spurious kappa (pi/dx)";
inline constexpr const char* kMinRatio = "min omega2/(c kappa)^2";
inline constexpr const char* kCutoff = "cutoff omega (c pi/dx)";
/// With map=sigma-kappa: the prestress range stable at every κ and direction, σ̄ (σ/E on the
/// line, σ/μ in 2D); ∓map_limit when nothing within the limit destabilizes that side.
inline constexpr const char* kCompressionBound = "compression limit (sigma bar)";
inline constexpr const char* kTensionBound = "tension limit (sigma bar)";
/// 000 eq 3.18 (what Fig. 3 plots) for the kbm-ni method's kernel and D_mx, in the two
/// readings of its w_{,xx} (stability/closed_forms.hpp, Normalization): scanned, and by the
/// three-point arccos formula (a second route, 1 < D_mx <= 2).
inline constexpr const char* kOnsetFrozen = "onset kappa eq 3.18 frozen normalization (pi/dx)";
inline constexpr const char* kOnsetShepard = "onset kappa eq 3.18 Shepard w'' (pi/dx)";
inline constexpr const char* kOnsetFrozenArccos =
    "onset kappa eq 3.18 frozen normalization, arccos (pi/dx)";
inline constexpr const char* kOnsetShepardArccos = "onset kappa eq 3.18 Shepard w'', arccos (pi/dx)";
}  // namespace dispersion_headline

/// The lattice study a dispersion case runs.
struct DispersionDefinition {
  LatticeKind lattice = LatticeKind::line;
  KernelFrame frame = KernelFrame::lagrangian;
  double sigma = 0;        ///< σ̄
  bool biaxial = true;     ///< 2D: σ̄ in xx and yy (else xx only)
  double nu = 0.25;        ///< 2D plane-strain Poisson's ratio
  std::vector<double> angles;  ///< wave directions θ in degrees
  bool consistent_mass = false;
  bool map = false;        ///< also the stable domain in the (σ̄, κ) plane
  double map_limit = 3;
  int half_width = 0;      ///< patch half width in spacings (0: from the supports)
  /// ω² from 000's closed forms (stability/closed_forms.hpp) instead of the method's own
  /// linearized force: a second route to the same verdicts, for kbm-ni and kbm-si where 000
  /// derives them (eqs 3.12, 3.18, 3.23, 4.6, 4.17, 4.20, 4.26).
  bool closed_form = false;

  int dim() const { return lattice == LatticeKind::line ? 1 : 2; }
  /// E in 1D, μ in 2D: the modulus σ̄ and the frequencies are normalized by.
  double modulus() const { return dim() == 1 ? 1.0 : 1.0 / (2 * (1 + nu)); }
  /// The Bloch-analysis set-up at prestress σ̄ (material from `materials`).
  DispersionSetup setup(const MaterialRegistry& materials, double sigma_bar) const;
};

class DispersionProblem final : public Problem {
 public:
  explicit DispersionProblem(const Params& p);
  const DispersionDefinition& definition() const { return def_; }

  Domain domain() const override {
    return def_.lattice == LatticeKind::line ? Domain::interval(-1, 1)
                                             : Domain::rectangle(-1, -1, 1, 1);
  }
  std::vector<std::string> analyses() const override { return {"dispersion"}; }
  /// The resolution of an analysis on an infinite lattice is its sampling of κ.
  std::string resolution_name() const override { return "wave numbers per direction"; }
  std::vector<int> resolutions(Level) const override { return {101}; }
  std::vector<PublishedValue> published() const override;
  std::vector<std::string> published_notes() const override;
  std::vector<Finding> findings() const override;

 private:
  DispersionDefinition def_;
};

}  // namespace mfv
