/// The seam between the transient time loop (analyses/transient.cpp, run_transient) and an
/// explicit engine: the native ExplicitDynamics (NativeDynamics, an owning adaptor) or the
/// distributed total-Lagrangian one on PETSc (dynamics/petsc_dynamics.hpp).
///
/// The loop needs only stepping, the time, the energy balance, a blow-up check and the step
/// counters after every step; the problems' callbacks (probes, checkpoints, frames) read an
/// ExplicitDynamics, which a distributed engine fills with its gathered fields only when
/// asked (state()), never every step.
#pragma once
#include <memory>
#include <string>

#include "dynamics/explicit.hpp"

namespace mfv {

class DynamicsEngine {
 public:
  virtual ~DynamicsEngine() = default;
  /// ExplicitDynamics::set_particle_velocity.
  virtual void set_particle_velocity(const Eigen::MatrixXd& v) = 0;
  virtual void step(double dt) = 0;
  virtual double time() const = 0;
  virtual const EnergyBalance& energy() const = 0;
  virtual const DynamicsCounters& counters() const = 0;
  /// Whether every displacement and velocity unknown is finite (checked after every step).
  virtual bool fields_finite() const = 0;
  /// The engine the problems' callbacks read, holding the current state (a distributed
  /// engine gathers its fields into it on every rank; repeated calls within a step are free).
  virtual const ExplicitDynamics& state() = 0;
  virtual std::string description() const = 0;
};

/// The native engine behind the seam: every call forwards, so a run through it is the
/// ExplicitDynamics run bit for bit.
class NativeDynamics final : public DynamicsEngine {
 public:
  NativeDynamics(const Method& method, Discretization d, DynamicsModel model,
                 DynamicsOptions options)
      : sim_(method, std::move(d), std::move(model), options) {}
  void set_particle_velocity(const Eigen::MatrixXd& v) override { sim_.set_particle_velocity(v); }
  void step(double dt) override { sim_.step(dt); }
  double time() const override { return sim_.time(); }
  const EnergyBalance& energy() const override { return sim_.energy(); }
  const DynamicsCounters& counters() const override { return sim_.counters(); }
  bool fields_finite() const override {
    return sim_.displacement().allFinite() && sim_.velocity().allFinite();
  }
  const ExplicitDynamics& state() override { return sim_; }
  std::string description() const override { return sim_.description(); }

 private:
  ExplicitDynamics sim_;
};

/// The engine `name` names: "native" (NativeDynamics) or "petsc" (PetscDynamics, which
/// refuses with InputError the options it does not support). Throws InputError for any
/// other name.
std::unique_ptr<DynamicsEngine> make_dynamics_engine(const std::string& name,
                                                     const Method& method, Discretization d,
                                                     DynamicsModel model,
                                                     DynamicsOptions options);

}  // namespace mfv
