/// What the funnel of 001 §9.7 measures and is measured against: the funnel's geometry and
/// particle lattice, the free-streamline contraction coefficient
///   C_c(β) = [1 + (2/π) ∫₀^{π/2} sin(β(1 − 2α/π)) tan α dα]⁻¹
/// (catalogue §funnel; von Mises' 2D orifice with walls at β to the jet axis), Torricelli's
/// level law w(h) dh/dt = −C_c D √(2 g h) (with an optional start-up term), the drained
/// fraction and the level recovered from it. Pure functions, tested on closed forms.
#pragma once
#include <vector>

#include <Eigen/Dense>

#include "methods/particles.hpp"

namespace mfv::funnel {

/// The 2D funnel: outlet of width D at y = 0, walls at 45° to the vertical up to y = `cone`
/// (x = ±D/2 at y = 0 to ±(D/2 + cone) at y = cone), then vertical at x = ±(D/2 + cone) up to
/// y = `top`. Lengths in metres.
struct Geometry {
  double outlet = 0.04;  ///< D
  double cone = 0.10;    ///< height of the 45° part
  double top = 0.40;     ///< height of the vertical walls (above the water)
  /// Width w(y) of the funnel at height y ≥ 0: D + 2y in the cone, D + 2·cone above.
  double width(double y) const;
  /// A(h) = ∫₀^h w(y) dy, the area below the level h (per unit depth).
  double area(double h) const;
  /// The level whose area is `a` (A⁻¹, closed form: quadratic in the cone, linear above);
  /// 0 for a ≤ 0.
  double level_of_area(double a) const;
  /// ∫₀^h dy / w(y): the length over which the flux per unit width accelerates (the 1D
  /// inertance of the column above the outlet, per unit outlet flux).
  double inertance(double h) const;
};

/// Free-streamline contraction coefficient of a 2D orifice whose walls make the angle `beta`
/// (radians, in (0, π]) with the jet axis: 0.611 for a flat wall (π/2), 0.5 for Borda's
/// re-entrant tube (π). Integrated with GSL's QAGS after the substitution ε = π/2 − α, which
/// turns the integrand into sin(2βε/π) cot ε, regular at ε = 0 (limit 2β/π). Throws
/// InputError for β outside (0, π] or non-finite.
double contraction_coefficient(double beta);

/// Torricelli's level law for a funnel, integrated with GSL odeiv2 (rk8pd, relative 1e-10).
struct Torricelli {
  Geometry geometry;
  double cc = 0.611;  ///< contraction coefficient C_c
  double h0 = 0.25;   ///< level at t = 0 (m)
  double g = 9.81;    ///< gravity (m/s²)
  /// false: quasi-steady, w(h) dh/dt = −C_c D √(2 g h). true: the jet starts from rest and
  /// accelerates through the column's inertance (unsteady Bernoulli from the free surface to
  /// the vena contracta, 1D): C_c D I(h) dv/dt = g h − v²/2, w(h) dh/dt = −C_c D v, v(0) = 0,
  /// I(h) = Geometry::inertance(h); after the start-up it is the quasi-steady law.
  bool startup = false;
  /// The level at each of `times` (ascending, ≥ 0); once the funnel has emptied, 0.
  std::vector<double> levels(const std::vector<double>& times) const;
  /// The fraction of the water below y = 0 at each of `times`: 1 − A(h(t))/A(h0).
  std::vector<double> drained(const std::vector<double>& times) const;
  /// The first time the drained fraction reaches `fraction` (bisection on levels(), 1e-9 s);
  /// NaN when not before `horizon`.
  double time_to_drain(double fraction, double horizon) const;
};

/// The fraction of the mass below y = 0 (x: 2 × N positions, mass: N; 0 when the mass is 0).
double drained_fraction(const Eigen::MatrixXd& x, const Eigen::VectorXd& mass);

/// The level h with A(h) = (1 − drained) A(h0): the volume still above y = 0 inverted through
/// the funnel's area function (relative to the initial area, so the lattice's staircase at the
/// walls does not bias it).
double level_from_drained(const Geometry& g, double h0, double drained);

/// The first time the samples (t, f) reach `target` (f rising), interpolated linearly between
/// the two samples around it; NaN when they never do.
double first_crossing(const std::vector<double>& t, const std::vector<double>& f, double target);

/// The funnel's particles: a square lattice of spacing dx filling the water up to `h0` (rows
/// at y = (j + ½) dx below h0, columns at x = (i + ½) dx), each particle at least dx/2 from
/// every wall segment (so penalty walls of reach dx/2 are idle at t = 0), volume dx²; `quads`
/// are the lattice cells whose four corners are particles (counter-clockwise), and
/// `stress_points` sit at their centres with the square lattice's quad-centre split (a cell of
/// area dx² gives dx²/2 to its stress point and dx²/8 from each corner: a particle keeps
/// dx² − (its cells) dx²/8, so Σ V^P + Σ V^SP = N dx², the particles' volume). No box sides.
/// `wall_layers` > 0 adds dummy wall particles after the water's (walls=particles, issue 43):
/// the same lattice's sites outside the funnel (|x| ≥ w(y)/2, up to the walls' top) at a
/// distance in [dx/2, wall_layers·dx) from the wall segments, so the cells that straddle no
/// wall get stress points as the water's do (at the 45° walls the two sides' nearest sites
/// are dx/√2 from the wall; at the vertical ones dx/2). Their volumes are split the same way.
/// Throws InputError for a spacing that is not positive and finite, not below the outlet or
/// that gives more than `max_particles`, and for wall_layers outside [0, 10].
ParticleSet funnel_lattice(const Geometry& g, double h0, double dx, long max_particles = 2000000,
                           int wall_layers = 0);

/// Whether a reference position is inside the funnel (between the walls, 0 < y < top): the
/// water's particles and points; the others are wall particles (walls=particles).
bool inside(const Geometry& g, const Eigen::Vector2d& x);

/// The funnel's wall segments, in order: left cone, left vertical, right cone, right vertical
/// (each as the pair of its ends).
std::vector<std::array<Eigen::Vector2d, 2>> wall_segments(const Geometry& g);

}  // namespace mfv::funnel
