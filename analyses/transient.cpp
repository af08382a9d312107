#include "analyses/transient.hpp"

#include "analyses/analysis.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <memory>

#include <fmt/format.h>

#include "analyses/report_section.hpp"
#include "dynamics/external_solver.hpp"
#include "methods/core/clock.hpp"
#include "methods/core/errors.hpp"
#include "methods/core/signal_cleanup.hpp"
#include "reports/progress.hpp"

namespace mfv {

ParamSchema dynamics_schema(const std::string& default_integrator, double default_safety) {
  ParamSchema s{
      ParamSpec::choice("frame", "lagrangian", {"lagrangian", "eulerian"},
                        "kernel W(X - X_J) fixed at t = 0 (001 Table 1) or W(x - x_J(t)) "
                        "recomputed (Table 2)"),
      ParamSpec::choice("volume_average", "off", {"off", "patch"},
                        "off: each point's own det F; patch: F-bar, the volume change of each "
                        "particle's patch at every point (dynamics/explicit.hpp VolumeAverage; "
                        "native engine)"),
      ParamSpec::choice("wall_traction", "off", {"off", "weak"},
                        "off: the problem's walls act as forces at the particles only; weak: "
                        "also as the weak form's boundary term at the walls, through the test "
                        "functions (dynamics/explicit.hpp WallTraction; weak-form methods, "
                        "problems with rigid walls, native engine)"),
      ParamSpec::choice("centres", "coefficients", {"coefficients", "interpolated"},
                        "Eulerian kernel: supports centred at X + the particles' unknowns, or "
                        "at X + the trial field at the particles (their material positions; "
                        "differs for MLS/RKPM methods; dynamics/explicit.hpp KernelCentres)"),
      ParamSpec::count("update_every", 1, 1, "Eulerian kernel: steps between recomputations"),
      ParamSpec::choice("support", "fixed", {"fixed", "adaptive", "stretch"},
                        "Eulerian kernel: supports keep their t = 0 radii (fixed) or follow the "
                        "material, a_I = a_I(0) J_I^(1/d) (adaptive) or a_I(0) times the "
                        "largest principal stretch (stretch); 001 eq 16's h(x, t)"),
      ParamSpec::number("skin", 0.3,
                        "Eulerian kernel: skin of the neighbour lists over the spacing, in "
                        "[0, 10]; searched afresh only when points and particles have moved "
                        "more than it (0: at every recomputation); the tables do not depend "
                        "on it"),
      ParamSpec::choice("integrator", default_integrator, {"verlet", "newmark"},
                        "central differences (velocity Verlet) or the explicit Newmark "
                        "predictor-corrector of 004 III"),
      ParamSpec::number("gamma", 0.5, "Newmark gamma (>= 0.5; 0.5 is central differences)"),
      ParamSpec::positive("safety", default_safety,
                          "time step over the critical step 2/omega_max (when dt = 0)"),
      ParamSpec::number("dt", 0.0, "time step; 0: safety times the critical step"),
      ParamSpec::number("av_alpha", 0.0, "artificial viscosity, linear (Monaghan alpha)"),
      ParamSpec::number("av_beta", 0.0, "artificial viscosity, quadratic (Monaghan beta)"),
      ParamSpec::choice("force", "test", {"test", "variational"},
                        "internal force from the method's test functions (as published) or "
                        "the transpose of its trial gradient, which makes the internal power "
                        "the rate of stored energy (Bonet & Lok 1999; dynamics/explicit.hpp)"),
      ParamSpec::count("threads", 0, 0, "OpenMP threads for the force loops (0: all cores)"),
      ParamSpec::choice("reorder", "none", {"none", "hilbert"},
                        "particles and points renumbered along the Hilbert curve inside the "
                        "engine (Lagrangian kernel only), so that the force loops read nearby "
                        "memory at 10^5-10^6 particles or for unordered sets; the problem and "
                        "the report keep the particle numbering. Default none: sums over "
                        "particles keep their order and the suite's numbers stay bit for bit"),
      ParamSpec::choice("engine", "native", {"native", "petsc"},
                        "native (OpenMP, every option) or petsc: the total-Lagrangian step as "
                        "PETSc sparse products across the MPI ranks (dynamics/petsc_dynamics.hpp; "
                        "Lagrangian kernel only)"),
      ParamSpec::positive("drift_bound", kDriftBound,
                          "largest energy drift a run may end with, relative to its energy "
                          "(max |K + W_int - W_ext - E0| over max(E0, K, |W_ext|)); above it "
                          "the run is unstable"),
      ParamSpec::choice("density_filter", "off", {"off", "shepard", "mls"},
                        "Eulerian kernel, fluids: re-initialize the density every "
                        "density_filter_every steps by its Shepard or MLS kernel average "
                        "(Colagrossi & Landrini 2003; dynamics/fluid_remedies.hpp)"),
      ParamSpec::count("density_filter_every", 20, 1,
                       "steps between density re-initializations (density_filter)"),
      ParamSpec::number("density_diffusion", 0.0,
                        "Eulerian kernel, fluids: delta of the delta-SPH diffusive term "
                        "delta h c0 sum psi_ij . grad W_ij V_j in the continuity equation, in "
                        "[0, 1] (0.1 usual; 0: off; Molteni & Colagrossi 2009, Antuono et al. "
                        "2010; dynamics/fluid_remedies.hpp)"),
      ParamSpec::choice("density_diffusion_form", "antuono", {"antuono", "molteni"},
                        "psi_ij of the density diffusion: with the renormalized density "
                        "gradients subtracted (antuono, delta-SPH) or without (molteni)"),
      ParamSpec::number("shifting", 0.0,
                        "Eulerian kernel: particle shifting dr = -D h^2 grad C at every "
                        "recomputation, D in [0, 1] (0: off; Xu et al. 2009, Lind et al. 2012; "
                        "dynamics/fluid_remedies.hpp)"),
      ParamSpec::choice("shifting_form", "fickian", {"fickian", "xu"},
                        "particle shifting: Lind et al.'s Fickian -D h^2 grad C, or Xu et al.'s "
                        "repulsion D U_max dt sum (rbar^2/r^2) n of the neighbours"),
      ParamSpec::number("shifting_surface", 0.95,
                        "particle concentration C below which shifting moves a particle "
                        "tangentially only (free surface, walls; 1.02 inside the lattice)"),
      ParamSpec::count("frames", 12, 0, "VTK snapshots per run (0: none)"),
      ParamSpec::count("samples", 200, 2, "rows of the time histories per run"),
  };
  return s;
}

DynamicsOptions dynamics_options(const Params& p) {
  DynamicsOptions o;
  o.frame = kernel_frame_from(p.text("frame"));
  o.update_every = p.integer("update_every");
  o.volume_average = volume_average_from(p.text("volume_average"));
  o.kernel_centres = kernel_centres_from(p.text("centres"));
  o.wall_traction = wall_traction_from(p.text("wall_traction"));
  o.neighbour_skin = p.number("skin");
  if (!(o.neighbour_skin >= 0 && o.neighbour_skin <= 10))
    throw InputError(fmt::format("skin = {} must be in [0, 10] (spacings); 0.3 is the default, "
                                 "0 searches the neighbours afresh at every recomputation",
                                 o.neighbour_skin));
  o.integrator = time_integrator_from(p.text("integrator"));
  o.newmark_gamma = p.number("gamma");
  o.viscosity.alpha = p.number("av_alpha");
  o.viscosity.beta = p.number("av_beta");
  if (o.viscosity.alpha < 0 || o.viscosity.beta < 0)
    throw InputError(fmt::format("artificial viscosity alpha = {}, beta = {}: both must be >= 0",
                                 o.viscosity.alpha, o.viscosity.beta));
  o.force = force_form_from(p.text("force"));
  o.threads = p.integer("threads");
  o.order = particle_order_from(p.text("reorder"));
  o.support = support_rule_from(p.text("support"));
  o.remedies.filter = density_filter_from(p.text("density_filter"));
  o.remedies.filter_every = p.integer("density_filter_every");
  o.remedies.diffusion = p.number("density_diffusion");
  o.remedies.diffusion_form = diffusion_form_from(p.text("density_diffusion_form"));
  o.remedies.shifting = p.number("shifting");
  o.remedies.shifting_surface = p.number("shifting_surface");
  o.remedies.shifting_form = shifting_form_from(p.text("shifting_form"));
  o.remedies.validate();
  if (o.remedies.any() && p.text("engine") != "native")
    throw InputError("density_filter, density_diffusion and shifting run on the native engine "
                     "only (engine=native)");
  if (o.support != SupportRule::fixed && p.text("engine") != "native")
    throw InputError("support=adaptive|stretch runs on the native engine only (engine=native); the "
                     "PETSc engine keeps the t = 0 supports");
  return o;
}

std::string degenerate_note(long degenerate_peak) {
  return degenerate_peak > 0
             ? fmt::format(", at most {} points on the uncorrected-kernel fallback of degenerate "
                           "supports",
                           degenerate_peak)
             : "";
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

void run_transient(DynamicsEngine& sim, double dt_target, double dt_critical,
                   const TransientDefinition& plan, const std::vector<double>& checkpoints,
                   const Params& dynamics, TransientMeasures& m, CaseResult& r,
                   TransientOutcome* outcome) {
  const std::string& label = plan.label;
  if (!(plan.end_time > 0)) throw InputError("a transient run needs a positive end time");
  const double unit = checkpoints.empty() ? plan.end_time : checkpoints.front();
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
  for (double t : checkpoints) check_steps.push_back(std::lround(t / dt));

  TransientData& td = r.data<TransientData>();
  td.dt = dt;
  td.dt_critical = dt_critical;
  // Central differences are stable only for dt ≤ 2/ω_max. The critical step is the run's own
  // (a Rayleigh quotient of the power iteration, so it lies at or above the true one): a step
  // above it is unstable whatever the run shows before its end time. A blow-up names it in
  // its reason; a run that ends without one is flagged at step 0 (after the loop).
  const std::string above_critical =
      std::isfinite(dt_critical) && dt_critical > 0 && dt > dt_critical * (1 + 1e-9)
          ? fmt::format("the time step dt = {:.6g} is {:.4g} × the critical step 2/ω_max = "
                        "{:.6g} the run computed: central differences are unstable above it",
                        dt, dt / dt_critical, dt_critical)
          : std::string();
  td.end_time = steps * dt;
  td.dynamics = sim.description();
  td.history_columns = {"time", "kinetic", "internal work", "external work", "energy balance"};
  for (const auto& n : plan.probe_names) td.history_columns.push_back(n);
  const int samples = dynamics.integer("samples");
  const int frames = dynamics.integer("frames");
  const long sample_every = std::max(1L, steps / samples);
  const long frame_every = frames > 0 ? std::max(1L, steps / frames) : 0;

  double worst = 0, scale = std::abs(sim.energy().initial);
  long worst_step = 0;
  double worst_time = 0;
  double energy_in = std::abs(sim.energy().initial);  // E_in of kEnergyBound
  auto record = [&]() {
    const EnergyBalance& e = sim.energy();
    std::vector<double> row{sim.time(), e.kinetic, e.internal_work, e.external_work,
                            e.balance()};
    const ExplicitDynamics& now = sim.state();
    if (plan.probes)
      for (double v : plan.probes(now)) row.push_back(v);
    td.history.push_back(std::move(row));
    if (now.displacement().size() > 0)
      td.max_displacement = std::max(td.max_displacement, now.displacement().cwiseAbs().maxCoeff());
  };
  auto snapshot = [&]() {
    const ExplicitDynamics& now = sim.state();
    TransientData::Frame f;
    f.time = now.time();
    f.x = now.particle_positions();
    f.data.emplace_back("velocity", now.particle_velocity());
    f.data.emplace_back("displacement", now.particle_displacement());
    const Eigen::MatrixXd sigma = now.particle_cauchy_stress();
    if (now.dim() == 1) {
      f.data.emplace_back("stress", sigma);
    } else {  // Voigt xx, yy, xy from the column-major 2×2 blocks
      Eigen::MatrixXd voigt(3, sigma.cols());
      voigt.row(0) = sigma.row(0);
      voigt.row(1) = sigma.row(3);
      voigt.row(2) = sigma.row(2);
      f.data.emplace_back("stress", std::move(voigt));
    }
    if (plan.frame_data) plan.frame_data(now, f.data);
    td.frames.push_back(std::move(f));
  };
  record();
  if (frame_every) snapshot();

  ProgressBar bar(label, steps);
  const double t0 = cpu_seconds();
  long done = 0;
  auto mark_unstable = [&](long s, std::string why) {
    if (!above_critical.empty()) why += " (" + above_critical + ")";
    if (!td.instability) td.instability = TransientData::Instability{s, sim.time(), std::move(why)};
  };
  // The loop's CPU time is recorded however the loop ends (a collapsed particle arrangement
  // throws out of a step).
  struct LoopClock {
    CaseResult& r;
    double t0;
    ~LoopClock() { r.cpu.solve = cpu_seconds() - t0; }
  } loop_clock{r, t0};
  for (long s = 1; s <= steps; ++s) {
    sim.step(dt);
    done = s;
    const EnergyBalance& e = sim.energy();
    // The generic blow-up checks come before the checkpoints: a checkpoint at a step that
    // blew up is not reached.
    if (!std::isfinite(e.kinetic) || !std::isfinite(e.internal_work) ||
        !std::isfinite(e.external_work) || !sim.fields_finite()) {
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
    if (std::abs(e.balance()) > worst) {
      worst = std::abs(e.balance());
      worst_step = s;
      worst_time = sim.time();
    }
    for (std::size_t c = 0; c < check_steps.size(); ++c)
      if (check_steps[c] == s && plan.at_checkpoint)
        plan.at_checkpoint(sim.state(), static_cast<int>(c), m);
    if (s % sample_every == 0 || s == steps) record();
    if (frame_every && (s % frame_every == 0 || s == steps)) snapshot();
    bar.update(s, sim.time());
    if (plan.unstable && !td.instability)
      if (std::string why = plan.unstable(sim.state()); !why.empty())
        mark_unstable(s, std::move(why));
    if (plan.trace && outcome) {
      outcome->trace_time.push_back(sim.time());
      outcome->trace.push_back(plan.trace(sim.state()));
    }
    if (plan.stop && plan.stop(sim.state())) break;
  }
  bar.finish();
  // The energy balance over the whole run: a step above the critical one, or a growth too
  // slow to cross kEnergyBound before the end, leaves it broken while every field stays finite
  // (issue 26: rod-pulse at 1.28 × the critical step ended with a drift of 3.1 and passed).
  // Judged on runs of kMinDriftSteps or more: the first steps of a run started by a load carry
  // an O(1) start-up error of the balance (a steel ring's first step reads a drift of 1), and
  // a run that short above its critical step is flagged by that rule above.
  const double drift_bound = dynamics.number("drift_bound");
  if (!td.instability && done >= kMinDriftSteps && scale > 0 && worst / scale > drift_bound) {
    const std::string why =
        fmt::format("the energy balance drifted by {:.3g} of the run's energy, above the "
                    "bound {:g} (drift_bound; a stable run stays within a few per cent), "
                    "largest at step {}, t = {:.6g}",
                    worst / scale, drift_bound, worst_step, worst_time);
    td.instability = TransientData::Instability{
        worst_step, worst_time, above_critical.empty() ? why : why + " (" + above_critical + ")"};
  }
  if (!td.instability && !above_critical.empty())
    td.instability = TransientData::Instability{0, 0.0, above_critical};
  td.steps = done;
  td.stopped_early = done < steps;
  td.retabulations = sim.counters().retabulations;
  td.neighbour_rebuilds = sim.counters().neighbour_rebuilds;
  td.degenerate_peak = sim.counters().degenerate_peak;
  m.headline["energy drift"] = scale > 0 ? worst / scale : 0.0;
}

namespace {

/// Case directories of runs that died without cleaning up (SIGKILL, a crash): named
/// mfv-external-<pid>-XXXXXX, swept when their pid no longer runs, they are this user's, an
/// hour has passed since they changed, and they were not kept (keep=1 writes .mfv-keep).
void sweep_stale_case_directories(const std::filesystem::path& tmp) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto now = fs::file_time_type::clock::now();
  for (fs::directory_iterator it(tmp, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const std::string prefix = "mfv-external-";
    if (name.rfind(prefix, 0) != 0) continue;
    const auto dash = name.find('-', prefix.size());
    if (dash == std::string::npos || dash == prefix.size()) continue;
    const std::string digits = name.substr(prefix.size(), dash - prefix.size());
    if (digits.size() > 9 || !std::all_of(digits.begin(), digits.end(), ::isdigit)) continue;
    const pid_t pid = static_cast<pid_t>(std::stol(digits));
    if (pid == ::getpid() || ::kill(pid, 0) == 0 || errno != ESRCH) continue;
    struct stat st {};
    if (::lstat(it->path().c_str(), &st) != 0 || !S_ISDIR(st.st_mode) || st.st_uid != ::geteuid())
      continue;
    std::error_code e2;
    if (fs::exists(it->path() / ".mfv-keep", e2)) continue;
    const auto changed = fs::last_write_time(it->path(), e2);
    if (e2 || now - changed < std::chrono::hours(1)) continue;
    fs::remove_all(it->path(), e2);
  }
}

/// The case directory of an external run: removed afterwards unless kept, also when a signal
/// kills mfv (after the solver's process group: signal_cleanup.hpp runs the latest first).
struct CaseDirectory {
  std::filesystem::path path;
  bool keep = false;
  std::unique_ptr<OnSignal> on_signal;
  CaseDirectory() {
    sweep_stale_case_directories(std::filesystem::temp_directory_path());
    std::string t = (std::filesystem::temp_directory_path() /
                     fmt::format("mfv-external-{}-XXXXXX", ::getpid()))
                        .string();
    if (!::mkdtemp(t.data()))
      throw std::runtime_error(fmt::format("cannot create a case directory under '{}'",
                                           std::filesystem::temp_directory_path().string()));
    path = t;
    on_signal = std::make_unique<OnSignal>([this] {
      std::error_code ignored;
      if (!keep) std::filesystem::remove_all(path, ignored);
    });
  }
  ~CaseDirectory() {
    std::error_code ignored;
    if (!keep) std::filesystem::remove_all(path, ignored);
  }
};

/// The fewest steps a stable explicit run to `end_time` can take, from mfv's own critical
/// step of the same particles: the solver may be up to kStepMargin times more stable
/// (another scheme, mass or support) but no more. 0 when the step is not known.
constexpr double kStepMargin = 4;
long fewest_stable_steps(double end_time, double dt_critical) {
  if (!(dt_critical > 0) || !std::isfinite(dt_critical) || !(end_time > 0)) return 0;
  return static_cast<long>(std::floor(end_time / (kStepMargin * dt_critical)));
}

/// ½ Σ m_I |v_I|² with mfv's masses (ExplicitDynamics::kinetic_energy of a replayed state).
double frame_kinetic_energy(const Eigen::VectorXd& mass, const Eigen::MatrixXd& v) {
  double k = 0;
  for (int I = 0; I < v.cols() && I < mass.size(); ++I) k += 0.5 * mass[I] * v.col(I).squaredNorm();
  return k;
}

/// The solver's output against what mfv sent and against itself (ExternalSolverError naming
/// the first disagreement), returning the factor of the solver's energy unit to mfv's:
///   - a run set in motion (an initial velocity or a prescribed motion) does not answer with
///     frames that are all zero, and no frame is all zero after one that was not;
///   - the account's kinetic energy is proportional to the frames' with mfv's masses: a
///     solver may keep its energies per unit thickness or area (solvers/fem-rod does), so
///     the factor c is fixed where it is best known — at t = 0 from the initial velocity mfv
///     sent, else at the frame of largest kinetic energy — and must be positive; then
///     K_account(t) = c K_frame(t) at every frame within 5 % of the run's largest kinetic
///     energy (an account sampled between the half steps of central differences lags a
///     little; a wrong one is off by O(1)).
/// `kf` holds each frame's kinetic energy with mfv's masses. 1 when nothing moves or there is
/// no account.
double check_external_account(const ExternalEnergy* energy, double k0,
                              const std::vector<ExternalFrame>& frames,
                              const std::vector<double>& kf, const ExternalCase& ec) {
  const bool moved = k0 > 0 || std::any_of(ec.prescribed.begin(), ec.prescribed.end(),
                                           [](const ExternalPrescribed& p) {
                                             return p.value != 0;
                                           });
  const bool all_zero = !frames.empty() && std::all_of(frames.begin(), frames.end(),
                                                       [](const ExternalFrame& f) {
                                                         return f.u.isZero(0) && f.v.isZero(0);
                                                       });
  if (moved && all_zero)
    throw ExternalSolverError(fmt::format(
        "every one of the solver's {} frames is zero (displacements and velocities), though "
        "mfv set the body in motion (initial kinetic energy {:.6g}{}): the solver did not "
        "run the case it was given",
        frames.size(), k0, ec.prescribed.empty() ? "" : ", prescribed velocities"));
  // A body that moved does not come back exactly to its reference configuration at rest
  // (every displacement and velocity 0.0): such a frame after a moving one is output that
  // was cut or zeroed, and the errors measured before it would pass the run.
  const auto zero = [](const ExternalFrame& f) { return f.u.isZero(0) && f.v.isZero(0); };
  for (std::size_t k = 1; k < frames.size(); ++k)
    if (zero(frames[k]) && !zero(frames[k - 1]))
      throw ExternalSolverError(fmt::format(
          "the solver's frame at t = {:.6g} is zero (every displacement and velocity) after "
          "the frame at t = {:.6g} was not: a body that moved does not return exactly to "
          "rest in its reference configuration; the solver's output was cut or zeroed",
          frames[k].time, frames[k - 1].time));
  if (!energy) return 1;
  double kmax = k0;
  std::size_t at_max = frames.size();
  for (std::size_t k = 0; k < frames.size(); ++k) {
    if (!std::isfinite(kf[k])) return 1;  // the replay marks the run unstable
    if (kf[k] > kmax) kmax = kf[k], at_max = k;
  }
  if (!(kmax > 0)) return 1;  // nothing moves: no factor to fix
  const double c = k0 > 0 ? energy->kinetic[0] / k0
                          : energy->at(frames[at_max].time)[0] / kf[at_max];
  if (!(c > 0) || !std::isfinite(c))
    throw ExternalSolverError(fmt::format(
        "frames/energy.csv: the kinetic energy {} is {:.6g}, but {} with mfv's masses gives "
        "{:.6g}: the account is not of this run",
        k0 > 0 ? "at t = 0" : fmt::format("at t = {:.6g}", frames[at_max].time),
        k0 > 0 ? energy->kinetic[0] : energy->at(frames[at_max].time)[0],
        k0 > 0 ? "the initial velocity mfv sent (input.json)" : "the frame",
        k0 > 0 ? k0 : kf[at_max]));
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const double ka = energy->at(frames[k].time)[0];
    if (std::abs(ka - c * kf[k]) > 5e-2 * c * kmax)
      throw ExternalSolverError(fmt::format(
          "frames/energy.csv disagrees with the frames: at t = {:.6g} (frame {}) the account's "
          "kinetic energy is {:.6g}, the frame's velocities with mfv's masses give {:.6g} "
          "({:.6g} in the account's unit, fixed {}); beyond 5 % of the run's largest, {:.6g}",
          frames[k].time, k, ka, kf[k], c * kf[k], k0 > 0 ? "at t = 0" : "at its largest",
          c * kmax));
  }
  return c;
}

/// An external solver's run of a transient case (issue 30): the problem's definition becomes
/// the protocol's input (dynamics/external_solver.hpp), the solver runs once, and its frames
/// are replayed, in time order, through the problem's own measurements — checkpoints, probes,
/// trace, VTK frames, finish — on a state whose particle values are the solver's fields (an
/// SPH engine holds them; it is never stepped). The energy balance is the solver's own account
/// (frames/energy.csv: kinetic energy, internal and external work from t = 0), judged as mfv's
/// engine's is: the same drift, scale and drift_bound; a solver that keeps no account has NaN
/// work columns and no energy-drift headline.
void run_external(const ExternalSolverMethod& ext, const TransientProblem& problem,
                  const AnalysisContext& c, const Params& dynamics, CaseResult& r) {
  const SolverSpec& spec = ext.spec();
  if (!spec.supports(c.spec.problem))
    throw InputError(fmt::format("external solver '{}' supports {}, not problem '{}' (its "
                                 "file: '{}')",
                                 spec.name, fmt::join(spec.problems, ", "), c.spec.problem,
                                 spec.file.string()));
  const AnalysisContext particles_context{c.plugins, c.problem, c.spec, ext.particle_method()};
  Discretization d = discretize_case(problem, particles_context, r);
  // The particles are mfv's; everything else about the method is the solver's.
  r.method_description = fmt::format("external solver '{}': {} ({})", spec.name,
                                     spec.description.empty() ? "no description" : spec.description,
                                     spec.file.string());
  r.quadrature_points = r.stress_points = 0;
  r.cells = 0;
  r.quadrature_kind.clear();
  TransientData& td = r.emplace<TransientData>();
  const double t0 = cpu_seconds();
  TransientDefinition def = problem.define(
      d, TransientInputs{c.plugins.materials, c.spec.method, r.method_params, c.spec.nodes,
                         dynamics});
  if (def.material_name.empty())
    throw InputError(fmt::format("problem '{}' does not state its material for an external "
                                 "solver (TransientDefinition::material_name)",
                                 c.spec.problem));
  if (def.steps > 0)
    throw InputError(fmt::format("{}: a run of a fixed number of steps (a timing study) has "
                                 "no meaning for external solver '{}', which chooses its own",
                                 def.label, spec.name));
  if (!(def.end_time > 0)) throw InputError("a transient run needs a positive end time");

  ExternalCase ec;
  ec.problem = c.spec.problem;
  ec.problem_params = r.problem_params;
  ec.solver_params = r.method_params;
  ec.nodes = c.spec.nodes;
  ec.dim = d.particles.x.rows();
  ec.unit_system = def.unit_system;
  ec.time_unit = def.time_unit;
  ec.x = d.particles.x;
  ec.volume = d.particles.volume;
  ec.mass = def.model.mass;
  ec.sides.resize(d.particles.size());
  for (int I = 0; I < d.particles.size(); ++I) ec.sides[I] = static_cast<unsigned>(d.particles.sides[I]);
  ec.initial_velocity = def.initial_velocity;
  for (const PrescribedVelocity& p : def.model.prescribed)
    ec.prescribed.push_back({p.particle, p.component, p.value, p.until});
  ec.material = def.material_name;
  ec.material_params = def.material_params;
  ec.density = def.model.density;
  ec.end_time = def.end_time;
  // The times the problem reads the state at: its checkpoints, the history's samples, the
  // VTK frames and, for a problem that measures over the run (a period), a finer trace.
  ExplicitDynamics state(ext.particle_method(), std::move(d), std::move(def.model),
                         DynamicsOptions{});
  if (def.initial_velocity.size() > 0) state.set_particle_velocity(def.initial_velocity);
  ec.checkpoints = def.step_checkpoints
                       ? def.step_checkpoints(choose_step(state, dynamics).target,
                                              state.critical_time_step())
                       : def.checkpoints;
  const int samples = dynamics.integer("samples") * (def.trace ? 4 : 1);
  const int frames = dynamics.integer("frames");
  std::vector<double> times = ec.checkpoints;
  for (int k = 1; k <= samples; ++k) times.push_back(def.end_time * k / samples);
  for (int k = 1; k <= frames; ++k) times.push_back(def.end_time * k / frames);
  std::sort(times.begin(), times.end());
  for (double t : times)
    if (t > 0 && t <= def.end_time * (1 + 1e-12) &&
        (ec.output_times.empty() || t - ec.output_times.back() > 1e-9 * def.end_time))
      ec.output_times.push_back(t);
  r.cpu.assembly = cpu_seconds() - t0;

  CaseDirectory dir;
  dir.keep = ext.params().integer("keep") == 1;
  write_case_input(dir.path, ec);
  // A kept directory is the user's: the sweep of stale ones leaves it.
  if (dir.keep) std::ofstream(dir.path / ".mfv-keep") << "kept by keep=1\n";
  ProgressBar bar(def.label + " (external:" + spec.name + ")", 1);
  SolverRun run;
  try {
    run = run_solver(spec, dir.path);
  } catch (...) {
    bar.finish();
    throw;
  }
  bar.update(1, def.end_time);
  bar.finish();
  TransientData::External info;
  info.solver = spec.name;
  info.command = fmt::format("{} {}", fmt::join(spec.command, " "),
                             dir.keep ? dir.path.string() : std::string("<case directory>"));
  info.wall_seconds = run.wall_seconds;
  info.cpu_seconds = run.cpu_seconds;
  info.stdout_tail = file_tail(run.stdout_file);
  info.stderr_tail = file_tail(run.stderr_file);
  const std::vector<ExternalFrame> out_frames = read_case_output(dir.path, ec);
  info.frames = static_cast<int>(out_frames.size());
  if (!out_frames.empty()) info.solver_steps = out_frames.back().steps;
  const std::optional<ExternalEnergy> energy = read_case_energy(dir.path, ec);
  r.cpu.solve = run.cpu_seconds;

  td.main_error = def.main_error;
  td.time_unit = def.time_unit;
  td.unit_system = def.unit_system;
  td.end_time = def.end_time;
  td.dt = td.dt_critical = NAN;
  td.dynamics = fmt::format("external solver '{}' ({}); {} frames replayed through the "
                            "problem's measurements",
                            spec.name, spec.description.empty() ? info.command : spec.description,
                            info.frames);
  if (!def.notes.empty()) td.dynamics += "; " + def.notes;
  td.history_columns = {"time", "kinetic", "internal work", "external work", "energy balance"};
  for (const auto& n : def.probe_names) td.history_columns.push_back(n);
  // mfv judges the replayed run by its own physics (issue 45): the kinetic energy of every
  // frame from mfv's masses, under the engine's rules (non-finite fields, K above kEnergyBound
  // × E_in), and the solver's account against the load mfv set and against the frames.
  const double k0 = ec.initial_velocity.size() > 0
                        ? frame_kinetic_energy(ec.mass, ec.initial_velocity)
                        : 0.0;  // of the initial velocity mfv sent (input.json)
  // mfv's own critical step of these particles at t = 0, for the drift waiver's step count.
  const double dt_critical_mfv = state.critical_time_step();
  // Each frame's kinetic energy with mfv's masses, once: the account is checked against
  // them and the replay judges each frame by them.
  std::vector<double> frame_kinetic;
  for (const ExternalFrame& f : out_frames)
    frame_kinetic.push_back(frame_kinetic_energy(ec.mass, f.v));
  const double unit =
      check_external_account(energy ? &*energy : nullptr, k0, out_frames, frame_kinetic, ec);
  double energy_in = k0;  // E_in of kEnergyBound, in mfv's unit
  if (energy) {
    energy_in = std::max(energy_in, std::abs(energy->kinetic[0] + energy->internal_work[0] -
                                             energy->external_work[0]) / unit);
    for (double w : energy->external_work) energy_in = std::max(energy_in, std::abs(w) / unit);
  }
  TransientMeasures m;
  TransientOutcome outcome;
  // The balance of the solver's own account, K + W_int − W_ext against its t = 0 value (mfv's
  // EnergyBalance::balance()); without an account, the kinetic energy of the frames' velocities
  // with mfv's masses.
  const double e0 =
      energy ? energy->kinetic[0] + energy->internal_work[0] - energy->external_work[0] : NAN;
  auto balance_at = [&](double t) -> std::array<double, 4> {
    if (!energy) return {state.kinetic_energy(), NAN, NAN, NAN};
    const auto [k, wi, we] = energy->at(t);
    return {k, wi, we, k + wi - we - e0};
  };
  auto record = [&]() {
    const auto e = balance_at(state.time());
    std::vector<double> row{state.time(), e[0], e[1], e[2], e[3]};
    if (def.probes)
      for (double v : def.probes(state)) row.push_back(v);
    td.history.push_back(std::move(row));
  };
  record();
  const long frame_every =
      frames > 0 ? std::max<long>(1, static_cast<long>(ec.output_times.size()) / frames) : 0;
  long done = 0;
  for (std::size_t k = 0; k < out_frames.size(); ++k) {
    const ExternalFrame& f = out_frames[k];
    state.set_replayed_state(f.time, f.u, f.v);
    done = static_cast<long>(k) + 1;
    if (const double kf = frame_kinetic[k]; !td.instability) {
      if (!std::isfinite(kf))
        td.instability = TransientData::Instability{
            done, f.time,
            fmt::format("the replayed frame {} (t = {:.6g}) has a non-finite kinetic energy "
                        "with mfv's masses", k, f.time)};
      else if (energy_in > 0 && kf > kEnergyBound * energy_in)
        td.instability = TransientData::Instability{
            done, f.time,
            fmt::format("the replayed frame {} (t = {:.6g}): kinetic energy {:.3g} with mfv's "
                        "masses, above {:g} × the energy put in (E_in = {:.3g}; the energy "
                        "balance allows at most about 1 ×)",
                        k, f.time, kf, kEnergyBound, energy_in)};
      // As the engine does: a blown-up run stops there, its later checkpoints not reached.
      if (td.instability) {
        record();
        break;
      }
    }
    td.max_displacement = std::max(td.max_displacement, f.u.cwiseAbs().maxCoeff());
    for (std::size_t q = 0; q < ec.checkpoints.size(); ++q)
      if (std::abs(ec.checkpoints[q] - f.time) <= 1e-9 * def.end_time && def.at_checkpoint)
        def.at_checkpoint(state, static_cast<int>(q), m);
    record();
    if (frame_every && (done % frame_every == 0 || k + 1 == out_frames.size())) {
      TransientData::Frame fr;
      fr.time = f.time;
      fr.x = f.x;
      fr.data.emplace_back("velocity", f.v);
      fr.data.emplace_back("displacement", f.u);
      if (f.stress.size() > 0) fr.data.emplace_back("stress", f.stress);
      if (def.frame_data) def.frame_data(state, fr.data);
      td.frames.push_back(std::move(fr));
    }
    if (def.unstable && !td.instability)
      if (std::string why = def.unstable(state); !why.empty())
        td.instability = TransientData::Instability{done, f.time, std::move(why)};
    if (def.trace) {
      outcome.trace_time.push_back(f.time);
      outcome.trace.push_back(def.trace(state));
    }
    if (def.stop && def.stop(state)) break;
  }
  td.steps = done;
  td.stopped_early = done < static_cast<long>(out_frames.size());
  if (energy) {
    // mfv's drift (run_transient): the largest |balance| over the account's rows, over the
    // largest of |E₀|, the kinetic energy and |W_ext|; judged by drift_bound on runs of
    // kMinDriftSteps solver steps or more (or of unstated length).
    double worst = 0, worst_time = 0, scale = std::abs(e0);
    for (std::size_t i = 0; i < energy->time.size(); ++i) {
      scale = std::max({scale, energy->kinetic[i], std::abs(energy->external_work[i])});
      const double b =
          std::abs(energy->kinetic[i] + energy->internal_work[i] - energy->external_work[i] - e0);
      if (b > worst) worst = b, worst_time = energy->time[i];
    }
    const double drift = scale > 0 ? worst / scale : 0.0;
    m.headline["energy drift"] = drift;
    const double drift_bound = dynamics.number("drift_bound");
    // The waiver for short runs takes a count mfv can check: the solver's stated steps are
    // believed only when mfv's own critical step allows a run that short (a stable explicit
    // run to end_time takes at least end_time / (kStepMargin × dt_crit) steps).
    const long checkable = fewest_stable_steps(def.end_time, dt_critical_mfv);
    const long steps_judged =
        info.solver_steps < 0 ? -1 : std::max(info.solver_steps, checkable);
    if (info.solver_steps >= 0 && info.solver_steps < kMinDriftSteps && checkable >= kMinDriftSteps)
      td.dynamics += fmt::format("; the solver states {} steps, fewer than a stable explicit "
                                 "run to t = {:.6g} takes by mfv's critical step (at least {}): "
                                 "the drift is judged",
                                 info.solver_steps, def.end_time, checkable);
    if (!td.instability && (steps_judged < 0 || steps_judged >= kMinDriftSteps) &&
        drift > drift_bound)
      td.instability = TransientData::Instability{
          done, worst_time,
          fmt::format("the solver's energy balance (frames/energy.csv) drifted by {:.3g} of the "
                      "run's energy, above the bound {:g} (drift_bound), largest at t = {:.6g}",
                      drift, drift_bound, worst_time)};
    td.dynamics += fmt::format("; energy balance from the solver's account ({} rows)",
                               energy->time.size());
  } else {
    td.dynamics += "; no energy account from the solver (frames/energy.csv): drift not measured";
  }
  td.external = std::move(info);
  outcome.dt = def.end_time / static_cast<double>(out_frames.size());
  outcome.dt_critical = NAN;
  outcome.steps = static_cast<long>(out_frames.size());
  outcome.stopped_early = td.stopped_early;
  outcome.unstable = td.instability.has_value();
  outcome.unstable_time = td.instability ? td.instability->time : 0.0;
  outcome.cpu_seconds = r.cpu.total();
  outcome.cpu_loop = r.cpu.solve;
  if (def.finish) def.finish(state, outcome, m);
  r.errors = m.errors;
  r.errors_paper = r.errors;
  td.profiles = std::move(m.profiles);
  for (auto& [k, v] : m.headline) r.headline[k] = v;
  if (dir.keep) r.method_description += fmt::format(" (case directory kept: {})", dir.path.string());
}

class TransientAnalysis final : public Analysis {
 public:
  bool accepts(const Problem& problem) const override {
    return dynamic_cast<const TransientProblem*>(&problem) != nullptr;
  }
  explicit TransientAnalysis(Params p) : p_(std::move(p)) {}

  void run(const AnalysisContext& c, CaseResult& r) const override {
    const auto& problem = definition_of<TransientProblem>(
        c, "transient", "a transient run (a TransientProblem's define)");
    if (const auto* ext = dynamic_cast<const ExternalSolverMethod*>(&c.method))
      return run_external(*ext, problem, c, p_, r);
    Discretization d = discretize_case(problem, c, r);
    TransientData& td = r.emplace<TransientData>();
    const double t0 = cpu_seconds();
    TransientDefinition def = problem.define(
        d, TransientInputs{c.plugins.materials, c.spec.method, r.method_params, c.spec.nodes, p_});
    const std::unique_ptr<DynamicsEngine> engine = make_dynamics_engine(
        p_.text("engine"), c.method, std::move(d), std::move(def.model), dynamics_options(p_));
    DynamicsEngine& sim = *engine;
    if (def.initial_velocity.size() > 0) sim.set_particle_velocity(def.initial_velocity);
    StepChoice step = choose_step(sim.state(), p_);
    if (def.preferred_step && !(p_.number("dt") > 0)) step.target = def.preferred_step(step.critical);
    const std::vector<double> checkpoints =
        def.step_checkpoints ? def.step_checkpoints(step.target, step.critical) : def.checkpoints;
    if (def.steps < 0 || (def.steps > 0 && !checkpoints.empty()))
      throw InputError(fmt::format("{}: a run of a fixed number of steps ({}) takes no "
                                   "checkpoints and a count >= 0",
                                   def.label, def.steps));
    // With no checkpoint the end time is the unit run_transient divides into whole steps:
    // steps × the target step gives exactly `steps` steps of the target step.
    if (def.steps > 0) def.end_time = static_cast<double>(def.steps) * step.target;
    // A run whose errors are measured at checkpoints must reach one: an end time before the
    // first would measure nothing and print every error as "–".
    if (!checkpoints.empty() &&
        *std::min_element(checkpoints.begin(), checkpoints.end()) > def.end_time * (1 + 1e-12))
      throw InputError(fmt::format("{}: the run ends at t = {:.6g}, before its first checkpoint "
                                   "t = {:.6g}: nothing would be measured; raise end_time (or "
                                   "transits) past it",
                                   def.label, def.end_time,
                                   *std::min_element(checkpoints.begin(), checkpoints.end())));
    r.cpu.assembly = cpu_seconds() - t0;
    td.main_error = def.main_error;
    td.time_unit = def.time_unit;
    td.unit_system = def.unit_system;
    TransientMeasures m;
    TransientOutcome out;
    try {
      run_transient(sim, step.target, step.critical, def, checkpoints, p_, m, r, &out);
    } catch (const SingularError& e) {
      // An Eulerian kernel whose particles have crossed (a support left with one particle):
      // the instability has destroyed the particle arrangement.
      td.steps = sim.counters().steps;
      td.stopped_early = true;
      if (!td.instability)
        td.instability = TransientData::Instability{
            sim.counters().steps, sim.time(),
            fmt::format("the particle arrangement collapsed ({})", e.what())};
    }
    if (!def.notes.empty()) td.dynamics += "; " + def.notes;
    out.dt = td.dt;
    out.dt_critical = step.critical;
    out.steps = td.steps;
    out.stopped_early = td.stopped_early;
    out.unstable = td.instability.has_value();
    out.unstable_time = td.instability ? td.instability->time : 0.0;
    out.cpu_seconds = r.cpu.total();
    out.cpu_loop = r.cpu.solve;
    if (def.finish) def.finish(sim.state(), out, m);
    r.errors = m.errors;
    r.errors_paper = r.errors;
    td.profiles = std::move(m.profiles);
    for (auto& [k, v] : m.headline) r.headline[k] = v;
  }

  std::string page(const Registries& plugins, const ReportSection& section,
                   const std::string& title, const std::filesystem::path& dir,
                   bool vtk) const override {
    return write_transient_section(plugins, section, title, dir, vtk);
  }
  std::string summary(const Problem& problem, const ReportSection& section) const override {
    return ranking_block(section.studies, problem.resolution_name(),
                         "relative error of the problem's main field");
  }
  std::string page_contents(bool vtk) const override {
    return fmt::format("every resolution's errors, rates and CPU, plots, the findings, published "
                       "values{}",
                       vtk ? " and VTK files" : "");
  }
  MeasuredErrors measured_errors() const override {
    return {{"l2"}, false, "a transient run measures only the relative L2 error of its main field"};
  }
  int print_case(const CaseResult& r, std::ostream& out) const override {
    const TransientData& t = r.data<TransientData>();
    out << fmt::format("dynamics  {}\n", t.dynamics);
    if (t.external) {
      out << fmt::format("solver    {}: {:.2f} s wall, {:.2f} s CPU, {} frames to t = {:.6g}{}{}\n",
                         t.external->command, t.external->wall_seconds,
                         t.external->cpu_seconds, t.external->frames, t.end_time,
                         t.external->solver_steps >= 0
                             ? fmt::format(", {} solver steps", t.external->solver_steps)
                             : "",
                         t.stopped_early ? " (the problem stopped the replay early)" : "");
    } else {
    out << fmt::format("steps     {} of dt {:.6g} ({:.3f} of the critical step {:.6g}) to t = "
                       "{:.6g}{}{}\n",
                       t.steps, t.dt, t.dt / t.dt_critical, t.dt_critical, t.steps * t.dt,
                       t.stopped_early
                           ? fmt::format(" (stopped early; end time {:.6g})", t.end_time)
                           : "",
                       t.retabulations > 0
                           ? fmt::format(", {} retabulations ({} neighbour searches{})",
                                         t.retabulations, t.neighbour_rebuilds,
                                         degenerate_note(t.degenerate_peak))
                           : "");
    }
    if (t.instability) out << fmt::format("verdict   {}\n", t.verdict());
    // NaN: a checkpoint the run did not reach, or a norm the problem does not measure.
    const std::string missing = t.instability ? "not reached" : "–";
    auto shown = [&](double v, const char* spec) {
      return std::isnan(v) ? missing : fmt::format(fmt::runtime(spec), v);
    };
    out << fmt::format("L2 error  relative {} (the problem's main error)\n",
                       t.main_error.empty() ? std::string("not measured")
                                            : shown(r.errors.l2_rel, "{:.6e}"));
    for (const auto& [k, v] : r.headline) out << fmt::format("{:<26} {}\n", k, shown(v, "{:.6g}"));
    if (t.external)
      out << fmt::format("CPU       setup {:.4f} s, input {:.4f} s, solver {:.4f} s ({})\n",
                         r.cpu.setup, r.cpu.assembly, r.cpu.solve,
                         t.external->solver_steps >= 0
                             ? fmt::format("{:.3g} particle-steps/s",
                                           r.particles * double(t.external->solver_steps) /
                                               std::max(r.cpu.solve, 1e-9))
                             : std::string("the solver states no step count"));
    else
      out << fmt::format("CPU       setup {:.4f} s, engine {:.4f} s, time loop {:.4f} s "
                         "({:.3g} particle-steps/s)\n",
                         r.cpu.setup, r.cpu.assembly, r.cpu.solve,
                         r.particles * double(t.steps) / std::max(r.cpu.solve, 1e-9));
    return t.instability ? 1 : 0;
  }

 private:
  Params p_;
};

}  // namespace

void register_transient(AnalysisRegistry& r) {
  r.add("transient",
        "explicit dynamics of a transient problem's definition: engine, critical step, time "
        "loop with checkpoints, energy histories, VTK frames; blow-ups stop the run",
        dynamics_schema(),
        [](const Params& p) { return std::make_unique<TransientAnalysis>(p); });
}

}  // namespace mfv
