#include "problems/transient.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "reports/progress.hpp"
#include "verify/runner.hpp"

namespace mfv {

ParamSchema dynamics_schema(const std::string& default_integrator, double default_safety) {
  ParamSchema s{
      ParamSpec::choice("frame", "lagrangian", {"lagrangian", "eulerian"},
                        "kernel W(X - X_J) fixed at t = 0 (001 Table 1) or W(x - x_J(t)) "
                        "recomputed (Table 2)"),
      ParamSpec::count("update_every", 1, 1, "Eulerian kernel: steps between recomputations"),
      ParamSpec::choice("integrator", default_integrator, {"verlet", "newmark"},
                        "central differences (velocity Verlet) or the explicit Newmark "
                        "predictor-corrector of 004 III"),
      ParamSpec::number("gamma", 0.5, "Newmark gamma (>= 0.5; 0.5 is central differences)"),
      ParamSpec::positive("safety", default_safety,
                          "time step over the critical step 2/omega_max (when dt = 0)"),
      ParamSpec::number("dt", 0.0, "time step; 0: safety times the critical step"),
      ParamSpec::number("av_alpha", 0.0, "artificial viscosity, linear (Monaghan alpha)"),
      ParamSpec::number("av_beta", 0.0, "artificial viscosity, quadratic (Monaghan beta)"),
      ParamSpec::count("threads", 0, 0, "OpenMP threads for the force loops (0: all cores)"),
      ParamSpec::count("frames", 12, 0, "VTK snapshots per run (0: none)"),
      ParamSpec::count("samples", 200, 2, "rows of the time histories per run"),
  };
  return s;
}

DynamicsOptions dynamics_options(const Params& p) {
  DynamicsOptions o;
  o.frame = kernel_frame_from(p.text("frame"));
  o.update_every = p.integer("update_every");
  o.integrator = time_integrator_from(p.text("integrator"));
  o.newmark_gamma = p.number("gamma");
  o.viscosity.alpha = p.number("av_alpha");
  o.viscosity.beta = p.number("av_beta");
  if (o.viscosity.alpha < 0 || o.viscosity.beta < 0)
    throw InputError(fmt::format("artificial viscosity alpha = {}, beta = {}: both must be >= 0",
                                 o.viscosity.alpha, o.viscosity.beta));
  o.threads = p.integer("threads");
  return o;
}

StepChoice choose_step(const ExplicitDynamics& sim, const Params& p) {
  StepChoice c;
  c.critical = sim.critical_time_step();
  c.target = p.number("dt") > 0 ? p.number("dt") : p.number("safety") * c.critical;
  if (p.number("dt") < 0)
    throw InputError(fmt::format("dt = {} must be >= 0 (0: from the critical step)",
                                 p.number("dt")));
  return c;
}

void run_transient(ExplicitDynamics& sim, double dt_target, double dt_critical,
                   const TransientPlan& plan, const Params& dynamics, const std::string& label,
                   CaseResult& r) {
  if (!(plan.end_time > 0)) throw InputError("a transient run needs a positive end time");
  const double unit = plan.checkpoints.empty() ? plan.end_time : plan.checkpoints.front();
  // The step counts are checked as floating-point numbers before they become integers: a
  // tiny dt would overflow the conversion (undefined) and silently run one huge step.
  if (!(dt_target > 0) || !std::isfinite(dt_target))
    throw InputError(fmt::format("{}: time step dt = {} (critical step {}) must be positive and "
                                 "finite; set dt > 0 or safety > 0",
                                 label, dt_target, dt_critical));
  constexpr double kMaxSteps = 1e9;
  const double per_unit_real = std::ceil(unit / dt_target - 1e-9);
  const double steps_real = plan.end_time / unit * per_unit_real;
  if (!(per_unit_real <= kMaxSteps && steps_real <= kMaxSteps))
    throw InputError(fmt::format("{}: time step dt = {:.3g} gives {:.3g} steps to the end time "
                                 "t = {:.3g}, more than the {:.0e} a run may take; raise dt (the "
                                 "critical step is {:.3g}; dt=0 uses safety × it) or shorten the "
                                 "run (end_time, transits)",
                                 label, dt_target, steps_real, plan.end_time, kMaxSteps,
                                 dt_critical));
  const long per_unit = std::max(1L, static_cast<long>(per_unit_real));
  const double dt = unit / per_unit;
  const long steps = std::max(1L, std::lround(plan.end_time / dt));
  std::vector<long> check_steps;
  for (double t : plan.checkpoints) check_steps.push_back(std::lround(t / dt));

  TransientData& td = r.transient;
  td.dt = dt;
  td.dt_critical = dt_critical;
  td.end_time = steps * dt;
  td.dynamics = sim.description();
  td.history_columns = {"time", "kinetic", "internal work", "external work", "energy balance"};
  for (const auto& n : plan.probe_names) td.history_columns.push_back(n);
  const int samples = dynamics.integer("samples");
  const int frames = dynamics.integer("frames");
  const long sample_every = std::max(1L, steps / samples);
  const long frame_every = frames > 0 ? std::max(1L, steps / frames) : 0;

  double worst = 0, scale = std::abs(sim.energy().initial);
  double energy_in = std::abs(sim.energy().initial);  // E_in of kEnergyBound
  auto record = [&]() {
    const EnergyBalance& e = sim.energy();
    std::vector<double> row{sim.time(), e.kinetic, e.internal_work, e.external_work,
                            e.balance()};
    if (plan.probes)
      for (double v : plan.probes(sim)) row.push_back(v);
    td.history.push_back(std::move(row));
    if (sim.displacement().size() > 0)
      td.max_displacement = std::max(td.max_displacement, sim.displacement().cwiseAbs().maxCoeff());
  };
  auto snapshot = [&]() {
    TransientData::Frame f;
    f.time = sim.time();
    f.x = sim.particle_positions();
    f.data.emplace_back("velocity", sim.particle_velocity());
    f.data.emplace_back("displacement", sim.particle_displacement());
    const Eigen::MatrixXd sigma = sim.particle_cauchy_stress();
    if (sim.dim() == 1) {
      f.data.emplace_back("stress", sigma);
    } else {  // Voigt xx, yy, xy from the column-major 2×2 blocks
      Eigen::MatrixXd voigt(3, sigma.cols());
      voigt.row(0) = sigma.row(0);
      voigt.row(1) = sigma.row(3);
      voigt.row(2) = sigma.row(2);
      f.data.emplace_back("stress", std::move(voigt));
    }
    if (plan.frame_data) plan.frame_data(sim, f);
    td.frames.push_back(std::move(f));
  };
  record();
  if (frame_every) snapshot();

  ProgressBar bar(label, steps);
  const double t0 = cpu_seconds();
  long done = 0;
  auto mark_unstable = [&](long s, std::string why) {
    if (!td.instability) td.instability = TransientData::Instability{s, sim.time(), std::move(why)};
  };
  for (long s = 1; s <= steps; ++s) {
    sim.step(dt);
    done = s;
    const EnergyBalance& e = sim.energy();
    // The generic blow-up checks come before the checkpoints: a checkpoint at a step that
    // blew up is not reached.
    if (!std::isfinite(e.kinetic) || !std::isfinite(e.internal_work) ||
        !std::isfinite(e.external_work) || !sim.displacement().allFinite() ||
        !sim.velocity().allFinite()) {
      mark_unstable(s, fmt::format("the fields went non-finite (kinetic energy {:.3g}, internal "
                                   "work {:.3g})",
                                   e.kinetic, e.internal_work));
      break;
    }
    energy_in = std::max(energy_in, std::abs(e.external_work));
    if (energy_in > 0 && e.kinetic > kEnergyBound * energy_in) {
      mark_unstable(s, fmt::format("kinetic energy {:.3g} above {:g} × the energy put in "
                                   "(E₀ + max |W_ext| = {:.3g}; the energy balance allows at "
                                   "most about 1 ×)",
                                   e.kinetic, kEnergyBound, energy_in));
      record();
      if (frame_every) snapshot();
      break;
    }
    scale = std::max({scale, e.kinetic, std::abs(e.external_work)});
    worst = std::max(worst, std::abs(e.balance()));
    for (std::size_t c = 0; c < check_steps.size(); ++c)
      if (check_steps[c] == s && plan.at_checkpoint) plan.at_checkpoint(sim, static_cast<int>(c));
    if (s % sample_every == 0 || s == steps) record();
    if (frame_every && (s % frame_every == 0 || s == steps)) snapshot();
    bar.update(s, sim.time());
    if (plan.unstable && !td.instability)
      if (std::string why = plan.unstable(sim); !why.empty()) mark_unstable(s, std::move(why));
    if (plan.stop && plan.stop(sim)) break;
  }
  bar.finish();
  r.cpu.solve = cpu_seconds() - t0;
  td.steps = done;
  td.stopped_early = done < steps;
  td.retabulations = sim.counters().retabulations;
  r.headline["energy drift"] = scale > 0 ? worst / scale : 0.0;
}

}  // namespace mfv
