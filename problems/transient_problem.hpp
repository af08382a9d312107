/// Transient problems (explicit dynamics) as definitions: for a discretized case, the model
/// (material, density, masses, prescribed motion, loads), the initial state, the end time,
/// the checkpoints and what is measured there. The `transient` analysis
/// (analyses/transient.hpp) builds the engine, chooses the step, runs the loop and times it.
#pragma once
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "dynamics/explicit.hpp"
#include "methods/materials/material.hpp"
#include "problems/error_norms.hpp"
#include "problems/profile.hpp"
#include "problems/problem.hpp"

namespace mfv {

/// What a transient run measures: the main error norm (NaN where not measured or not
/// reached) and the problem's headline values.
struct TransientMeasures {
  ErrorNorms errors = ErrorNorms::not_measured();
  std::map<std::string, double> headline;
  std::vector<Profile> profiles;  ///< curves over space (problems/profile.hpp)
};

/// How a run went, for the problem's closing measurements.
struct TransientOutcome {
  double dt = 0, dt_critical = 0;
  long steps = 0;
  bool stopped_early = false;  ///< ended before the end time (unstable, or the problem's stop)
  bool unstable = false;
  double unstable_time = 0;    ///< when the instability was detected (unstable runs)
  double cpu_seconds = 0;      ///< set-up, engine and time loop
  double cpu_loop = 0;         ///< the time loop alone (cpu_seconds includes it)
  /// TransientDefinition::trace after every step, with the times: the history a closing
  /// measurement over the run reads (empty when the definition traces nothing).
  std::vector<double> trace_time;
  std::vector<std::vector<double>> trace;  ///< a row per step, in trace_names' order
};

/// What define() gets besides the discretization: the materials to build the problem's
/// from, and the case's method (some measurements belong to one method's window).
struct TransientInputs {
  const MaterialRegistry& materials;
  std::string method;    ///< registered name
  Params method_params;  ///< resolved
  int nodes = 0;
  Params dynamics;       ///< the transient analysis's parameters, resolved (safety, frame ...)
};

/// One transient case as the problem defines it. Callbacks may keep state between calls
/// (peaks, onset times): they are called in the order of the run, on one thread.
struct TransientDefinition {
  DynamicsModel model;
  /// The material as an external solver is told it (issue 30; docs/external-solvers.md): the
  /// registry name and the parameters model.material was created from. Empty: the problem
  /// cannot be run by an external solver.
  std::string material_name;
  Params material_params;
  /// Particle velocities at t = 0 (dim × N); empty: at rest.
  Eigen::MatrixXd initial_velocity;
  double end_time = 0;
  /// A run of exactly this many steps of the chosen step (a timing study, where every method
  /// must take the same number): end_time becomes steps × dt and `checkpoints` must be
  /// empty. 0: run to end_time.
  long steps = 0;
  /// Times the step must land on (errors are measured there), at_checkpoint's k counts them.
  std::vector<double> checkpoints;
  /// Checkpoints that depend on the chosen step (whole steps near given times); replaces
  /// `checkpoints` when set. May throw InputError for a step the problem cannot use.
  std::function<std::vector<double>(double dt_target, double dt_critical)> step_checkpoints;
  /// The step to take when the case sets no dt (instead of safety × the critical step),
  /// e.g. a Courant number times the finite-element step.
  std::function<double(double dt_critical)> preferred_step;
  std::string label;       ///< what the progress bar shows
  std::string main_error;  ///< what errors.l2_rel measures, with units ("" : none)
  std::string notes;       ///< appended to the engine's description ("gaussian loading")
  /// The units the problem is stated in, for the report's axes: its time unit and the
  /// system every probe, energy and field is in (rod-pulse and notched-beam use mm, ms, kg,
  /// GPa; 2D energies are per unit depth, 1D ones per unit cross-section).
  std::string time_unit = "s";
  std::string unit_system = "SI: m, s, kg, Pa";
  std::function<void(const ExplicitDynamics&, int checkpoint, TransientMeasures&)> at_checkpoint;
  std::vector<std::string> probe_names;
  std::function<std::vector<double>(const ExplicitDynamics&)> probes;
  /// Extra arrays of a VTK frame (exact velocity, error ...) besides velocity,
  /// displacement and stress.
  std::function<void(const ExplicitDynamics&,
                     std::vector<std::pair<std::string, Eigen::MatrixXd>>&)>
      frame_data;
  /// What finish() measures over the whole run (a period from zero crossings, an onset
  /// time): names and the values at the state, recorded after every step into
  /// TransientOutcome::trace, so no state is shared between callbacks. Every step: keep it
  /// to a few numbers (probes, by contrast, are the `samples` rows of the report's history).
  std::vector<std::string> trace_names;
  std::function<std::vector<double>(const ExplicitDynamics&)> trace;
  /// Called after every step; true stops the run (a detector that has seen enough).
  std::function<bool(const ExplicitDynamics&)> stop;
  /// The problem's own instability criterion, after every step: the first non-empty reason
  /// marks the run unstable at that step; the run goes on until `stop` or the generic bound.
  std::function<std::string(const ExplicitDynamics&)> unstable;
  /// After the run, stable or not: the problem's closing measurements, with the run's
  /// outcome and its trace.
  std::function<void(const ExplicitDynamics&, const TransientOutcome&, TransientMeasures&)>
      finish;
};

/// A problem run by the `transient` analysis.
class TransientProblem : public ParticleProblem {
 public:
  std::vector<std::string> analyses() const override { return {"transient"}; }
  /// The run of the case whose discretization at t = 0 is `d`.
  virtual TransientDefinition define(const Discretization& d, const TransientInputs& in) const = 0;
};

}  // namespace mfv
