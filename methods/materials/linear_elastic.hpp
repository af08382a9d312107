/// Linear isotropic elasticity in 2D: plane stress or plane strain, Voigt notation
/// σ = D ε with ε = (ε_xx, ε_yy, γ_xy), σ = (σ_xx, σ_yy, σ_xy).
#pragma once
#include <string>

#include <Eigen/Dense>

namespace mfv {

struct LinearElastic {
  double E = 1, nu = 0;
  bool plane_strain = false;

  /// The 3 × 3 elasticity matrix D.
  Eigen::Matrix3d D() const;
  /// Stresses (3 × n, Voigt) from displacement gradients (4 × n rows ∂u_x/∂x, ∂u_x/∂y,
  /// ∂u_y/∂x, ∂u_y/∂y).
  Eigen::MatrixXd stress(const Eigen::MatrixXd& grad) const;
  /// Voigt strains (3 × n) from displacement gradients.
  static Eigen::MatrixXd strain(const Eigen::MatrixXd& grad);
  /// Twice the strain energy density, ε·Dε (one per column), from displacement gradients:
  /// the integrand of the energy norm ‖u‖²_E = ∫ ε·Dε.
  Eigen::VectorXd energy_density(const Eigen::MatrixXd& grad) const;
  std::string describe() const;
};

}  // namespace mfv
