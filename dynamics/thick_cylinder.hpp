/// The references the 2D ring runs are compared with: closed forms of the thick-walled cylinder
/// under inner pressure (plane strain) and a 1D axisymmetric total-Lagrangian finite-element ring
/// driven by the same batch material interface as the 2D engine (methods/materials/material.hpp).
///
/// The 1D ring: linear elements on [a, b] in the reference radius R, current radius r(R, t).
/// In the polar basis (which does not spin in axisymmetric motion) the deformation gradient is
///   F = diag(λ_r, λ_θ),  λ_r = ∂r/∂R,  λ_θ = r/R   (plane strain: F_zz = 1),
/// an isotropic material returns P = diag(P_rr, P_θθ), and per radian of circumference
///   f_int,i = ∫ (P_rr dN_i/dR + P_θθ N_i/R) R dR,   m_i = ρ ∫ N_i R dR,
///   f_ext,0 = p(t) r_a(t)   (the pressure follows the current inner surface),
///   σ_rr = P_rr/λ_θ,  σ_θθ = P_θθ/λ_r   (σ = P Fᵀ/J, J = λ_r λ_θ).
/// The stress profiles and the internal force include the artificial viscosity, if any.
/// Time integration: central differences in velocity-Verlet form with lumped masses.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "dynamics/explicit.hpp"
#include "methods/materials/material.hpp"

namespace mfv {

// --- Closed forms (plane strain, inner pressure p, inner radius a, outer b, a ≤ r ≤ b). ---------
// Every function throws InputError for a ≤ 0, b ≤ a, r or c outside [a, b] or a NaN argument.

/// Lamé's radial stress σ_rr(r) = p a²(1 − b²/r²)/(b² − a²) (Timoshenko & Goodier, Theory of
/// Elasticity, the thick-walled cylinder; catalogue `ring`): −p at r = a, 0 at r = b.
double lame_sigma_rr(double p, double a, double b, double r);
/// Lamé's hoop stress σ_θθ(r) = p a²(1 + b²/r²)/(b² − a²) (ibid.).
double lame_sigma_tt(double p, double a, double b, double r);
/// Plane strain: σ_zz = ν(σ_rr + σ_θθ) = 2ν p a²/(b² − a²), uniform through the wall.
double lame_sigma_zz(double p, double a, double b, double r, double nu);
/// Plane-strain radial displacement u(r) = (1 + ν) p a² /(E (b² − a²)) [(1 − 2ν) r + b²/r]
/// (the plane-stress form of
/// Timoshenko & Goodier with E → E/(1 − ν²), ν → ν/(1 − ν)).
double lame_displacement(double p, double a, double b, double r, double E, double nu);
/// Pressure of first yield at the inner surface (von Mises, plane strain, Lamé field):
///   p_y = σ_Y0 (1 − a²/b²)/√(3 + (1 − 2ν)² a⁴/b⁴)   (Hill, The Mathematical Theory of
/// Plasticity, ch. V §3; catalogue `ring`).
double first_yield_pressure(double yield_stress, double a, double b, double nu);
/// Hill's perfectly plastic cylinder (plane strain, von Mises with the shear yield σ_Y/√3):
/// the pressure that carries the plastic zone to radius c,
///   p(c) = (σ_Y/√3)[2 ln(c/a) + 1 − c²/b²]   (Hill ch. V §3).
double hill_pressure(double yield_stress, double a, double b, double c);
/// Collapse (whole wall plastic, c = b): p_lim = (2/√3) σ_Y ln(b/a).
double hill_collapse_pressure(double yield_stress, double a, double b);
/// Slip lines of the plastic zone: straight lines of slope ±1 in log-polar coordinates
/// ζ = ln(r/a), θ = θ0 ± ζ, i.e. logarithmic spirals r = a e^{±(θ − θ0)} leaving the inner
/// surface at ±π/4 (Hill ch. V §3; 000 §5.3). branch = +1 or −1.
double slip_line_angle(double r, double a, double theta0, int branch);

// --- The 1D axisymmetric ring. ------------------------------------------------------------------

struct ThickCylinder {
  double inner = 0, outer = 0;  ///< reference radii a < b
  int elements = 0;             ///< linear elements through the wall, uniform in R
  std::shared_ptr<const Material> material;
  double density = 0;
  std::function<double(double t)> pressure;  ///< inner pressure p(t), positive outward push
  /// The 2D engine's artificial viscosity (explicit.hpp), with l the reference element length:
  /// q = (ρ/J)(β (l ∇·v)² − α c l ∇·v) in compression, ∇·v = λ̇_r/λ_r + λ̇_θ/λ_θ, added to the
  /// stress as −q I (P_v = −q J F⁻ᵀ); c = material->wave_speed. Off by default. A shock-like load
  /// needs it for pointwise convergence (tests/test_thick_cylinder.cpp, the rubber ring).
  ArtificialViscosity viscosity;
};

/// Two Gauss points per element (ξ = ±1/√3). One point would also be free of hourglass modes
/// here — λ_r sees the difference of the element's two radial displacements and λ_θ their mean,
/// so the one-point strain map is already of rank 2 — but the hoop stretch r/R varies inside an
/// element and two points resolve it, and give two stress samples per element for the profiles.
class AxisymmetricRing {
 public:
  static constexpr int points_per_element = 2;

  explicit AxisymmetricRing(ThickCylinder cylinder);

  /// 2/ω_max from the element eigenvalue theorem (ω_max ≤ max_e ω_e): each element's 2×2
  /// tangent K_e = ∫ Bᵀ ∂(P_rr, P_θθ)/∂(λ_r, λ_θ) B R dR, taken by finite differences of the
  /// material at the current stretches on a copy of the state, against its lumped masses. The
  /// tangent stiffens in compression (the rubber's ln I3), so call it again as the ring deforms.
  /// With artificial viscosity the damped bound (2/ω)(√(1 + ξ²) − ξ) is taken per element, ξ the
  /// damping ratio of the element's highest mode.
  double critical_time_step() const;
  /// The largest step over which no element's current length ℓ changes by more than
  /// fraction·ℓ, from the nodal velocities and accelerations: |Δv| dt + ½|Δa| dt² ≤ fraction·ℓ.
  /// A load far above the unloaded stiffness (the rubber ring's 6.2e7 Pa is three bulk moduli)
  /// moves the inner node by more than an element in one step of the unloaded ring's
  /// critical_time_step(), before the compressed tangent (which stiffens) can shorten it.
  double kinematic_time_step(double fraction) const;
  /// One central-difference step of length dt > 0; throws SingularError naming the time if the
  /// state goes non-finite or an element inverts (λ_r ≤ 0 or λ_θ ≤ 0).
  void step(double dt);

  double time() const { return t_; }
  double inner_radius() const { return R_(0) + u_(0); }
  double outer_radius() const { return R_(R_.size() - 1) + u_(u_.size() - 1); }
  Eigen::VectorXd node_radii() const { return R_ + u_; }
  Eigen::VectorXd node_velocities() const { return v_; }
  /// Current radii of the Gauss points (two per element, inner first) and their Cauchy stresses.
  /// σ_zz is not returned: the plane-strain material hands back only the in-plane P.
  Eigen::VectorXd point_radii() const;
  Eigen::VectorXd sigma_rr() const;
  Eigen::VectorXd sigma_tt() const;
  /// Energies per radian of circumference (J/m per rad): ½ Σ m v², and the trapezoidal sums
  /// ∫ f_ext · du, ∫ f_int · du.
  double kinetic_energy() const;
  double external_work() const { return external_work_; }
  double internal_work() const { return internal_work_; }
  /// The material's history variables, state_size(2) per Gauss point, in point order.
  const std::vector<double>& state() const { return state_; }
  const ThickCylinder& cylinder() const { return cyl_; }

 private:
  /// Stretches, P and forces at the current displacement; the material state advances over
  /// the step dt (0 at the start: no time has passed).
  void compute_forces(double dt);
  /// Adds the artificial viscosity's P_v to P_ at the current half-step velocities.
  void add_viscosity();
  double pressure_at(double t) const;

  ThickCylinder cyl_;
  Eigen::VectorXd R_, u_, v_, a_, mass_, f_int_, point_R_, point_w_;
  std::vector<double> F_, P_, state_;
  double f_ext_ = 0;  ///< on the inner node only
  double t_ = 0, external_work_ = 0, internal_work_ = 0;
};

/// Inner and outer radius at the sample times, and the stress profiles at the end.
struct RadiusHistory {
  std::vector<double> times, inner, outer;
  Eigen::VectorXd point_radii, sigma_rr, sigma_tt;  ///< at end_time
  double kinetic_energy = 0, external_work = 0, internal_work = 0;  ///< at end_time
  long steps = 0;
};

/// Runs the ring from rest to end_time with dt = min(safety · critical_time_step(),
/// kinematic_time_step(stretch_per_step)) recomputed every step and shortened to land on each
/// sample time (sorted, in [0, end_time]). The default 0.02 keeps the inviscid rubber ring's
/// energy balance within 0.4 % from its first step, through the shock-like start (0.1: 1.8 %).
/// Throws SingularError naming the time if the ring inverts, goes non-finite, or the step
/// collapses below 1e-9 end_time (a load that crushes the wall).
RadiusHistory run_thick_cylinder(const ThickCylinder& cylinder, double end_time, double safety,
                                 const std::vector<double>& sample_times,
                                 double stretch_per_step = 0.02);

/// The ring's own convergence study: runs at elements = n, 2n, 4n, ... (n = cylinder.elements,
/// `levels` ≥ 2 runs) and measures, between consecutive levels, the largest relative difference
/// of the inner-radius histories, max_k |r_fine(t_k) − r_coarse(t_k)| / r_fine(t_k).
struct CylinderConvergence {
  std::vector<int> elements;
  std::vector<RadiusHistory> runs;
  std::vector<double> differences;  ///< levels − 1 values, coarse pair first
  /// The "converged in its own study" figure: the difference between the two finest levels.
  double converged() const { return differences.back(); }
};

CylinderConvergence thick_cylinder_convergence(const ThickCylinder& cylinder, double end_time,
                                               double safety,
                                               const std::vector<double>& sample_times,
                                               int levels = 3, double stretch_per_step = 0.02);

}  // namespace mfv
