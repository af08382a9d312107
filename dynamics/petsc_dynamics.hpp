/// Total-Lagrangian explicit dynamics on PETSc: the step of ExplicitDynamics (Lagrangian
/// kernel) as distributed sparse linear algebra across MPI ranks.
///
/// With a Lagrangian kernel the tables are fixed, so both force loops are sparse products
/// (001 Table 1):
///   F_q = I + Σ_J u_J ⊗ ∇₀N_J(X_q)          H = (G ⊗ I_dim) u          (MatMult)
///   f_I = Σ_q w_q P_q · ∇₀N^test_I(X_q)      f = (G̃ ⊗ I_dim)ᵀ P         (MatMultTranspose)
/// G is an MPIAIJ matrix with a row per (point q, direction j) and a column per particle J,
/// entry ∂N_J/∂X_j(X_q); G̃ the same for the test functions (the trial ones for
/// force=variational) with the reference weight w_q folded in. MATMAIJ applies them to the
/// interleaved unknowns (u_x, u_y of each particle), so H's entries per point are F − I in
/// ExplicitDynamics's column-major order and one scatter of dim values per ghost particle is
/// the halo of each product (PETSc's own VecScatter; reversed and added for the transpose).
/// Columns (particles) are split into contiguous ranges of their numbers over the ranks, and
/// each point goes with its particle (nodal points) or with the median particle of its
/// support (stress and Gauss points); the rows are numbered rank by rank. The material is
/// called on each rank's own points in batches, as the native engine calls it, with the
/// history kept where the point lives. Velocity Verlet or explicit Newmark with
/// lumped masses, prescribed velocities, external forces, artificial viscosity (Ḟ = G du/dt
/// is one more MatMult) and the energy balance (one MPI_Allreduce per step) follow
/// ExplicitDynamics::step line by line, so one rank matches it to round-off (the products sum
/// a row in PETSc's column order).
///
/// External forces come from the model's callback, which fills every unknown on every rank
/// (each keeps its own entries): O(N) per rank and step, fine for the problems' boundary
/// loads, to be distributed with the set-up.
///
/// Every rank builds the native engine on the whole discretization too: it supplies the
/// initial state (the nodal velocity fit, the initial force), the critical step, and the
/// ExplicitDynamics the problems' callbacks read, into which state() gathers the distributed
/// fields (checkpoints, histories, frames: never every step). Set-up is therefore replicated;
/// the time loop is distributed.
///
/// Not supported (InputError naming the option; use engine=native): the Eulerian frame (its
/// tables change every step), follower pressures and particle forces (they need the current
/// positions of arbitrary particles every step).
#pragma once
#include <memory>

#include "dynamics/dynamics_engine.hpp"

namespace mfv {

/// The communication and storage of one rank's step, for the scaling model.
struct PetscHalo {
  int ranks = 1, rank = 0;
  long owned_points = 0, owned_unknowns = 0;
  /// Ghost unknowns the MatMult for F receives: dim × the columns of G's off-diagonal block.
  long ghost_trial = 0;
  /// Ghost unknowns the MatMultTranspose for f sends and adds: dim × G̃'s off-diagonal columns.
  long ghost_test = 0;
  /// Halo bytes this rank moves per step: 8 (ghost_trial + ghost_test), with viscosity one
  /// more ghost_trial (Ḟ), plus the 4 doubles of the energy reduction.
  long halo_bytes = 0;
  /// Bytes of the two operators' local storage (values and column indices) streamed per step.
  long matrix_bytes = 0;
};

class PetscDynamics final : public DynamicsEngine {
 public:
  /// Initializes PETSc on first use (methods/core/petsc_session.hpp) and runs on
  /// PETSC_COMM_WORLD. Throws InputError for an option it does not support.
  PetscDynamics(const Method& method, Discretization d, DynamicsModel model,
                DynamicsOptions options);
  ~PetscDynamics() override;
  PetscDynamics(const PetscDynamics&) = delete;
  PetscDynamics& operator=(const PetscDynamics&) = delete;

  void set_particle_velocity(const Eigen::MatrixXd& v) override;
  void step(double dt) override;
  double time() const override;
  const EnergyBalance& energy() const override;
  const DynamicsCounters& counters() const override;
  bool fields_finite() const override;
  const ExplicitDynamics& state() override;
  std::string description() const override;

  /// The unknowns (dim·N, interleaved), gathered on every rank (collective).
  Eigen::VectorXd displacement() const;
  Eigen::VectorXd velocity() const;
  PetscHalo halo() const;

 private:
  struct Impl;
  /// Copies the native engine's initial state into the distributed vectors.
  void load_from_native();
  std::unique_ptr<Impl> impl_;
};

}  // namespace mfv
