/// The standard remedies of weakly compressible free-surface flow (issue 43, item 2), as
/// options of the explicit engine's Eulerian kernel, off by default (every result without them
/// bit for bit as before). They act on a fluid's density, which the engine keeps as
///   ρ_q = ρ_ref,q / J_q,   J_q = det F_q,
/// at every integration point q (particles and stress points for kbm-si, the particles for the
/// nodal rules, Gauss points for the cell rules); ρ_ref is the material's `reference_density`
/// slot (the `tait` water's hydrostatic density) or the model's density. A remedy that changes
/// ρ_q sets it by scaling F_q isotropically, F_q ← (ρ_q / ρ̃_q)^{1/D} F_q: each point keeps its
/// mass w0_q ρ_ref,q, and only its volume w0_q J_q changes, as an SPH particle keeps m and
/// changes V = m/ρ. The sums run over the points at their current positions x_q with their
/// current volumes V_q = w0_q J_q and an SPH kernel of their own: Wendland's C2 (2D, support 2h),
///   W(r, h) = 7/(4π h²) (1 − q/2)⁴ (2q + 1),  q = r/h < 2,   h = 1.2 Δx
/// (the SPH convention h/Δx = 1.2-1.3; its support 2.4 Δx is kbm's default dmax), so they act
/// identically for every method. 2D, Eulerian kernel, native engine.
///
/// (b) Density re-initialization (Colagrossi & Landrini 2003, "Numerical simulation of
///     interfacial flows by smoothed particle hydrodynamics", J. Comput. Phys. 191, 448-475,
///     §2.4): every `every` steps the density is replaced by its kernel average,
///       shepard: ρ̃_i = Σ_j ρ_j W_ij V_j / Σ_j W_ij V_j       (zeroth order),
///       mls:     ρ̃_i = Σ_j ρ_j W^MLS_ij V_j,  W^MLS_ij = (β_0 + β·(x_i − x_j)) W_ij,
///                A_i (β_0, β) = (1, 0), A_i = Σ_j W_ij V_j [1, r_ij; r_ij, r_ij ⊗ r_ij]
///     (first order: a linear density, the hydrostatic stratification, is kept exactly; a point
///     whose A_i is singular falls back to Shepard).
/// (c) Density diffusion, δ-SPH (Molteni & Colagrossi 2009, "A simple procedure to improve the
///     pressure evaluation in hydrodynamic context using the SPH", Comput. Phys. Commun. 180,
///     861-872; Antuono, Colagrossi, Marrone & Molteni 2010, "Free-surface flows solved by
///     means of SPH schemes with numerical diffusive terms", Comput. Phys. Commun. 181,
///     532-549): a diffusive term in the continuity equation, integrated at every step,
///       dρ_i/dt += D_i = δ h c0 Σ_j ψ_ij · ∇_i W_ij V_j,
///       ψ_ij = 2 (ρ_j − ρ_i) (x_j − x_i)/|x_j − x_i|²                         (molteni)
///              − (⟨∇ρ⟩_i^L + ⟨∇ρ⟩_j^L)                                      (antuono, default)
///     with the renormalized gradient ⟨∇ρ⟩_i^L = L_i Σ_j (ρ_j − ρ_i) ∇_i W_ij V_j,
///     L_i = [Σ_j ∇_i W_ij ⊗ (x_j − x_i) V_j]⁻¹ (the uncorrected sum where that matrix is
///     near-singular, det < 0.1). ψ_ij is symmetric and ∇_i W_ij antisymmetric in (i, j), so
///     Σ_i V_i D_i = 0: the term moves density between points and creates none; Antuono's ψ
///     vanishes for a linear density (no drift of a hydrostatic state). c0 is the material's
///     wave speed, δ = 0.1 the usual value.
/// (d) Particle shifting (Xu, Stansby & Laurence 2009, "Accuracy and stability in
///     incompressible SPH (ISPH) based on the projection method and a new approach", J. Comput.
///     Phys. 228, 6703-6725; Lind, Xu, Stansby & Rogers 2012, "Incompressible smoothed particle
///     hydrodynamics for free-surface flows: a generalised diffusion-based algorithm for
///     stability and validations for impulsive flows and propagating waves", J. Comput. Phys.
///     231, 1499-1523): at every recomputation of the tables the particles (the kernels'
///     centres) move by
///       δr_I = −D h² ∇C_I,   C_I = Σ_J W_IJ Δx²   (the particle concentration, 1.02 on the
///     square lattice), capped at 0.1 Δx per move, towards lower concentration (a particle
///     displaced by ε from the square lattice moves back by about 0.88 D ε); a particle with
///     C_I < `surface` (the free surface and the walls' first rows: 0.82 at a flat free
///     surface, 1.02 one row down), or with such a particle within 2h (Lind et al.'s
///     vicinity of the free surface, whose rows the missing side would pull outwards), keeps
///     only the part tangential to it, δr ← (I − n n) δr, n = ∇C_I/|∇C_I|; so does a particle
///     within 2h of a rigid wall (penalty walls,
///     DynamicsModel::rigid_walls), along the wall's normal: the concentration misses the
///     wall's side there as at a free surface, and the shift would push the rows next to the
///     wall into it (measured: the funnel's second row at its 45° walls, C = 0.978, moved
///     0.02 Δx towards the wall per move and blew up by 0.015 s); held particles (prescribed
///     velocities: wall particles) do not move. The
///     fields follow by Lind's first-order Taylor correction, v_I += (∇v)(x_I) δr_I (the trial
///     gradient at the particle) and ρ_q += ⟨∇ρ⟩_q^L · δx_q at every point the move displaces.
///     `xu` (shifting_form): Xu et al.'s own shift, a repulsion of the nearest neighbours,
///       δr_I = D α Σ_J (r̄_I² / r_IJ²) n_IJ,  n_IJ = (x_I − x_J)/r_IJ,  α = U_max Δt_s,
///     r̄_I the mean distance to the neighbours within 2h, U_max the largest particle speed
///     and Δt_s the time since the last move (D = 0.01-0.1: Xu's C); it grows as 1/r² where
///     two particles close up, where the Fickian shift's ∇C vanishes with W′(0) = 0 (measured:
///     pairs 0.001 Δx apart in the funnel's variational runs, which the Fickian shift does not
///     part). The same cap, surface and wall projections.
///     The unknowns u_I move by δr_I (the supports' centres, KernelCentres::coefficients; with
///     `interpolated` they move by Σ_J N_J(X_I) δr_J). Nodal and stress-point rules (the
///     velocity gradient is read at the particles' own points).
/// None of them books its energy: a remedy changes the stored, kinetic or potential energy
/// without a force doing work, and the energy balance reports that as an error.
#pragma once
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "dynamics/fluid_remedy_options.hpp"

namespace mfv {

/// The remedies' smoothing length over the spacing, h = 1.2 Δx.
inline constexpr double kRemedySmoothing = 1.2;
/// The largest shift per move, over the spacing.
inline constexpr double kMaxShift = 0.1;

namespace remedies {

/// Wendland's C2 kernel in 2D (support 2h) and dW/dr.
double kernel(double r, double h, double* dw = nullptr);

/// The pairs of a point cloud (2 × m) within the kernel's support 2h, each point's list in
/// ascending index and including the point itself. The operators below build them, or take
/// them from a caller that applies several to the same cloud. Per-point loops run on `threads`
/// OpenMP threads (each point's sums in a fixed order: the same bits on any count).
struct Pairs {
  Pairs(const Eigen::MatrixXd& x, double h, int threads = 1);
  std::vector<int> offsets, index;
  int threads = 1;
};

/// The re-initialized densities of the cloud (x, V, ρ) by `kind` (shepard or mls).
Eigen::VectorXd filtered_density(const Eigen::MatrixXd& x, const Eigen::VectorXd& volume,
                                 const Eigen::VectorXd& rho, double h, DensityFilter kind);
Eigen::VectorXd filtered_density(const Pairs& pairs, const Eigen::MatrixXd& x,
                                 const Eigen::VectorXd& volume, const Eigen::VectorXd& rho,
                                 double h, DensityFilter kind);
/// ⟨∇ρ⟩^L at every point (2 × m).
Eigen::MatrixXd density_gradient(const Eigen::MatrixXd& x, const Eigen::VectorXd& volume,
                                 const Eigen::VectorXd& rho, double h);
Eigen::MatrixXd density_gradient(const Pairs& pairs, const Eigen::MatrixXd& x,
                                 const Eigen::VectorXd& volume, const Eigen::VectorXd& rho,
                                 double h);
/// The diffusive term D_i of the continuity equation (δ h c0 Σ_j ψ_ij · ∇_i W_ij V_j).
Eigen::VectorXd density_diffusion(const Eigen::MatrixXd& x, const Eigen::VectorXd& volume,
                                  const Eigen::VectorXd& rho, double h, double c0, double delta,
                                  DiffusionForm form);
Eigen::VectorXd density_diffusion(const Pairs& pairs, const Eigen::MatrixXd& x,
                                  const Eigen::VectorXd& volume, const Eigen::VectorXd& rho,
                                  double h, double c0, double delta, DiffusionForm form);
/// Forward-Euler sub-steps the diffusion takes over a step dt: its fastest mode (the
/// particle/stress-point checkerboard) decays at about 4.64 δ h c0 / Δx² (Wendland, h = 1.2 Δx,
/// measured on the square lattice with its cell centres), stable for a sub-step below 2 over
/// it; the sub-steps keep it below 1 (the fluid problems' step, 0.8 Δx/c0, needs 2 from
/// δ = 0.23).
int diffusion_substeps(double delta, double h, double c0, double dt, double dx);
/// C_I = Σ_J W_IJ Δx² over the particles x (2 × N).
Eigen::VectorXd concentration(const Eigen::MatrixXd& x, double h, double dx);
/// The shifts δr_I (2 × N) of the particles x: −D h² ∇C_I, capped at kMaxShift Δx, tangential
/// only where C_I < surface or a neighbour's is, zero where `held`; `wall_normal` (2 × N, or empty) removes, where
/// a column is not zero, the component along it (a rigid wall's normal at the particle);
/// `xu`: Xu et al.'s δr_I = D α Σ_J (r̄_I²/r_IJ²) n_IJ instead of the Fickian −D h² ∇C_I.
Eigen::MatrixXd shifts(const Eigen::MatrixXd& x, double h, double dx, double D, double surface,
                       const std::vector<char>& held, const Eigen::MatrixXd& wall_normal = {},
                       ShiftingForm form = ShiftingForm::fickian, double alpha = 0);

}  // namespace remedies
}  // namespace mfv
