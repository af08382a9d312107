/// Free-surface water for the transient analysis (001 §9.7): the Tait fluid of eq 77,
///   p = B((ρ/ρ0)^γ − 1),
/// gravity, rigid frictionless walls and a hydrostatic state at t = 0, built the same way for
/// every method and both kernels, and the run's watch (energy, density, blow-up). Shared by
/// the `funnel`, `hydrostatic-column` and `dam-break` problems.
///
/// Walls are penalty walls acting on the particles (DynamicsModel::particle_forces): a
/// particle closer than the reach r0 = Δx/2 to a wall segment is pushed back along the
/// segment's normal by k (r0 − d), k = m_I (c0/Δx)², no friction, no damping (the force is
/// conservative: its work enters the energy balance as external work and comes back). Why
/// penalty walls and not wall particles: a fixed wall particle would enter a Lagrangian
/// kernel's neighbour set and every method's corrections differently; a force on the fluid's
/// own particles acts identically in all of them (the hydrostatic column measures the price:
/// its walls=particles, dummy wall particles, holds every method's column 10-400 times closer,
/// issue 27; the flows' walls reach beyond the water's lattice, so they keep these). k gives a wall frequency c0/Δx, below the
/// fluid's own highest frequency (about 2 c0/Δx), so the walls do not cut the critical step,
/// and a hydrostatic penetration g H Δx / c0² (4 μm for 0.25 m of water at Δx = 5 mm).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "dynamics/explicit.hpp"
#include "methods/materials/material.hpp"

namespace mfv::fluid {

/// 001 §9.7's water (SI units: ρ0 = 0.001 g/mm³ = 1000 kg/m³, B = 0.4704 MPa) and gravity.
struct Water {
  double rho0 = 1000, gamma = 7, B = 4.704e5;
  double g = 9.81;  ///< downwards (−y), our choice: 001 gives no gravity
  double sound_speed() const;                    ///< c0 = √(γB/ρ0), 57.4 m/s
  double pressure(double rho) const;             ///< eq 77
  /// The density whose pressure is ρ0 g `depth` (the hydrostatic state; eq 77 inverted).
  double hydrostatic_density(double depth) const;
};

/// A rigid wall: the segment a–b; it pushes particles away from itself on both sides.
using Wall = RigidWall;

/// Penalty walls (see the file comment).
class Walls {
 public:
  /// `reach` r0 (> 0), `stiffness_per_mass` k/m (> 0, 1/s²).
  Walls(std::vector<Wall> walls, double reach, double stiffness_per_mass);
  /// Adds the wall forces on the particles at x (2 × N) of masses m into f (2 × N).
  void add_forces(const Eigen::MatrixXd& x, const Eigen::VectorXd& mass, Eigen::MatrixXd& f) const;
  /// Σ_I ½ k_I (r0 − d)²: the energy the walls hold.
  double energy(const Eigen::MatrixXd& x, const Eigen::VectorXd& mass) const;
  const std::vector<Wall>& walls() const { return walls_; }
  double reach() const { return reach_; }

 private:
  std::vector<Wall> walls_;
  double reach_, k_per_mass_;
};

/// What a fluid problem supplies to water_model.
struct Setup {
  Water water;
  /// The free surface's height at t = 0 (the hydrostatic state's H; particles above it are
  /// at ρ0).
  double surface = 0;
  std::vector<Wall> walls;
};

/// The dynamics model: the registry's `tait` material with `water`'s constants, masses
/// ρ_ref(y) V_I with ρ_ref the hydrostatic density at depth H − y (so the column starts in
/// equilibrium), the same reference density at the integration points (the material's
/// history), gravity and the walls as particle forces, and the Eulerian kernel's fallback at
/// degenerate supports (a splash or a jet that breaks up; counted). Throws InputError when the
/// registry has no `tait`.
DynamicsModel water_model(const Discretization& d, const MaterialRegistry& materials,
                          const Setup& setup);

/// The transient analysis's defaults every fluid problem shares: Monaghan's linear artificial
/// viscosity α = 0.1, β = 0 (Monaghan 1994, J. Comput. Phys. 110, 399–406: 0.01–0.1 for
/// free-surface water; it damps the acoustic ripple of a hydrostatic start or a gate's
/// removal, and there are no shocks), and safety 0.5 on the critical step of the power
/// iteration at t = 0 (water at rest): free-surface speeds stay far below c0 = 57 m/s
/// (advection adds ≤ 14 % at 8 m/s), the density stays within a few % of ρ0 (c ∝ ρ³ for
/// γ = 7: ≤ 10 %) and the walls' frequency c0/Δx is below the fluid's; 0.5 leaves room for
/// all three at once. `frames`: VTK snapshots per run.
Params transient_defaults(int frames);

/// Σ_I m_I g y_I of the particles at x.
double potential_energy(const Eigen::MatrixXd& x, const Eigen::VectorXd& mass, double g);

/// Limits of the blow-up watch.
struct Limits {
  double speed = 0;  ///< a particle faster than this (m/s) has blown up; e.g. 5 √(2 g H0)
  /// Kinetic energy above this multiple of the potential energy released so far (plus the
  /// initial kinetic energy) cannot come from gravity: the scheme made it.
  double energy_factor = 2;
  /// Added to the released potential energy in that budget (J/m): the elastic energy a
  /// hydrostatic state stores at t = 0 (stored_energy), which a released column turns into
  /// kinetic energy before it has released any potential energy. 0: none.
  double energy_floor = 0;
};

/// Σ_I V_I p_I² / (2 ρ0 c0²): the elastic energy of water at the pressures p of particles of
/// volumes V (the Tait fluid linearized about ρ0).
double stored_energy(const Eigen::VectorXd& volume, const Eigen::VectorXd& pressure,
                     const Water& water);

/// The watch of a fluid run, called after every step (TransientDefinition::unstable):
/// returns the first reason for a blow-up ("" while sound) — a non-finite field, an inverted
/// point (det F ≤ 0), a particle faster than limits.speed, or kinetic energy beyond
/// limits.energy_factor × the released potential energy. Keeps the history of the
/// speed, kinetic energy and density range for the growth rate and the verdicts.
class Watch {
 public:
  Watch(const Eigen::VectorXd& mass, double g, double potential0, Limits limits);
  std::string check(const ExplicitDynamics& sim);
  /// Records one sample of the histories (time, energies, balance, speed, density range);
  /// the caller decides how often.
  void sample(const ExplicitDynamics& sim);

  struct Sample {
    double t, kinetic, potential, internal_work, external_work, balance, max_speed;
    double density_min, density_max;  ///< over the integration points (NaN without the slot)
  };
  const std::vector<Sample>& samples() const { return samples_; }
  /// Growth rate (1/s) of the largest speed over the last `window` samples before the
  /// blow-up, fitted to ln(max speed); NaN with fewer than 3 samples.
  double speed_growth_rate(int window = 20) const;
  /// The largest |energy balance| over the released potential energy at any sample (NaN when
  /// nothing was released).
  double worst_energy_error() const;
  /// The largest |ρ/ρ0 − 1| of the samples' density ranges (non-finite values skipped; 0
  /// without samples or without the density slot).
  double max_density_deviation(double rho0) const;
  double released_energy() const { return released_; }
  /// The density range reads only these integration points (the water's, where wall
  /// particles are part of the set); empty: every point.
  void watch_density_at(std::vector<int> points) { water_points_ = std::move(points); }

 private:
  Eigen::VectorXd mass_;
  double g_, potential0_;
  Limits limits_;
  double released_ = 0;
  std::vector<Sample> samples_;
  std::vector<int> water_points_;
};

}  // namespace mfv::fluid
