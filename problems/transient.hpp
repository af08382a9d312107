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
};

/// Runs `sim` to plan.end_time with a step that lands on every checkpoint: the largest step
/// not above `dt_target` that divides the first checkpoint (or the end time) into whole
/// steps. Fills r.transient (dt, steps, histories, frames), r.cpu.solve (the loop's CPU
/// seconds) and the headline "energy drift": max |K + W_int − W_ext − K₀| over the run,
/// relative to the largest of K₀, the peak kinetic energy and |W_ext|. Shows a progress bar
/// on a terminal (quiet in CI).
void run_transient(ExplicitDynamics& sim, double dt_target, double dt_critical,
                   const TransientPlan& plan, const Params& dynamics, const std::string& label,
                   CaseResult& r);

/// The critical step and the step the parameters ask for (dt, or safety × critical).
struct StepChoice {
  double critical = 0, target = 0;
};
StepChoice choose_step(const ExplicitDynamics& sim, const Params& dynamics);

}  // namespace mfv
