/// Stability of the continuum (the PDE) for a material state: strong ellipticity of the
/// linearized momentum equation, the reference for the discrete stable domains of 001 Fig. 1
/// (principal-stretch map of the `rubber` material). Implemented in closed_forms.cpp.
#pragma once
#include <Eigen/Dense>

namespace mfv {

class Material;

/// A(i + 2J, k + 2L) = ∂P_iJ/∂F_kL (2D, plane strain for the materials that model it), by
/// central differences of Material::first_piola with step `step`·max(1, |F_kL|).
Eigen::Matrix4d tangent_modulus_2d(const Material& material, const Eigen::Matrix2d& F,
                                   double step = 1e-6);

/// min over directions n = (cos θ, sin θ), θ = π d/directions, of the smallest eigenvalue of the
/// acoustic tensor Q_ik(n) = A_iJkL n_J n_L (its symmetric part).
double min_acoustic_eigenvalue(const Material& material, const Eigen::Matrix2d& F,
                               int directions = 720);

/// Strong ellipticity: Q(n) positive definite for every scanned direction (smallest eigenvalue
/// above 1e-9 of the largest |A| entry). F is the 2D deformation gradient (elastic materials:
/// no history state is passed).
bool pde_stable(const Material& material, const Eigen::Matrix2d& F, int directions = 720);

}  // namespace mfv
