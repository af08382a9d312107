/// Closed-form von Neumann dispersion relations of the corrected-derivative particle method of
/// 000 (Belytschko & Xiao 2002) §3–4: Shepard trial and test functions w_I = W/ΣW (eq 2.7),
/// corrected derivatives G_iI = a_ij w_{I,j} (eqs 2.12–2.20) for the deformation gradient,
/// lumped mass m = ρV (eq 2.22), infinite uniform lattice. They are independent cross-checks of
/// the generic numerical dispersion analysis (stability/dispersion.*): lattice sums written out
/// from the paper's equations, no matrices assembled.
///
/// Conventions (000 §2.2): the paper's weight is W(s), s = r/h, h = D_mx Δx the support radius.
/// An mfv Kernel evaluates W at s_mfv = r/a with W = 0 for s_mfv >= support(); the paper's
/// weight is W_paper(r) = kernel(r · support() / h), so any registered kernel can be used
/// ("quartic-spline" is eq 2.8 and "exponential" eq 2.9, both with support() = 1). A lattice
/// point exactly at r = h (e.g. the outer stress points for D_mx = 1.5, 2.5) gets W = 0, the
/// kernel's own convention (the paper writes s <= 1; it matters only for the truncated
/// exponential, W(1) = e^{-6.25} = 0.0019).
/// On a uniform lattice ΣW(x − x_K) is periodic and, at nodes, interval midpoints, quad centres
/// and triangle centres, stationary by symmetry, so there ∇w_K = ∇W/S(x) with S(x) = ΣW the
/// (constant per kind of point) Shepard normalization. The correction factor is computed from
/// its definition at each kind of point: 1D a = 1/Σ_I w_{I,X} X_I (eq 2.20), 2D a = A^{-T} with
/// A_ij = Σ_I w_{I,j} X_Ii (eqs 2.14–2.16).
///
/// ──── Discrepancies between the printed equations and their derivation (closed_forms.md) ────
/// D1 (eqs 3.12, 3.23, small κ). Derived from eq 3.10 (and 3.22), 3.12 and 3.23 are correct as
///    printed. Because the test function derivative w_{I,X} is NOT corrected (Petrov–Galerkin:
///    only the trial gradient G = a w_{,X} is), Σ_j w_{,X}(jΔX) sin(κ jΔX) → −κ/a for small κ
///    and 3.12 gives ω²/κ² → C̄/(aρ0), not C̄/ρ0; 3.23 gives C̄/(2ρ0)(1/a_m + 1/a_s). a ≈ 1
///    (quartic spline, D_mx = 1.5: a = 1.03125), so the continuum wave speed is recovered only
///    to O(a − 1). The tests assert the exact discrete limit and report a − 1.
/// D2 (eq 3.18). Derived from 3.14–3.17: ω² = [a(C̄' + σ) T² − σ Σ_j w_{,xx}(jΔx)(1 − cos κjΔx)]/ρ,
///    T = Σ_j w_{,x} sin(κ jΔx), C̄' = C^{σT} + σ. This is algebraically the printed 3.18 (its
///    "+ σ a T²" inside the braces). The assumption of eq 3.16 is kept: the perturbed kernel
///    derivative is w_{I,xx}(x_J)(ũ_J − ũ_I), i.e. w_I is treated as a function of x − x_I
///    alone: the Shepard normalization ΣW and the correction factor a are frozen at their
///    values in the uniform state and do not change with the particle motion. Accordingly
///    w_{,xx} = W''/S0 (S0 = Σ_j W(jΔx)). With this reading the onset of the tensile
///    instability for the quartic spline, D_mx = 1.5, σ̄ = 1 is exactly κ = 0.5π/Δx (the paper
///    reads ≈ 0.6π/Δx off its Fig. 3): for D_mx = 1.5 only j = ±1 contribute and
///    3a·4w_{,x}² = 2w_{,xx} there, so ω² ∝ sin²(κΔx) − (1 − cos κΔx) < 0 ⇔ cos κΔx < 0.
///    Also: at the cut-off T = 0 and ω² = −(2σ/ρ) Σ_{j odd} w_{,xx}(jΔx), negative for any
///    σ > 0 with the quartic spline (w_{,xx} > 0 for 1/3 < s < 1), for D_mx = 1.5 and 2.5.
/// D3 (eq 4.3). Printed C̃_ijrl = C^SE_ikab F_rk F_js + S_il δ_jr has unmatched indices. From
///    P = S Fᵀ (P_ji = S_jk F_ik, the nominal stress of eq 2.2): Ṗ_ij = C^SE_ikal F_ra F_jk Ḟ_rl
///    + S_il Ḟ_jl (i the derivative index), i.e. C̄_ijrl = C^SE_ikal F_ra F_jk + S_il δ_jr,
///    which at F = I is eq 4.9.
/// D4 (eqs 4.6, 4.17, 4.20, 4.26). (a) The force is f_iI = Σ_J V_J w_{I,j} P̃_ji (eq 4.1), so the
///    tensor is contracted as w_{I,j} C̄_jirl, not w_{I,j} C̄_ijrl as printed (same for the
///    symmetric elastic part, different for the stress term S_il δ_jr). (b) The printed
///    "ω² = 1/(m(θ_X + θ_Y)) Σ_i ..." assumes the eigenvector is the longitudinal polarization
///    A_r = A θ_r and sums the two component equations; that is exact only where the lattice
///    does not couple the polarizations, returns one (polarization-mixed) value and divides by
///    zero at θ = 135°. We form the 2×2 dynamical matrix D_ir, m ω² A_i = D_ir A_r, and return
///    both eigenvalues. (c) eq 4.12's index k should be t; eq 4.23's ũ_t(x_J^m) should be
///    ũ_t(x_I^m) (the particle I of the equation).
/// D5 (eqs 4.10–4.17). σ̃ = C̄' : L̃ with C̄' of eq 4.16 (Truesdell rate) is correct; adding the
///    J̃ term of eq 4.10 cancels its −σ_ij δ_rl, so the tensor multiplying w_{I,j}(x_J) g_l is
///    E_jirl = C_jirl + δ_jr σ_li + σ_jl δ_ir (the "w_{I,j} σ_ij θ_t S_t" term of 4.17 is the
///    J̃ term). The w̃ term uses the same frozen-normalization assumption as D2.
#pragma once
#include <array>
#include <complex>

#include <Eigen/Dense>

namespace mfv {
class Kernel;
}

namespace mfv::closed_form {

// ───────────────────────────── 1D (000 §3) ─────────────────────────────

/// Correction factor a = 1/Σ_I w_{I,X}(X) X_I (eq 2.20) at a point of an infinite uniform 1D
/// lattice, offset (in units of Δx) from a particle: 0 = at a particle (a, a_m), 0.5 = at an
/// interval midpoint (stress point, a_s). Independent of Δx.
double correction_factor_1d(const Kernel& W, double dmx, double offset = 0.0);

/// Eq 3.12, Lagrangian kernel, nodal integration:
///   ω²(κ) = (a C̄/ρ0) [Σ_j w_{,X}(jΔX) sin(κ jΔX)]²,  w_{,X} = W'/Σ_j W(jΔX).
/// C̄ is the first elasticity modulus (eq 3.4; C̄ = C^{σT} + σ in the reference = current state).
double omega2_lagrangian_nodal_1d(const Kernel& W, double dmx, double dx, double kappa,
                                  double C_bar, double rho0);

/// Eq 3.18, Eulerian kernel, nodal integration, prestress σ (see D2 above):
///   ω² = (a C̄'/ρ) T² − (σ/ρ){Σ_j w_{,xx}(jΔx)[1 − cos(κ jΔx)] − a T²},
///   T = Σ_j w_{,x}(jΔx) sin(κ jΔx), C̄' = C^{σT} + σ (eq 3.17), w_{,xx} = W''/S0.
double omega2_eulerian_nodal_1d(const Kernel& W, double dmx, double dx, double kappa,
                                double C_sigmaT, double sigma, double rho);

/// Eq 3.23, Lagrangian kernel, stress points at interval midpoints (Voronoi volumes Δx/2 for
/// particles and stress points, mass ρ0Δx):
///   ω² = (C̄/(2ρ0)) [a_m (Σ_j w_{,X}(jΔX) sin κjΔX)² + a_s (Σ_j w̄_{,X}((j+½)ΔX) sin κ(j+½)ΔX)²],
/// w̄ the Shepard function at a midpoint (normalization Σ_j W((j+½)ΔX)), a_m, a_s eq 2.20 at a
/// particle and at a midpoint.
double omega2_lagrangian_stress_points_1d(const Kernel& W, double dmx, double dx, double kappa,
                                          double C_bar, double rho0);

/// Smallest κ in (0, π/Δx] with ω² < 0 in eq 3.18, in units of π/Δx (NaN if none). σ̄ =
/// σ/C^{σT}; c_sign = sign of C^{σT} (000 Figs 3 and 4). Scanned on 4000 wave numbers, then
/// bisected to 1e-12.
double onset_wavenumber_eulerian_1d(const Kernel& W, double dmx, double sigma_bar,
                                    double c_sign = 1.0);

/// What eq 3.18's w_{,xx}(jΔx) is (000 §3.1.2 leaves it open). `frozen`: the second
/// derivative of W(x − x_I)/S0 with the normalization fixed at its uniform value, as eq 3.16
/// (w̃_{I,x}(x_J) = w_{I,xx}(x_J)(ũ_J − ũ_I)) and the radial Hessian of eq 4.12 treat w_I: a
/// function of x_J − x_I alone. `shepard`: the second derivative of the Shepard function
/// w_I = W/ΣW itself (eq 2.7), d²/dx²[W(x − x_I)/S(x)] = W''/S − W S''/S² at a particle
/// (S' = 0 there). Quartic spline, D_mx = 1.5, σ̄ = 1: onset 0.500 (frozen), 0.471 (shepard).
enum class Normalization { frozen, shepard };

/// Eq 3.18 with w_{,xx} read as `n` (omega2_eulerian_nodal_1d is the frozen reading).
double omega2_eulerian_nodal_1d(const Kernel& W, double dmx, double dx, double kappa,
                                double C_sigmaT, double sigma, double rho, Normalization n);
/// Smallest κ in (0, π/Δx] with ω² < 0 in eq 3.18 read as `n`, C^{σT} > 0 (000 Fig. 3), in
/// π/Δx; NaN if none. Scanned on 4000 wave numbers, then bisected to 1e-12.
double onset_wavenumber_eulerian_1d(const Kernel& W, double dmx, double sigma_bar,
                                    Normalization n);
/// The same onset by a second route, without a scan: for 1 < D_mx <= 2 only the neighbours
/// j = ±1 enter eq 3.18, T = 2w'(Δx) sin κΔx, Q = 2w''(Δx)(1 − cos κΔx), and
///   ω²ρ/C^{σT} = (1 − cos κΔx)[4a(1 + 2σ̄) w'² (1 + cos κΔx) − 2σ̄ w''],
/// negative iff cos κΔx < β − 1, β = 2σ̄ w''/(4a(1 + 2σ̄) w'²): κ_onset = arccos(β − 1)/π
/// (NaN if β <= 0: stable; 0 if β >= 2). std::invalid_argument outside 1 < D_mx <= 2.
double onset_wavenumber_eulerian_three_point(const Kernel& W, double dmx, double sigma_bar,
                                             Normalization n);

/// The stress at which ω²(κ) = 0 (000 Figs 5–6): the response at κ is stable (ω² >= 0) for
/// σ̄ >= sigma_bar if stable_above, for σ̄ <= sigma_bar otherwise. sigma_bar is NaN where
/// ω² = 0 for every σ̄ (κ = 0, and the cut-off κ = π/Δx of eq 3.12), ±inf where ω² has the
/// same sign for every σ̄.
struct StressThreshold {
  double sigma_bar;
  bool stable_above;
};
/// Eq 3.12 with C̄ = C^{σT}(1 + σ̄): σ̄* = −1 at every κ (the exact material instability).
StressThreshold stable_threshold_lagrangian_1d(const Kernel& W, double dmx, double kappa_dx,
                                               double c_sign = 1.0);
/// Eq 3.18: ω²ρ/C^{σT} = aT² + σ̄(2aT² − Q), Q = Σ_j w_{,xx}(1 − cos κjΔx) (Δx = 1), so
/// σ̄* = aT²/(Q − 2aT²).
StressThreshold stable_threshold_eulerian_1d(const Kernel& W, double dmx, double kappa_dx,
                                             double c_sign = 1.0);

// ───────────────────────────── 2D (000 §4) ─────────────────────────────

enum class Lattice2D {
  rectangular,  ///< square lattice, spacing Δx; stress points at quadrilateral centres
  hexagonal     ///< triangular lattice (6 neighbours at Δx); stress points at triangle centres
};
enum class Frame { lagrangian, eulerian };

struct Setup2D {
  Lattice2D lattice = Lattice2D::rectangular;
  bool stress_points = false;  ///< false: nodal integration
  Frame frame = Frame::lagrangian;
  double dx = 1.0;   ///< nearest-neighbour spacing; the x axis is along a lattice vector
  double dmx = 1.5;  ///< support radius h = dmx·dx
  double lambda = 0.0, mu = 1.0;  ///< plane strain C_ijkl (eqs 4.8, 4.15)
  /// Prestress: S (PK2, eq 4.9) for the Lagrangian kernel, σ (Cauchy, eq 4.16) for the
  /// Eulerian; the current configuration is the reference one (F = I), so the two coincide.
  Eigen::Matrix2d stress = Eigen::Matrix2d::Zero();
  double rho = 1.0;
};

/// The 2×2 dynamical matrix D(k) with ω² A = D A for a plane wave ũ_K = A e^{i k·X_K + iωt}
/// (see D3–D5): D_ir = (1/m) Σ_q V_q [conj(g_j^q) E_jirl (a^q g^q)_l + eulerian w̃ term],
/// q over the kinds of integration points (particles; quad or triangle centres), g_k^q =
/// Σ_z w_{,k}(z) e^{−ik·z} over z = x_q − X_K, V_q Voronoi volumes (all equal: cell area /
/// points per cell), m = ρ·cell area. E = C + S_jl δ_ir (Lagrangian, eq 4.9), E = C + δ_jr σ_li
/// + σ_jl δ_ir (Eulerian, 4.16 + J̃).
Eigen::Matrix2cd dynamical_matrix_2d(const Kernel& W, const Setup2D& s, const Eigen::Vector2d& k);

/// The two ω² branches at wave number κ and direction θ (radians, from the x axis), ascending:
/// real parts of the eigenvalues of D (D is real symmetric except for the Eulerian kernel under
/// a non-isotropic σ, where it need not be symmetric).
std::array<double, 2> omega2_2d(const Kernel& W, const Setup2D& s, double kappa, double theta);

/// Named forms of omega2_2d: eq 4.6 (nodal, Lagrangian), 4.17 (nodal, Eulerian), 4.20 (stress
/// points, Lagrangian), 4.26 (stress points, Eulerian); they set stress_points and frame.
std::array<double, 2> omega2_lagrangian_nodal_2d(const Kernel& W, Setup2D s, double kappa,
                                                 double theta);
std::array<double, 2> omega2_eulerian_nodal_2d(const Kernel& W, Setup2D s, double kappa,
                                               double theta);
std::array<double, 2> omega2_lagrangian_stress_points_2d(const Kernel& W, Setup2D s,
                                                         double kappa, double theta);
std::array<double, 2> omega2_eulerian_stress_points_2d(const Kernel& W, Setup2D s,
                                                       double kappa, double theta);

/// Correction matrix a (eqs 2.14–2.16, a = A^{-T}) at a point offset from a particle of the
/// 2D lattice (offset in absolute units).
Eigen::Matrix2d correction_matrix_2d(const Kernel& W, const Setup2D& s,
                                     const Eigen::Vector2d& offset);

/// Continuum reference: eigenvalues (ascending) of the acoustic tensor
/// Q_ir = (C_jirl + S_jl δ_ir) k_j k_l / ρ, i.e. ρω² of the linearized PDE at F = I.
std::array<double, 2> omega2_continuum_2d(const Setup2D& s, double kappa, double theta);

// ──────────────── 003 §4.3.3: the α of eq 30 as DMAX grows ────────────────

/// The lumped cell masses of 003 §4.3.3: row sum (003's MLS2 without enrichment) and MLS1
/// (eq 16: m_I = Δx M_II/Σ_J M_JJ).
enum class CellLumping { row_sum, mls1 };

/// α∞ = lim_{DMAX→∞} λ_max(K_cell, M_cell) DMAX² (eqs 27–30 with E = ρ = Δx = 1) for one
/// interior integration cell of a uniform 1D bar, EFG with a linear basis and weight W whose
/// support radius is DMAX·Δx; `trimmed`: only the nodes whose middle half of the support
/// [0.25 s, 0.75 s] covers the cell (003's heuristic). Derivation: as DMAX → ∞ the linear-basis
/// MLS functions become Shepard functions, Φ_I(x) = φ(ξ_I)/R, φ = W/∫W, ξ_I = (x_I − x)/R
/// (the first moment and its derivative vanish on the lattice's continuum limit). Every Gauss
/// point of the cell sees the same φ to O(1/R), so K_cell → Δx g gᵀ (rank one, g_I = Φ'_I =
/// φ'(ξ_I)/R²) and λ_max = Δx Σ_I g_I²/m_I; the sum over nodes tends to R ∫ dξ:
///   row sum   m_I = ∫_cell Φ_I Σ_J Φ_J = Δx φ_I/R · P   ⇒  α∞ = (1/P) ∫ φ'²/φ dξ,
///   MLS1      m_I = Δx φ_I²/(R ∫φ²)                   ⇒  α∞ = ∫φ² · ∫ (φ'/φ)² dξ,
/// integrals over |ξ| <= 1 (<= 1/2 trimmed), P = ∫φ over the kept nodes (1 untrimmed). The
/// untrimmed MLS1 integrand (φ'/φ)² ~ (1 − |ξ|)^{-2} at the support's edge is not integrable:
/// +∞ (the "very small contributions" that 003 says enlarge λ). Cubic spline: 12.4629 (row
/// sum), 7.0504 (row sum trimmed), 9.9658 (MLS1 trimmed); 003: 12.46, 7.1, 10.
double cell_alpha_limit(const Kernel& W, CellLumping lumping, bool trimmed);

}  // namespace mfv::closed_form
