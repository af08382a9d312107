/// Gradient operators of the particle methods of 001 Table 1 (SPH, Randles–Libersky,
/// Krongauz–Belytschko), as shape tables: row q lists G_J(x_q) with ∇u_h(x_q) = Σ_J G_J u_J.
/// They are built from kernel tables of CorrectedKernelApproximation (sph, shepard, mls) with
/// the same particles, dilations and kernel, so every table has the same neighbour lists.
#pragma once
#include "methods/approximations/shape_table.hpp"
#include "methods/particles.hpp"

namespace mfv {

/// Symmetrized SPH gradient at the particles (001 eq 25, Table 1 row SPH):
/// ∇u(X_I) = Σ_J V_J (u_J - u_I) ⊗ ∇W(X_I - X_J). `sph_at_particles` is the plain SPH table
/// (values W(X_I - X_J) V_J and their gradients) at the particles; the result has values δ_IJ
/// (the unknowns are the particle displacements) and the symmetrized gradients.
ShapeTable sph_symmetric_gradient(const ShapeTable& sph_at_particles);
/// The same into `out` in place (storage reused), rows spread over `threads` OpenMP threads;
/// equal bit for bit on any thread count. Likewise the in-place forms below.
void sph_symmetric_gradient(const ShapeTable& sph_at_particles, ShapeTable& out, int threads);
/// The same with the SPH table turned into the gradient table where it lies (the rows are the
/// same); equal bit for bit to the forms above.
void sph_symmetric_gradient_in_place(ShapeTable& sph_at_particles, int threads);

/// Randles–Libersky normalized gradient (001 eqs 33–34): c_IJ = V_J Bᵀ_I ∇W(X_I - X_J),
/// B_I⁻¹ = Σ_J V_J (X_J - X_I) ⊗ ∇W(X_I - X_J), so linear fields are differentiated exactly.
/// `trial` holds F_I = Σ_J (u_J - u_I) ⊗ c_IJ; `test` the internal force of Table 1 row RLM,
/// f_I = -V_I Σ_J (σ_J + σ_I) · c_IJ, written as f_I = Σ_q V_q H_I(X_q) · σ_q so every
/// method assembles Σ_q w_q H_I(x_q)ᵀ σ_q. Throws SingularError where B_I⁻¹ is singular.
/// With `degenerate` (Eulerian recomputations that ask for it) a singular B_I⁻¹ (too few or
/// collinear neighbours, the same determinant test) takes B_I = I instead, the plain SPH
/// gradient of eq 25 at that particle: constants still give zero gradients and the force
/// stays the transpose, so splashes go on at zero-order consistency; an isolated particle's
/// row has only itself and gets zero gradients. The particle is marked there.
struct RandlesLiberskyTables {
  ShapeTable trial, test;
};
RandlesLiberskyTables randles_libersky(const ShapeTable& sph_at_particles,
                                       const ParticleSet& particles);
void randles_libersky(const ShapeTable& sph_at_particles, const ParticleSet& particles,
                      RandlesLiberskyTables& out, int threads,
                      DegenerateMarks* degenerate = nullptr);

/// Krongauz–Belytschko corrected gradient (001 eqs 26–32): G_I(x) = a(x) · ∇W^S_I(x) with
/// a = M⁻¹, M = Σ_I ∇W^S_I(x) ⊗ X_I, so Σ_I G_I ⊗ X_I = I (eq 29). `shepard` is the Shepard
/// table at the points (order >= 1). Returns a table with the values of `values` (the trial
/// functions: MLS in KBM, eq 63) and the corrected gradients. Both tables must share
/// neighbour lists. Throws SingularError where M is singular.
/// With `degenerate` (Eulerian recomputations that ask for it), marking the points there:
/// a singular or ill-conditioned M (the same determinant test) takes a = I, the plain
/// Shepard gradient ∇W^S_I, which still sums to zero (zero-order consistency) where the
/// correction has too few or collinear particles to act on; a point whose Shepard row sums
/// to zero (an empty support, the Shepard fallback of CorrectedKernelApproximation) gets
/// zero values and gradients, so it gives no velocity gradient and receives no force.
ShapeTable corrected_gradient(const ShapeTable& shepard, const ShapeTable& values,
                              const ParticleSet& particles, const Eigen::MatrixXd& points);
void corrected_gradient(const ShapeTable& shepard, const ShapeTable& values,
                        const ParticleSet& particles, const Eigen::MatrixXd& points,
                        ShapeTable& out, int threads, DegenerateMarks* degenerate = nullptr);

}  // namespace mfv
