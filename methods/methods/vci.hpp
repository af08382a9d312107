/// Variationally consistent integration (VCI; Chen, Hillman & Rüter 2013, IJNME 95, not a
/// method of 001), of linear or quadratic order.
///
/// Linear order (vci=true or vci=linear): a constant vector ξ_I per particle added to the test-function
/// gradient at every quadrature point of the particle's support so that the quadrature
/// satisfies the divergence identity of the test functions with the boundary rule the
/// tractions and multipliers use,
///   Σ_q w_q (∇Ψ_I(x_q) + ξ_I) = Σ_b w_b Ψ_I(x_b) n_b,   ξ_I = d_I / Σ_{q ∋ I} w_q,
/// where d_I = Σ_b w_b Ψ_I(x_b) n_b − Σ_q w_q ∇Ψ_I(x_q) is the identity's defect. A linear
/// field then gives a constant stress whose internal force equals its boundary traction, so
/// the patch test passes whatever the quadrature. Applied as a decorator over any method's
/// test-gradient table (nodal, stress-point or cell rules alike). The patch test needs the
/// identity's boundary rule to be where the boundary forces act: nodal and stress-point rules
/// put tractions and multipliers on the same particles (kbm-ni/si, efg-ni and rlm then pass to
/// round-off); Gauss-cell rules integrate tractions on their own boundary points while the
/// multipliers sit at the particles, so there VCI keeps the identity but not the patch test.
///
/// Quadratic order (vci=quadratic; Chen, Hillman & Rüter 2013 §4, their "quadratically
/// consistent" correction): the test gradient becomes ∇Ψ_I + ξ_I + η_I (x − x_I), ξ_I a vector
/// and η_I a dim × dim matrix, chosen so that the quadrature also satisfies the second
/// divergence identity, the one a linear stress field needs,
///   Σ_q w_q [∇Ψ̃_I(x_q) x_qᵀ + Ψ_I(x_q) 𝟙] = Σ_b w_b Ψ_I(x_b) n_b x_bᵀ,
/// besides the first. Why it is needed (issue 43): test functions that are not linearly
/// complete (KBM's Shepard functions, 001 eq 28) leave the interior quadrature inconsistent
/// at second order, Σ_q w_q (Ψ_I′ x_q + Ψ_I) ≠ 0 at every interior particle, so the scheme
/// converges to −E_eff u″ = f with E_eff ≠ E and its error stalls (measured in 1D at dmax 2.4:
/// E_eff/E − 1 = 2.6e-3 with stress points; tests/reference/kbm_1d.py). The linear correction
/// leaves that defect; the quadratic one removes both. Per particle and component c the
/// unknowns (ξ_c, η_c·) solve the moment system
///   [m0  m1ᵀ] [ξ_c ]   [d1_c            ]    m0 = Σ_{q∋I} w_q, m1 = Σ w_q r_q, M2 = Σ w_q r_q r_qᵀ,
///   [m1  M2 ] [η_cᵀ] = [d2_c·ᵀ − x_I d1_c],  r_q = x_q − x_I,
/// d1 and d2 the defects of the two identities.
#pragma once
#include <memory>
#include <string>

#include <Eigen/Dense>

#include "methods/methods/method.hpp"

namespace mfv {

/// The defect d_I of the divergence identity for every particle (dim × particles), over all
/// sides of the domain, with the discretization's own test table, weights and boundary rule.
Eigen::MatrixXd divergence_defect(const Discretization& d);

/// Summary of a defect: the largest and the root-mean-square |d_I| over the particles, each
/// relative to the particle's Σ_q w_q |∇Ψ_I(x_q)| (the size of the sums that should cancel).
struct DefectSummary {
  double max_relative = 0;
  double rms_relative = 0;
  int worst_particle = -1;
};
DefectSummary summarize_defect(const Discretization& d, const Eigen::MatrixXd& defect);

/// The order of the correction.
enum class VciOrder { linear, quadratic };
/// "linear" (or "true") and "quadratic"; InputError naming the choices otherwise.
VciOrder vci_order_from(const std::string& name);

/// The defect of the second identity, d2_I = Σ_b w_b Ψ_I n_b x_bᵀ − Σ_q w_q [∇Ψ_I x_qᵀ + Ψ_I 𝟙],
/// for every particle: (dim·dim) × particles, row c·dim + e for entry (c, e).
Eigen::MatrixXd second_divergence_defect(const Discretization& d);

/// Adds the correction of `order` to every test-gradient entry of particle I in d.test_q.
/// The trial table is left alone (a Galerkin method becomes Petrov–Galerkin in its
/// gradients). Throws InputError when a particle with a defect has no quadrature weight in its
/// support, or (quadratic) too few points there to fix a linear correction.
void apply_vci(Discretization& d, VciOrder order = VciOrder::linear);

/// The decorator: discretize with `inner`, then apply_vci. Eulerian retabulation is refused
/// (the boundary rule is the reference box, not the deformed boundary).
std::unique_ptr<Method> with_vci(std::unique_ptr<Method> inner,
                                 VciOrder order = VciOrder::linear);

}  // namespace mfv
