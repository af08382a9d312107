/// The `transient` analysis: explicit dynamics of a TransientProblem's definition
/// (problems/transient_problem.hpp). Its parameters are the engine's (kernel frame,
/// integrator, time step, viscosity, threads, outputs); it builds the engine, chooses the
/// step and runs the time loop with exact checkpoints, energy histories, VTK frames and
/// progress, and stops a run that blows up.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "analyses/case.hpp"
#include "dynamics/dynamics_engine.hpp"
#include "problems/transient_problem.hpp"

namespace mfv {

/// Parameters of the engine, the analysis's schema (a problem changes their defaults by
/// Problem::analysis_defaults):
/// frame (lagrangian|eulerian), update_every, integrator (verlet|newmark), gamma, safety,
/// dt (0: safety × the critical step), av_alpha, av_beta (viscosity), threads, engine
/// (native|petsc: dynamics/dynamics_engine.hpp), frames (VTK snapshots per run), samples
/// (history rows per run).
ParamSchema dynamics_schema(const std::string& default_integrator = "verlet",
                            double default_safety = 0.8);
DynamicsOptions dynamics_options(const Params& resolved);

/// The generic blow-up bound of run_transient. The engine keeps the balance
/// K + W_int − W_ext = E₀ (E₀ the energy at t = 0) to the integrator's O((ω Δt)²) shadow-
/// energy error, which stays below E₀ for any step under the critical one. With a stored
/// energy W_int that is not negative about the start, a stable run therefore has
/// K ≤ E₀ + max_t |W_ext| = E_in, up to a factor of order one. A kinetic energy above
/// kEnergyBound · E_in (velocities 100 times what the balance allows) can only be a blow-up:
/// an instability grows exponentially and crosses it a few dozen steps after its onset. Runs
/// with E_in = 0 (nothing set in motion) are checked for non-finite values only.
inline constexpr double kEnergyBound = 1e4;

/// The default `drift_bound`: the largest energy drift (the headline "energy drift") a run
/// may end with before it is judged unstable. The stable runs of the default suite end below
/// 0.17 (the prestressed rod at 0.8 of its critical step), the blown-up ones above 0.86; a
/// drift of one half means half the run's energy is unaccounted for.
inline constexpr double kDriftBound = 0.5;
/// The fewest steps a run must take before its drift is judged against `drift_bound`.
inline constexpr long kMinDriftSteps = 20;

/// Runs `sim` to def.end_time with a step that lands on every checkpoint: the largest step
/// not above `dt_target` that divides the first checkpoint (or the end time) into whole
/// steps. Fills r's TransientData (dt, steps, histories, frames), r.cpu.solve (the loop's
/// CPU seconds) and m's headline "energy drift": max |K + W_int − W_ext − K₀| over the steps
/// taken, relative to the largest of K₀, the peak kinetic energy and |W_ext|. Shows a
/// progress bar on a terminal (quiet in CI).
/// Stops at once, with the instability set ("unstable at step k, t = …"), at the first step
/// whose kinetic energy, work or fields are not finite or whose kinetic energy exceeds
/// kEnergyBound · E_in; the checkpoints after it are not reached (their values stay NaN).
/// def.unstable may mark the run unstable without stopping it. The problem's callbacks read
/// sim.state(): a distributed engine gathers its fields for them (at every step only when the
/// problem sets `unstable`, `stop` or `trace`). def.trace's values after every step go to
/// outcome->trace (when `outcome` is given).
void run_transient(DynamicsEngine& sim, double dt_target, double dt_critical,
                   const TransientDefinition& def, const std::vector<double>& checkpoints,
                   const Params& dynamics, TransientMeasures& m, CaseResult& r,
                   TransientOutcome* outcome = nullptr);

/// The critical step and the step the parameters ask for (dt, or safety × critical).
struct StepChoice {
  double critical = 0, target = 0;
};
StepChoice choose_step(const ExplicitDynamics& sim, const Params& dynamics);

/// ", at most K points on the uncorrected-kernel fallback" for a run whose recomputed
/// supports degenerated (TransientData::degenerate_peak > 0), "" otherwise.
std::string degenerate_note(long degenerate_peak);

}  // namespace mfv
