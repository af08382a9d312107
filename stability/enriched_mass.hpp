/// Stiffness, the mass matrices of 003 §4 and the critical step of an extended EFG
/// discretization (columns: particles, then enrichments), shared by `enriched-bar` and tests.
///
/// K = Σ_q w_q Bᵀ D B (1D: E N_I' N_J'); consistent M = ρ Σ_q w_q N_I N_J (003 eq 13);
/// row sum M_I = Σ_J M_IJ; MLS1 (003 eqs 14-16, Hinton's lumping per background cell h):
/// m_I = Σ_h ϑ_h ∫_h ρ Ñ_I², ϑ_h = ∫_h ρ / Σ_I ∫_h ρ Ñ_I² over every column, enriched or not;
/// MLS2 (003 eqs 19-22, kinetic-energy preserving): ordinary columns by row sum over the
/// ordinary columns (∫ ρ N_I), an enriched column ψ N_I gets its node's mass times the
/// N_I²-weighted mean of ψ² (eq 21; for the step H² = 1 this is eq 22's M̂'_I = M̂_I).
/// Δt = 2/√λ_max of K φ = λ M φ (003 eq 12).
#pragma once
#include <Eigen/Dense>

#include "methods/methods/method.hpp"

namespace mfv {

enum class MassScheme { consistent, row_sum, mls1, mls2 };

/// 1D: E·A with A = 1; 2D: plane stress or strain, thickness 1.
struct BarMaterial {
  double E = 200e9, rho = 7850, nu = 0.3;
  bool plane_strain = false;
};

/// Dense K over (N + enriched_unknowns) × components unknowns, components interleaved.
Eigen::MatrixXd enriched_stiffness(const Discretization& d, const BarMaterial& m);
/// The mass matrix of a scheme (dense; diagonal for the lumped ones). MLS2 needs the
/// discretization's trial approximation to be an EnrichedApproximation when it has
/// enrichment columns.
/// mls1_per_point: eq 16's ϑ per Gauss point instead of per background cell.
Eigen::MatrixXd enriched_mass(const Discretization& d, const BarMaterial& m, MassScheme s,
                              bool mls1_per_point = false);
/// MLS2 with eq 21 read over the region where an enrichment acts (a reading 003 leaves open):
/// M̂'_I = ∫_Ω ψ²ρ dΩ / Σ_{J=1}^{N} ψ(X_J)² (eq 21), scaled so that the step (ψ² = 1) keeps
/// eq 22's M̂'_I = M̂_I: an enriched column ψ_K N_I gets its node's row-sum mass times
///   (mean of ψ_K² over the Gauss points where ψ_K acts) / (mean of ψ_K² over the particles
///   there),
/// "where ψ_K acts" being the union of the supports of the nodes it enriches. enriched_mass's
/// MLS2 instead weights the mean of ψ² by N_I² over node I's own support; the two agree for
/// the step and differ for the branch functions (√r ...), whose ψ² is small near the tip.
Eigen::MatrixXd enriched_mass_mls2_region(const Discretization& d, const BarMaterial& m);

/// λ_max of K φ = λ M φ (M diagonal: eigenvalues of M^{-1/2} K M^{-1/2}); +∞ when M is not
/// positive definite (a lumped mass with a non-positive entry has no stable step).
double largest_eigenvalue(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M, bool diagonal);
/// 2/√λ_max.
double critical_step(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M, bool diagonal);

}  // namespace mfv
