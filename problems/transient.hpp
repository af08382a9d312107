/// What every transient problem shares: the explicit-dynamics parameters a case can set
/// (kernel frame, integrator, time step, viscosity, threads, outputs) and the driver that
/// runs the time loop with exact checkpoints, energy histories, VTK frames and progress.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "dynamics/explicit.hpp"
#include "problems/problem.hpp"

namespace mfv {

/// Parameters of the engine, appended to a transient problem's own schema:
/// frame (lagrangian|eulerian), update_every, integrator (verlet|newmark), gamma, safety,
/// dt (0: safety × the critical step), av_alpha, av_beta (viscosity), threads, frames (VTK
/// snapshots per run), samples (history rows per run).
ParamSchema dynamics_schema(const std::string& default_integrator = "verlet",
                            double default_safety = 0.8);
DynamicsOptions dynamics_options(const Params& resolved);

/// A time loop to run: end time, times that must be hit exactly (errors are measured
/// there), and the problem's probes and extra VTK arrays.
struct TransientPlan {
  double end_time = 0;
  std::vector<double> checkpoints;
  std::function<void(const ExplicitDynamics&, int checkpoint)> at_checkpoint;
  std::vector<std::string> probe_names;
  std::function<std::vector<double>(const ExplicitDynamics&)> probes;
  /// Extra arrays of a VTK frame (exact velocity, error...), besides velocity,
  /// displacement and stress.
  std::function<void(const ExplicitDynamics&, TransientData::Frame&)> frame_data;
  /// Called after every step; returning true stops the run (a detector that has seen enough,
  /// e.g. an instability that has grown by orders of magnitude).
  std::function<bool(const ExplicitDynamics&)> stop;
  /// The problem's own instability criterion (e.g. a peak velocity above twice what the
  /// energy bound allows), called after every step: the first non-empty reason marks the run
  /// unstable at that step (TransientData::instability). The run goes on until `stop` or the
  /// generic bound below ends it, so the growth can be measured.
  std::function<std::string(const ExplicitDynamics&)> unstable;
};

/// The generic blow-up bound of run_transient. The engine keeps the balance
/// K + W_int − W_ext = E₀ (E₀ the energy at t = 0) to the integrator's O((ω Δt)²) shadow-
/// energy error, which stays below E₀ for any step under the critical one. With a stored
/// energy W_int that is not negative about the start, a stable run therefore has
/// K ≤ E₀ + max_t |W_ext| = E_in, up to a factor of order one. A kinetic energy above
/// kEnergyBound · E_in (velocities 100 times what the balance allows) can only be a blow-up:
/// an instability grows exponentially and crosses it a few dozen steps after its onset. Runs
/// with E_in = 0 (nothing set in motion) are checked for non-finite values only.
inline constexpr double kEnergyBound = 1e4;

/// Runs `sim` to plan.end_time with a step that lands on every checkpoint: the largest step
/// not above `dt_target` that divides the first checkpoint (or the end time) into whole
/// steps. Fills r.transient (dt, steps, histories, frames), r.cpu.solve (the loop's CPU
/// seconds) and the headline "energy drift": max |K + W_int − W_ext − K₀| over the steps
/// taken, relative to the largest of K₀, the peak kinetic energy and |W_ext|. Shows a
/// progress bar on a terminal (quiet in CI).
/// Stops at once, with r.transient.instability set ("unstable at step k, t = …"), at the
/// first step whose kinetic energy, work or fields are not finite or whose kinetic energy
/// exceeds kEnergyBound · E_in; the checkpoints after it are not reached (the problem leaves
/// their errors NaN). plan.unstable may mark the run unstable without stopping it.
void run_transient(ExplicitDynamics& sim, double dt_target, double dt_critical,
                   const TransientPlan& plan, const Params& dynamics, const std::string& label,
                   CaseResult& r);

/// The critical step and the step the parameters ask for (dt, or safety × critical).
struct StepChoice {
  double critical = 0, target = 0;
};
StepChoice choose_step(const ExplicitDynamics& sim, const Params& dynamics);

}  // namespace mfv
