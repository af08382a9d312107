/// Explicit dynamics of any registered method: lumped-mass central differences (velocity
/// Verlet) or the explicit Newmark predictor–corrector of 004 III, with total Lagrangian
/// (Lagrangian kernel, 001 Table 1) or updated Lagrangian (Eulerian kernel, Table 2) forces
/// computed from the method's two gradient tables:
///   F_q = I + Σ_J u_J ⊗ ∇₀N_J(X_q),  f_I = Σ_q w_q P_q · ∇₀N^test_I(X_q)      (Lagrangian)
///   Ḟ_q = L_q F_q, L_q = Σ_J v_J ⊗ ∇N_J(x_q),  f_I = Σ_q w_q σ_q · ∇N^test_I(x_q)  (Eulerian)
/// so every plugin gets wave propagation, energy balances and time-step estimates for free.
#pragma once
#include <algorithm>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "dynamics/fluid_remedy_options.hpp"
#include "methods/materials/material.hpp"
#include "methods/methods/method.hpp"

namespace mfv {

/// Which configuration the kernel lives in (001 §3.1).
enum class KernelFrame {
  lagrangian,  ///< W(X − X_J): neighbours, shape functions and corrections computed once
  eulerian     ///< W(x − x_J(t)): recomputed at the current positions every `update_every` steps
};

enum class TimeIntegrator {
  verlet,  ///< central differences in velocity-Verlet form (half-step velocities)
  newmark  ///< explicit Newmark predictor–corrector (β = 0, γ ≥ ½), 004 III §4
};

/// Which gradients the internal force sums. The method's own test functions (001: KBM's
/// Shepard functions, RLM's eq 34 rows, the Galerkin methods' trial functions) make a
/// Petrov–Galerkin force whose power Σ_I f_I·v_I differs from the rate of stored energy
/// Σ_q w_q σ_q : L_q wherever the test and trial gradients differ (free surfaces, irregular
/// particles). The variational force is the transpose of the trial gradient operator,
///   f_I = Σ_q w_q σ_q · ∇N_I(x_q)    (the same ∇N_J(x_q) that gives F_q and L_q),
/// so Σ_I f_I·v_I = Σ_q w_q σ_q : L_q exactly: the internal forces can create no energy
/// (Bonet & Lok 1999, CMAME 180: 97–115, the variational form of corrected SPH). It conserves
/// linear momentum whenever the gradients of a constant vanish (every corrected method).
/// Methods whose test functions are their trial functions (sph, the EFG/RKPM Galerkin
/// methods) are unchanged by it.
enum class ForceForm {
  test_functions,  ///< f_I = Σ_q w_q σ_q · ∇N^test_I(x_q): the method as published (default)
  variational      ///< f_I = Σ_q w_q σ_q · ∇N_I(x_q), the trial gradients (Bonet & Lok 1999)
};

/// Monaghan-type artificial viscosity, written at the integration points so that it acts in
/// every method: a pressure q = ρ (β (l ∇·v)² − α c l ∇·v) in compression (∇·v < 0), l the
/// particle spacing, c the wave speed (Monaghan's Π_IJ with μ_IJ → l ∇·v).
struct ArtificialViscosity {
  double alpha = 0, beta = 0;
  bool enabled() const { return alpha > 0 || beta > 0; }
};

/// The order the engine keeps particles and integration points in while it steps.
enum class ParticleOrder {
  as_given,  ///< the discretization's (default: results bit for bit those of earlier versions)
  /// Renumbered along the Hilbert curve (methods/ordering.hpp) inside the engine: the force
  /// loops read neighbours that are near in memory whatever order the set came in. Everything
  /// the engine takes and gives (prescribed particles, loops, masses, velocities, fields,
  /// point values, callbacks, discretization()) stays in the discretization's order, so
  /// problems that name particles by index are unaffected; sums over particles change order,
  /// so results agree with as_given to round-off, not bit for bit. Lagrangian kernel only.
  hilbert
};

/// How an Eulerian kernel's support radii evolve (issue 27; 001 eq 16 writes the Eulerian
/// kernel with h(x, t) and leaves the rule open). `adaptive`: each particle's dilation is its
/// t = 0 value times J_I^{1/d}, J_I = det F at the particle, as SPH's h_I = η (m_I/ρ_I)^{1/d}
/// (Monaghan 2005 §2.8). `stretch`: times the largest principal stretch λ_max(F_I), so the
/// support keeps its neighbours along the direction that stretches most (a nearly
/// incompressible solid keeps J ≈ 1 while stretching 1.5 one way). Supports are scattered
/// (particle J's own radius decides whether it reaches a point), as the corrected-kernel tables
/// already are; the neighbour lists rebuild when the largest radius grows.
enum class SupportRule { fixed, adaptive, stretch };
/// The largest factor support=adaptive|stretch applies to a t = 0 radius.
inline constexpr double kMaxSupportGrowth = 3.0;
SupportRule support_rule_from(const std::string& name);

/// What the stress sees of each point's volume change J = det F.
enum class VolumeAverage {
  off,  ///< the point's own F (default: every existing result bit for bit)
  /// F-bar over the particles' patches (de Souza Neto et al. 1996, "Design of simple low order
  /// finite elements for large strain analysis of nearly incompressible solids", IJSS 33,
  /// 3277-3296, with the patch of Bonet & Burton 1998, "A simple average nodal pressure
  /// tetrahedral element", CNME 14, 437-449): the current over the reference volume of each
  /// particle's patch,
  ///   Ĵ_I = Σ_q w0_q J_q S_I(x_q) / Σ_q w0_q S_I(x_q),
  /// is interpolated back to the points, J̄_q = Σ_I S_I(x_q) Ĵ_I / Σ_I S_I(x_q), and the
  /// stress is evaluated at F̄_q = (J̄_q / J_q)^{1/D} F_q (S: the test functions' values, or
  /// the trial functions' when the test table has none). One volume change per particle:
  /// the particle points and the stress points of an si rule can no longer carry volume
  /// changes (pressures) of opposite sign that each rule alone integrates to no force (the
  /// stress points' pressure mode of a fluid, which has no shear stiffness to resist it).
  /// The Eulerian kernel commits F̄ (its F is integrated from increments, so the average
  /// also removes what the mode had accumulated); the Lagrangian one recomputes F from u.
  /// J ≡ 1 is kept exactly, so a state whose stratification is in the reference density
  /// (the hydrostatic column) starts unchanged. Native engine, as-given order only.
  /// Measured on the hydrostatic column (kbm-si, 20 × 40, 20 crossings; issue 27): without it
  /// the time-averaged pressure at the particle points is 1.5-2.8 × ρ0 g (H − y) and at the
  /// stress points −1.3 to 0.5 × (rows near the floor; the pair's mean is near exact); with
  /// it the split is gone and the time-averaged error falls 1.35 → 0.18 (Lagrangian kernel,
  /// bottom row 2.75 → 1.01 of exact) and 4.56 → 0.72 (Eulerian). Not yet a default: one
  /// volume change per particle leaves particle-scale compaction free (in the Eulerian
  /// column the two bottom rows close up by 4 of their 5 mm) and the kinetic energy still
  /// grows (a second instability of KBM on the fluid, issue 27's report). Methods whose
  /// unknowns are particle values on a nodal rule (sph, rlm) tabulate the values as the
  /// identity, so there it changes nothing (measured bit for bit); efg-ni's Eulerian column:
  /// 0.36 → 0.19.
  patch
};

/// Where the Eulerian kernel centres the particles' supports when it recomputes its tables.
enum class KernelCentres {
  /// X_I + u_I, u_I the particle's unknowns (default: every existing result bit for bit).
  coefficients,
  /// X_I + Σ_J N_J(X_I) u_J, the trial field at the particle: the particle's material
  /// position, where the walls, gravity's work, the frames and particle_positions() already
  /// see it and where the stress points (X_q + u^h(X_q)) are moved. Differs from
  /// `coefficients` only for methods whose unknowns are not particle values (MLS, RKPM: kbm,
  /// efg, ...). Measured on the hydrostatic column (kbm-si, Eulerian, 20 × 40, 20 crossings):
  /// end kinetic energy 0.0136 → 0.0022 M g H, time-averaged pressure error 4.56 → 1.93: a
  /// coefficient pattern the trial field hardly sees moved the supports and so the forces.
  interpolated
};

/// How the forces of the model's rigid walls (DynamicsModel::wall_forces) reach the unknowns
/// (issue 27). A weak form integrates ∫_Ω σ : ∇N^test_I dΩ over the material and so owes every
/// unknown whose test function reaches a wall the boundary term
///   f_I^wall = ∫_Γwall N^test_I t dΓ    (t the wall's contact traction)
/// (the principle of virtual work). A penalty force R_K at particle K near a wall is the
/// wall's traction over that particle's stretch of wall; carried to the unknowns as a force
/// at the particle, Σ_K N_I(X_K) R_K, it reaches the unknowns of the particles near K, while
/// the boundary term reaches every unknown whose test function covers the wall, d_max rows
/// deep: the rows between are left pressed towards the wall by a force no wall holds, and a
/// fluid, which has no shear stiffness to carry it, moves.
enum class WallTraction {
  off,  ///< R_K as a force at particle K (default: every existing result bit for bit)
  /// R_K as the traction at K's foot on the nearest wall, x_K^wall (the wall's boundary term
  /// by the nodal rule of the particles along the wall):
  ///   f_I += N^test_I(x_K^wall) R_K,
  /// N^test the functions the internal force sums (test or trial, ForceForm), evaluated at
  /// the current positions (Eulerian kernel) or the reference ones (Lagrangian). A foot
  /// whose support is too small for the approximation keeps the force at the particle.
  /// Methods with particle-value unknowns (sph, rlm) collocate at the particles: their test
  /// functions are δ at the particles, so the boundary term's nodal rule is the force at the
  /// particle, and `weak` changes nothing there. Native engine, 2D, given particle order.
  /// Tried first and dropped: the traction t = (n·σ·n) n read from the material's own stress
  /// at the wall (the stress extrapolated by the trial functions); it balances a hydrostatic
  /// state exactly, but a wall that pushes with whatever stress the material has offers no
  /// stiffness of its own, and the kbm-si column blew up within 2 sound crossings at any step.
  weak
};
WallTraction wall_traction_from(const std::string& name);

struct DynamicsOptions {
  KernelFrame frame = KernelFrame::lagrangian;
  WallTraction wall_traction = WallTraction::off;
  KernelCentres kernel_centres = KernelCentres::coefficients;
  VolumeAverage volume_average = VolumeAverage::off;
  int update_every = 1;  ///< Eulerian: steps between recomputations of the tables
  /// Eulerian: skin of the neighbour (Verlet) lists over the particle spacing; the lists are
  /// searched afresh only when the largest point move plus the largest particle move since
  /// the last search exceeds it (methods/neighbours.hpp). 0.3 Δx: a rebuild every few
  /// retabulations at the rod's strain rates, lists ~1.3² longer than the supports. 0 searches
  /// afresh at every recomputation. The tables do not depend on it.
  double neighbour_skin = 0.3;
  TimeIntegrator integrator = TimeIntegrator::verlet;
  double newmark_gamma = 0.5;
  ArtificialViscosity viscosity;
  ForceForm force = ForceForm::test_functions;
  int threads = 0;  ///< OpenMP threads for the force loops; 0: the OpenMP default
  ParticleOrder order = ParticleOrder::as_given;
  /// Eulerian: the support radii follow the material (issue 27, 001 eq 16's h(x, t)) or keep
  /// their t = 0 size in the current configuration (today's runs).
  SupportRule support = SupportRule::fixed;
  /// Eulerian: the fluid remedies (density filter, density diffusion, particle shifting;
  /// dynamics/fluid_remedies.hpp), all off by default.
  FluidRemedies remedies;
};

/// A prescribed velocity of one unknown (particle, component): v(t), or nothing (free) once
/// `until` has passed.
struct PrescribedVelocity {
  int particle = 0, component = 0;
  double value = 0;
  double until = 1e300;
};

/// A pressure on a closed surface that follows the deformation (the rings' inner surface, 000
/// §5.2–5.3): the surface is the polygon of its particles' current positions, and particle I
/// gets f_I = p(t) ℓ_I n_I, ℓ_I n_I = ½ R₋₉₀(x_{I+1} − x_{I−1}) (half of each adjacent edge's
/// length times its normal). For a loop that runs counter-clockwise around the loaded hole the
/// force points away from the hole, into the material. Methods whose unknowns are not the
/// particle values get Σ_I N_J(X_I) f_I (the nodal rule of the surface integral ∫ N_J p n dΓ).
struct FollowerPressure {
  std::vector<int> loop;                     ///< the surface's particles, in order (≥ 3)
  std::function<double(double t)> pressure;  ///< p(t), positive pushing into the material
};

/// A rigid frictionless wall, the segment a–b (2D): the fluid problems' penalty walls and
/// WallTraction::weak's feet.
struct RigidWall {
  Eigen::Vector2d a, b;
  /// The point of the segment nearest to p.
  Eigen::Vector2d nearest(const Eigen::Vector2d& p) const {
    const Eigen::Vector2d s = b - a;
    return a + std::clamp((p - a).dot(s) / s.squaredNorm(), 0.0, 1.0) * s;
  }
};

/// What a problem supplies besides the discretization.
struct DynamicsModel {
  std::shared_ptr<const Material> material;
  double density = 1;
  Eigen::VectorXd mass;          ///< lumped mass per particle (see lumped_masses)
  Eigen::MatrixXd initial_stress;  ///< dim × dim second Piola–Kirchhoff prestress S₀ (or empty)
  std::vector<PrescribedVelocity> prescribed;
  /// External forces at time t into f (dim·N, interleaved), which arrives zeroed; optional.
  std::function<void(double t, Eigen::VectorXd& f)> external_force;
  std::vector<FollowerPressure> follower_pressures;  ///< 2D only
  /// Forces on the particles where they are now (gravity m_I g, walls): called with the time
  /// and the current positions (dim × N), adds into f (dim × N, arrives zeroed). Methods
  /// whose unknowns are not the particle values get Σ_I N_J(X_I) f_I, as follower pressures.
  /// The engine counts their work as external work, so a conservative wall keeps the
  /// balance. Optional.
  std::function<void(double t, const Eigen::MatrixXd& x, Eigen::MatrixXd& f)> particle_forces;
  /// Sets the material history of the integration points from their reference positions
  /// (dim × nq), after the material's own initial_state: state_size values per point (a
  /// fluid's hydrostatic reference density). Optional.
  std::function<void(const Eigen::MatrixXd& points, int state_size, double* state)>
      initial_state;
  /// Eulerian kernel: where a recomputed support is degenerate (too few or collinear
  /// particles, a splash or a jet breaking up) the method falls back to its uncorrected
  /// kernel instead of failing (Retabulation::degenerate_fallback); counted in the counters.
  bool degenerate_fallback = false;
  /// Integration points that carry no tension: their stress's isotropic part is dropped
  /// whenever it pulls (tr σ > 0), after the material. Dummy wall particles of a fluid
  /// (problems' walls=particles), whose density falls as water leaves them: with tension they
  /// hold a film of water on the wall (Hughes & Graham 2010, "Comparison of incompressible and
  /// weakly-compressible SPH models for free-surface water flows", J. Hydraulic Res. 48, 105-117,
  /// keep wall densities at or above ρ0 for the same reason). Empty: none (default).
  std::vector<int> tensionless_points;
  /// Forces of rigid walls on the particles where they are now (penalty walls), as
  /// particle_forces; WallTraction says how they reach the unknowns. Optional.
  std::function<void(double t, const Eigen::MatrixXd& x, Eigen::MatrixXd& f)> wall_forces;
  /// The walls of wall_forces (WallTraction::weak finds each particle's foot on them).
  std::vector<RigidWall> rigid_walls;
};

/// How the particle masses are allocated (001 §6).
enum class MassLumping {
  volume,  ///< m_I = ρ V_I: boundary particles half, corners a quarter of the interior mass
  uniform  ///< every particle the same mass ρ V/N
};
Eigen::VectorXd lumped_masses(const ParticleSet& particles, double density, MassLumping lumping);

/// Energy balance of a run: E = K + W_int − W_ext − K₀ stays 0 for a conservative scheme.
struct EnergyBalance {
  double kinetic = 0, internal_work = 0, external_work = 0, initial = 0;
  double balance() const { return kinetic + internal_work - external_work - initial; }
};

/// CPU-free counters of what the engine did (timings are the caller's).
struct DynamicsCounters {
  long steps = 0, retabulations = 0;
  long neighbour_rebuilds = 0;  ///< Eulerian: fresh neighbour searches of the retabulations
  long degenerate_points = 0;   ///< Eulerian: points on the fallback at the last recomputation
  long degenerate_peak = 0;     ///< ... and the most at any recomputation
};

class ExplicitDynamics {
 public:
  /// Takes the discretization (built with a Lagrangian kernel at t = 0); `method` is kept for
  /// Eulerian recomputation and must outlive this object.
  ExplicitDynamics(const Method& method, Discretization d, DynamicsModel model,
                   DynamicsOptions options);

  /// Sets the velocity field from its values at the particles (dim × N): the unknowns are the
  /// particle values themselves (SPH, RLM) or the nodal parameters whose field takes these
  /// values at the particles (MLS), found by a sparse solve.
  void set_particle_velocity(const Eigen::MatrixXd& v);
  /// Sets the time and the particles' displacements and velocities (dim × N) to fields
  /// computed elsewhere — an external solver's frame (dynamics/external_solver.hpp) — so the
  /// problems' measurements read them. Methods whose unknowns are the particle values only
  /// (std::logic_error otherwise); stresses and energies other than the kinetic one are not
  /// the solver's and are not to be read.
  void set_replayed_state(double t, const Eigen::MatrixXd& u, const Eigen::MatrixXd& v);

  /// ω_max² of M⁻¹K about the current state, K from central differences of the internal force
  /// (power iteration; free unknowns only). The critical step of central differences is
  /// 2/ω_max.
  double max_eigenvalue(int iterations = 60) const;
  double critical_time_step(int iterations = 60) const;

  /// Moves the committed state by the displacement increment du as one step would, without
  /// time, viscosity or energy: Lagrangian u += du; Eulerian F ← (I + Σ du_J ⊗ ∇N_J) F with
  /// the current tables, then the tables recomputed at the moved positions. Prepares the
  /// deformed states that stability analyses linearize about.
  void displace(const Eigen::VectorXd& du);
  /// The internal force after a trial increment du from the committed state (Eulerian: with
  /// the tables recomputed at the moved positions, so the kernel's own motion enters), the
  /// engine left as it was. Its central differences are the engine's tangent stiffness, the
  /// operator the dispersion analysis of any method linearizes (stability/dispersion.hpp).
  Eigen::VectorXd trial_force(const Eigen::VectorXd& du) const;

  /// Advances one step of size dt.
  void step(double dt);

  double time() const { return t_; }
  const DynamicsCounters& counters() const { return counters_; }
  const EnergyBalance& energy() const { return energy_; }
  const Discretization& discretization() const { return d_; }
  int dim() const { return dim_; }
  int particles() const { return n_; }
  /// Unknowns (dim·N, interleaved): nodal displacements and velocities.
  const Eigen::VectorXd& displacement() const { return u_; }
  const Eigen::VectorXd& velocity() const { return v_; }
  /// The fields at the particles (dim × N): v(X_I) = Σ_J N_J(X_I) v_J, likewise u.
  Eigen::MatrixXd particle_velocity() const;
  Eigen::MatrixXd particle_displacement() const;
  /// Current positions of the particles (X_I + u(X_I)), dim × N.
  Eigen::MatrixXd particle_positions() const;
  /// Cauchy stress at the integration points (dim·dim × nq, column-major per point) and at
  /// the particles (nodal and stress-point rules: their own points; cell rules: the nearest
  /// Gauss point's value, for pictures only).
  Eigen::MatrixXd point_cauchy_stress() const;
  Eigen::MatrixXd particle_cauchy_stress() const;
  /// The integration point that stands for each particle: its own (nodal and stress-point
  /// rules) or the nearest one in the reference configuration (cell rules; pictures only).
  const std::vector<int>& particle_points() const;
  double kinetic_energy() const;
  std::string description() const;
  /// The smallest det F over the integration points: ≤ 0 means a point has inverted.
  double min_jacobian() const;
  /// Neighbours (trial-table entries) of each integration point, and their minimum: an
  /// Eulerian kernel's supports empty as the particles separate.
  Eigen::VectorXi point_neighbours() const;
  int min_neighbours() const;
  /// The material history slot called `name` (Material::state_names) at every integration
  /// point; empty when the material has no such slot.
  Eigen::VectorXd point_state(const std::string& name) const;
  const Material& material() const { return *model_.material; }
  /// The current positions of the particles of `loop` (follower surfaces, measurements).
  Eigen::MatrixXd positions_of(const std::vector<int>& particles) const;

 private:
  /// The PETSc engine (dynamics/petsc_dynamics.hpp) starts from this engine's initial state
  /// and gathers its distributed fields into it for the problems' callbacks.
  friend class PetscDynamics;
  void build_force_tables();
  /// The tables the force loops read: the discretization's, or their renumbered copies.
  const ShapeTable& trial_table() const;
  /// The table whose gradients the internal force sums (the test table, or the trial one).
  const ShapeTable& force_table() const;
  void renumber_along_hilbert_curve();
  /// Point-ordered values (rows × nq, the engine's order) in the discretization's order.
  Eigen::MatrixXd points_to_given(Eigen::MatrixXd by_engine) const;
  /// f_int at displacement u (Lagrangian) or after the increment du from the committed
  /// state (Eulerian); dt > 0 turns on the viscosity (velocity du/dt). `commit` stores F and
  /// the material history; otherwise they are left as they were (trial evaluations).
  void internal_force(const Eigen::VectorXd& u, const Eigen::VectorXd& du, double dt,
                      bool commit, Eigen::VectorXd& f) const;
  /// The two force loops of internal_force in D dimensions.
  /// The table whose values weigh the patches (VolumeAverage::patch).
  const ShapeTable& volume_table() const;
  /// F → F̄ at every point (VolumeAverage::patch).
  void average_volumes(double* F) const;
  template <int D>
  void forces(const Eigen::VectorXd& u, const Eigen::VectorXd& du, double dt, bool eulerian,
              bool viscosity, double* F, double* state, Eigen::VectorXd& f) const;
  /// f = Σ_q w0_q σ_q ∇N_I(x_q) from the summed stresses: the gather over the transposed
  /// table, or the serial scatter over the force table (scatter_forces_).
  template <int D>
  void sum_forces(Eigen::VectorXd& f) const;
  /// support=adaptive|stretch: the particles' dilations from F (SupportRule).
  void adapt_supports();
  void retabulate();
  void external_force(double t, Eigen::VectorXd& f) const;
  /// WallTraction::weak: the wall forces fw (dim × N) at the particles x carried to f through
  /// the force functions at the particles' feet on the walls.
  void add_wall_tractions(const Eigen::MatrixXd& x, const Eigen::MatrixXd& fw,
                          Eigen::VectorXd& f) const;
  /// A 2D force at particle K into f: on its unknown, or Σ_J N_J(X_K) force on the unknowns
  /// (methods whose unknowns are not the particle values).
  void add_force_at_particle(int K, const Eigen::Vector2d& force, Eigen::VectorXd& f) const;
  /// DynamicsModel::tensionless_points: their stresses' pulling isotropic parts dropped.
  void release_tension() const;
  void apply_prescribed(double t, Eigen::VectorXd& v, Eigen::VectorXd& a) const;
  /// DynamicsOptions::remedies (defined in dynamics/fluid_remedies.cpp): the checks at
  /// construction, the remedies due after step counters_.steps (before that step's
  /// recomputation of the tables), the supports' current centres, and the integration
  /// points' current positions for those centres.
  void check_fluid_remedies() const;
  void apply_fluid_remedies(double dt);
  Eigen::MatrixXd remedy_centres() const;
  Eigen::MatrixXd remedy_points(const Eigen::MatrixXd& centres) const;

  const Method& method_;
  Discretization d_;
  DynamicsModel model_;
  DynamicsOptions opt_;
  int dim_ = 1, n_ = 0, nq_ = 0;
  double t_ = 0, spacing_ = 0, wave_speed_ = 0;
  DynamicsCounters counters_;
  EnergyBalance energy_;

  Eigen::VectorXd u_, v_, a_, f_int_, f_ext_, inv_mass_;
  Eigen::VectorXd du_, f_new_, fe_new_, v_pred_;  ///< step scratch: no allocation per step
  // Reference (t = 0) configuration, kept for the Eulerian update.
  Eigen::MatrixXd X_, Xq_;
  Eigen::VectorXd V0_, w0_;
  ShapeTable values_at_particles_;  ///< N_J(X_I), for fields at the particles
  /// Eulerian kernel: the trial values at the integration points at t = 0, N_J(X_q), which
  /// carry a point that is not a particle with the material: x_q = X_q + Σ_J N_J(X_q) u_J.
  ShapeTable values_at_points0_;
  Eigen::VectorXd dilation0_;  ///< the t = 0 dilations (support=adaptive scales them)
  // Transposed test table with the reference weights folded in: for particle I the entries
  // (q, w0_q ∇N_I(x_q)), so the force is a gather over particles (no write conflicts).
  std::vector<int> tt_offsets_, tt_point_, tt_next_;
  std::vector<double> tt_grad_;
  /// The Eulerian frame with serial force loops: the force is scattered from the point-major
  /// force table, in the gather's order (each particle's terms by ascending point), so no
  /// particle-major copy is built at every recomputation (bit for bit the gather's sums).
  bool scatter_forces_ = false;
  /// ParticleOrder::hilbert: engine → given numbering of particles and points, the trial and
  /// force tables renumbered (the force table is trial_r_ itself when the two are equal),
  /// the reference weights in the engine's order, and gather/scatter scratch.
  bool renumbered_ = false, force_is_trial_ = false;
  std::vector<int> particle_given_, point_given_;
  ShapeTable trial_r_, force_r_;
  Eigen::VectorXd w0_r_;
  mutable Eigen::VectorXd u_r_, du_r_, f_r_;
  /// Eulerian kernel: neighbour lists and table storage kept between recomputations.
  Retabulation retabulation_;
  // Per integration point: F (Eulerian: integrated in time), the stress the force sums
  // (P, or the Kirchhoff stress τ = J σ in the Eulerian frame), material history.
  mutable std::vector<double> F_, stress_, state_, scratch_F_;
  std::vector<double> committed_F_;
  mutable std::vector<int> nearest_point_;
  mutable Eigen::MatrixXd wall_force_;  ///< scratch of model_.wall_forces (WallTraction::weak)
  mutable Eigen::MatrixXd particle_force_;  ///< scratch of model_.particle_forces  ///< particle_points(), found on the first call
};

/// Parses "lagrangian"/"eulerian" and "verlet"/"newmark", throwing InputError with the valid
/// names otherwise.
KernelFrame kernel_frame_from(const std::string& name);
TimeIntegrator time_integrator_from(const std::string& name);
/// Parses "none"/"hilbert" (ParticleOrder), throwing InputError with the valid names otherwise.
ParticleOrder particle_order_from(const std::string& name);
VolumeAverage volume_average_from(const std::string& name);
KernelCentres kernel_centres_from(const std::string& name);
/// Parses "test"/"variational" (ForceForm), throwing InputError with the valid names otherwise.
ForceForm force_form_from(const std::string& name);

}  // namespace mfv
