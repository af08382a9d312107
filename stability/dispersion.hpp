/// Von Neumann (Bloch-wave) dispersion analysis of any registered method, computed from the
/// method's own explicit-dynamics internal force instead of a hand-derived formula:
///   K_0J = ∂f_0/∂u_J          central differences of ExplicitDynamics::trial_force on a
///                             lattice patch (Eulerian kernels: tables recomputed at the
///                             perturbed positions, so the kernel's motion enters),
///   D(κ) = Σ_J K_0J e^{iκ·(X_J − X_0)},   M(κ) = m_0 (lumped) or Σ_J M_0J e^{iκ·(X_J−X_0)},
///   D(κ) φ = ω² M(κ) φ                 (000 eqs 3.10, 3.22 and their 2D counterparts).
/// A unit cell of every lattice holds one particle (stress points carry no unknowns), so
/// the centre particle's row of the stiffness is the whole infinite-lattice operator.
/// The closed forms of 000 (stability/closed_forms.hpp) are cross-checks of this.
#pragma once
#include <complex>
#include <memory>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "dynamics/explicit.hpp"
#include "methods/materials/material.hpp"
#include "methods/methods/method.hpp"
#include "stability/lattice.hpp"

namespace mfv {

/// What is analysed: the lattice, the kernel frame, the material and the uniform state.
struct DispersionSetup {
  LatticeKind lattice = LatticeKind::line;
  double spacing = 1;
  KernelFrame frame = KernelFrame::lagrangian;
  std::shared_ptr<const Material> material;
  double density = 1;
  /// Uniform prestress S₀ (dim × dim; the Cauchy stress at F = I), or empty for none.
  Eigen::MatrixXd prestress;
  /// Uniform deformation F₀ the state is linearized about (dim × dim), or empty for I.
  Eigen::MatrixXd deformation;
  bool consistent_mass = false;  ///< Σ_q w_q ρ N_0 N_J (Galerkin methods) instead of ρ V_0
  int half_width = 0;            ///< patch half width in spacings; 0: from the supports
  double step = 1e-6;            ///< finite-difference step over the spacing
  /// K_0J from the centre's perturbation alone, by the lattice's translation invariance
  /// (K_0J = K_{P,0} with X_P = X_0 − (X_J − X_0)): 2·dim force evaluations instead of
  /// 2·dim per neighbour, on a patch wide enough that every such P sees only interior
  /// particles, and checked against direct differences at two neighbours (a discretization
  /// that is not translation invariant falls back to the direct row). false: always direct.
  bool by_translation = true;
};

/// The centre particle's row of the linearized operator: blocks K_0J and offsets X_J − X_0.
struct BlochRow {
  int dim = 1;
  std::vector<Eigen::VectorXd> offset;  ///< reference offsets of the neighbours J
  std::vector<Eigen::MatrixXd> stiffness;  ///< K_0J, dim × dim
  std::vector<double> mass;     ///< consistent M_0J (empty: lumped)
  double lumped_mass = 0;       ///< m_0 = ρ V_0
  double spacing = 1;
  LatticeKind lattice = LatticeKind::line;
  int patch_particles = 0, half_width = 0, force_evaluations = 0;
  bool translated = false;      ///< K_0J came from the centre's perturbation (by_translation)
  double influence_radius = 0;  ///< neighbours taken, in spacings
  std::string description;      ///< the method's composition on the patch

  /// ω² branches at wave vector κ (real parts, ascending) and the largest |Im ω²| (non-zero
  /// for non-symmetric operators: Petrov–Galerkin, Eulerian kernels).
  std::vector<double> omega2(const Eigen::VectorXd& kappa, double* imaginary = nullptr) const;
  /// The row of a + s·(b − a): the operator is affine in the prestress, so two rows give
  /// every stress level (stable-domain maps).
  static BlochRow combine(const BlochRow& a, const BlochRow& b, double s);
};

/// Builds the lattice patch, discretizes `method` on it, and differentiates the engine's
/// internal force at the centre particle. Throws InputError for methods or settings the
/// analysis cannot take (a consistent mass of a collocation method, a bad lattice).
BlochRow bloch_row(const Method& method, const DispersionSetup& setup);

/// ω²(κ) along direction θ from κ = 0 to the Brillouin-zone boundary.
struct DispersionBranch {
  double theta = 0;             ///< radians
  std::vector<double> kappa;    ///< in units of π/Δx
  std::vector<std::vector<double>> omega2;  ///< per κ: branches ascending (units (c π/Δx)²)
  std::vector<double> imaginary;            ///< per κ: largest |Im ω²|, same units
};
/// Samples `points` wave numbers per direction; ω² normalized by (c π/Δx)² with c² = `modulus`/ρ.
DispersionBranch dispersion_branch(const BlochRow& row, double theta, int points,
                                   double modulus, double density);

/// What the dispersion relation says (tolerance: ω² within 1e-7 (c π/Δx)² of zero is zero).
struct StabilityVerdict {
  bool unstable = false;      ///< ω² < 0 at some κ
  bool spurious = false;      ///< ω² = 0 at some κ away from 0 (a zero-energy mode)
  double onset = NAN;         ///< smallest unstable κ (π/Δx), refined by bisection
  double onset_theta = NAN;   ///< its direction (degrees)
  double spurious_kappa = NAN, spurious_theta = NAN;
  double min_ratio = NAN;     ///< min over κ > 0.02 π/Δx of ω²/(c κ)²
  double cutoff_omega = NAN;  ///< ω at the zone boundary of θ = the first direction, / (c π/Δx)
  std::string text;           ///< "stable", "spurious mode at κ = 1.000 π/Δx (θ = 0°)", ...
};
/// Scans every direction; `tension` names an instability "tensile" in the text.
StabilityVerdict stability_verdict(const BlochRow& row, const std::vector<double>& thetas,
                                   int points, double modulus, double density, bool tension);
/// The scan behind stability_verdict for any lowest branch ω²(κ, θ) in (c π/Δx)², κ in π/Δx
/// (a lattice patch's, or a closed form's): `points` samples from 0 to `zone_boundary(θ)`
/// along each θ (radians), the onset refined by bisection, ω² within 1e-7 of zero counted as
/// zero.
StabilityVerdict scan_stability(const std::vector<double>& thetas, int points, bool tension,
                                const std::function<double(double theta)>& zone_boundary,
                                const std::function<double(double kn, double theta)>& lowest);

/// Stable-domain threshold (000 Figs 5–6): for each κ along θ, the normalized stresses
/// s at which min ω² of a + s (b − a) crosses zero, searched in [−limit, limit]: the lowest
/// stable s below 0 and the highest above (NaN where the whole range is stable or unstable).
struct ThresholdCurve {
  std::vector<double> kappa, lower, upper;
};
ThresholdCurve stress_threshold(const BlochRow& unstressed, const BlochRow& stressed,
                                double theta, int points, double limit, double modulus,
                                double density);

}  // namespace mfv
