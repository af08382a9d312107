/// Variationally consistent integration (VCI, linear order; Chen, Hillman & Rüter 2013, IJNME
/// 95, not a method of 001): a constant vector ξ_I per particle added to the test-function
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
#pragma once
#include <memory>

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

/// Adds ξ_I to every test-gradient entry of particle I in d.test_q. The trial table is left
/// alone (a Galerkin method becomes Petrov–Galerkin in its gradients). Throws InputError when
/// a particle with a defect has no quadrature weight in its support.
void apply_vci(Discretization& d);

/// The decorator: discretize with `inner`, then apply_vci. Eulerian retabulation is refused
/// (the boundary rule is the reference box, not the deformed boundary).
std::unique_ptr<Method> with_vci(std::unique_ptr<Method> inner);

}  // namespace mfv
