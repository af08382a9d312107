/// `funnel`: water draining from a 2D funnel, 001 §9.7 (Fig. 20): with KBM si the Eulerian
/// kernel flows out, the Lagrangian kernel "becomes unstable; the velocities explode". 001
/// gives no geometry, gravity, walls or resolution; the catalogue's choices (§funnel): gravity
/// 9.81 m/s² downwards, an outlet D = 40 mm at y = 0, walls at 45° to the vertical up to
/// y = 0.10 m, then vertical at x = ±0.12 m; water at rest to H0 = 0.25 m in the hydrostatic
/// state (problems/fluid.hpp); the outlet's gate is gone at t = 0 (no wall across the outlet);
/// frictionless penalty walls. Nothing is deleted: what leaves the outlet falls freely below
/// y = 0 (no floor) and counts as drained.
///
/// Reference: Torricelli, exit speed √(2 g h), outflow per unit depth ρ0 C_c D √(2 g h), level
/// from w(h) dh/dt = −C_c D √(2 g h) (problems/funnel_measures.hpp), with the free-streamline
/// contraction coefficient C_c(β) between a flat wall's (β = π/2, 0.611) and the 45° funnel's
/// (β = π/4) — the band. Its fast edge is the quasi-steady law at C_c(π/4); its slow edge is
/// the law at C_c(π/2) with the start-up from rest (the column accelerating through its
/// inertance, unsteady Bernoulli): the water starts at rest, and the quasi-steady law would
/// have it flow at full rate at t = 0. Measured: the drained fraction (mass below y = 0), the
/// level recovered from it through the funnel's area function, the half-drain time, the
/// outflow rate, energies (kinetic, potential, internal, balance) and the density range, and
/// the blow-up (problems/fluid.hpp's Watch) with its time and the speed's growth rate.
#include <algorithm>
#include <cmath>
#include <memory>

#include <fmt/format.h>

#include "methods/core/errors.hpp"
#include "problems/finding_tally.hpp"
#include "problems/fluid.hpp"
#include "problems/funnel_measures.hpp"
#include "problems/problem.hpp"
#include "problems/transient_problem.hpp"

namespace mfv {

namespace {

using finding::fmt_or_dash;
using finding::last;
using finding::Tally;

/// The blow-up speed as a multiple of √(2 g H0), the fastest a particle leaves the outlet; a
/// particle that left at t = 0 and fell freely since is at most √(2 g H0) + g t, which stays
/// below 5 √(2 g H0) until t = 4 √(2 g H0)/g (0.9 s at H0 = 0.25 m); for longer runs the bound
/// is 2 (√(2 g H0) + g t_end).
constexpr double kSpeedFactor = 5.0;
/// Kinetic energy above this multiple of the potential energy released so far is a blow-up
/// (fluid::Limits; gravity cannot give more than 1 ×).
constexpr double kEnergyFactor = 2.0;
/// Energy verdict: the largest |balance| (K + W_int − W_ext − K0, gravity and walls in
/// W_ext, the artificial viscosity's dissipation in W_int) over the released potential energy.
/// Central differences close the balance to O(dt²); the bound leaves room for the walls'
/// penalty energy in transit and the Eulerian recomputations' interpolation of the state.
constexpr double kEnergyBound = 0.05;
/// Density verdict: the density at every particle in the funnel (above the outlet, y > 0)
/// within this fraction of ρ0 at every watch sample. The
/// hydrostatic compression at 0.25 m is 0.07 %, stagnation at the largest speeds (ρ v²/2 for
/// 7 m/s) 0.2 %; a weakly compressible scheme is held to Ma² ≈ 1 % variations (Monaghan 1994);
/// 3 % leaves room for the acoustic start-up and the jet's break-up.
constexpr double kDensityBound = 0.03;
/// Watch samples per run (fixed stride in steps once the step is known); the blow-up's growth
/// rate is fitted over the last kGrowthWindow samples before it.
constexpr int kWatchSamples = 3000;
constexpr int kGrowthWindow = 20;
/// Points of the band's level and drained-fraction curves.
constexpr int kBandPoints = 401;

class Funnel final : public TransientProblem {
 public:
  explicit Funnel(const Params& p) : p_(p) {
    if (!(p.number("end_time") <= 5))
      throw InputError(fmt::format("funnel: end_time = {} s is above 5 s (the funnel drains in "
                                   "about 1.5 s); give e.g. 0.6",
                                   p.number("end_time")));
    if (!(p.number("level") >= 0.05 && p.number("level") <= 0.35))
      throw InputError(fmt::format("funnel: level = {} m is outside [0.05, 0.35] (the cone "
                                   "reaches 0.10 m, the walls 0.40 m); give e.g. 0.25",
                                   p.number("level")));
  }

  Domain domain() const override {
    return Domain::rectangle(-0.5 * geometry_.width(geometry_.cone), 0,
                             0.5 * geometry_.width(geometry_.cone), geometry_.top);
  }
  std::string resolution_name() const override { return "spacings across the outlet (D/Δx)"; }
  int components() const override { return 2; }
  std::vector<int> resolutions(Level level) const override {
    // D/Δx = 8: Δx = 5 mm (nightly); 16: 2.5 mm (full).
    if (level == Level::full) return {8, 16};
    return {8};
  }

  Params analysis_defaults(const std::string& analysis) const override {
    if (analysis != "transient") return {};
    Params p = fluid::transient_defaults(12);
    // Recomputing the Eulerian tables every second step keeps the nightly kbm-si run near
    // 35 s on one core (every step: about 55 s; measured at 5 mm, 1980 particles); particles
    // move at most v dt ≈ 8 m/s × 7e-5 s = 0.1 Δx between two recomputations.
    p.set("update_every", 2);
    return p;
  }

  ParticleSet particles(int nodes, double perturbation) const override {
    if (nodes < 4 || nodes > 64)
      throw InputError(fmt::format("funnel: {} spacings across the outlet is outside [4, 64] "
                                   "(8: Δx = 5 mm, 16: 2.5 mm); give e.g. 8",
                                   nodes));
    if (perturbation != 0)
      throw InputError(fmt::format("funnel: perturbation = {} is not supported (the lattice "
                                   "keeps every particle Δx/2 from the walls); give 0",
                                   perturbation));
    return funnel::funnel_lattice(geometry_, level(), geometry_.outlet / nodes, 2000000,
                                  wall_particles() ? p_.integer("wall_layers") : 0);
  }

  TransientDefinition define(const Discretization& d, const TransientInputs& in) const override;
  std::vector<Finding> findings() const override;
  std::vector<std::string> published_notes() const override;
  std::vector<std::string> comparison_headlines() const override {
    return {"drained fraction",        "drained fraction band low", "drained fraction band high",
            "half-drain time (s)",     "blow-up time (s)",          "speed growth rate (1/s)",
            "energy error",            "density min / rho0",        "density max / rho0"};
  }
  std::string studies_table(const std::vector<StudySummary>& studies) const override;

 private:
  double level() const { return p_.number("level"); }
  bool wall_particles() const { return p_.text("walls") == "particles"; }
  double end_time() const { return p_.number("end_time"); }
  /// The band's two edges (see the file comment).
  funnel::Torricelli fast_edge() const {
    return {geometry_, funnel::contraction_coefficient(M_PI / 4), level(), water_.g, false};
  }
  funnel::Torricelli slow_edge() const {
    return {geometry_, funnel::contraction_coefficient(M_PI / 2), level(), water_.g, true};
  }

  Params p_;
  funnel::Geometry geometry_;
  fluid::Water water_;
};

TransientDefinition Funnel::define(const Discretization& d, const TransientInputs& in) const {
  const ParticleSet& ps = d.particles;
  const int n = ps.size();
  const double H0 = level(), t_end = end_time(), g = water_.g;
  TransientDefinition def;
  fluid::Setup setup;
  setup.water = water_;
  setup.surface = H0;
  const bool wall_particles = this->wall_particles();
  if (!wall_particles)
    for (const auto& w : funnel::wall_segments(geometry_)) setup.walls.push_back({w[0], w[1]});
  def.model = fluid::water_model(d, in.materials, setup);
  // walls=particles: the water's particles and points are those inside the funnel; the wall
  // particles (dummy particles, as hydrostatic-column's: Crespo et al. 2007) are held still,
  // their points carry no tension, and they count in no measure of the water.
  std::vector<char> is_water(n, 1);
  std::vector<int> water_points;
  if (wall_particles) {
    for (int I = 0; I < n; ++I)
      if (!funnel::inside(geometry_, ps.x.col(I))) {
        is_water[I] = 0;
        for (int c = 0; c < 2; ++c) def.model.prescribed.push_back({I, c, 0.0});
      }
    for (Eigen::Index q = 0; q < d.quadrature.points.cols(); ++q)
      (funnel::inside(geometry_, d.quadrature.points.col(q)) ? water_points
                                                            : def.model.tensionless_points)
          .push_back(static_cast<int>(q));
  }
  // The water's masses (the wall particles' zero): the drained fraction's.
  Eigen::VectorXd mass = def.model.mass;
  for (int I = 0; I < n; ++I)
    if (!is_water[I]) mass[I] = 0;
  const double total_mass = mass.sum();
  def.end_time = t_end;
  // The catalogue's end time, 0.5 s, is a checkpoint when the run goes beyond it.
  constexpr double kCatalogueEnd = 0.5;
  def.checkpoints = t_end > kCatalogueEnd ? std::vector<double>{kCatalogueEnd, t_end}
                                          : std::vector<double>{t_end};
  def.label = "funnel";
  def.notes = fmt::format("water to {:g} m in the funnel, outlet {:g} mm, gravity {:g} m/s², "
                          "{}, no deletion: drained water falls freely",
                          H0, geometry_.outlet * 1e3, g,
                          wall_particles
                              ? fmt::format("{} layers of dummy wall particles held still",
                                            p_.integer("wall_layers"))
                              : std::string("penalty walls (reach Δx/2)"));

  const funnel::Geometry geometry = geometry_;
  // The band on a grid of times, for the probes and profiles.
  const funnel::Torricelli fast = fast_edge(), slow = slow_edge();
  std::vector<double> band_t(kBandPoints);
  for (int k = 0; k < kBandPoints; ++k) band_t[k] = t_end * k / (kBandPoints - 1);
  const std::vector<double> fast_f = fast.drained(band_t), slow_f = slow.drained(band_t);
  const std::vector<double> fast_h = fast.levels(band_t), slow_h = slow.levels(band_t);
  const double half_fast = fast.time_to_drain(0.5, std::max(10 * t_end, 5.0));
  const double half_slow = slow.time_to_drain(0.5, std::max(10 * t_end, 5.0));
  auto band_at = [t_end](const std::vector<double>& v, double t) {
    const double s = std::clamp(t / t_end, 0.0, 1.0) * (kBandPoints - 1);
    const int k = std::min(static_cast<int>(s), kBandPoints - 2);
    return v[k] + (s - k) * (v[k + 1] - v[k]);
  };

  const double v_free = std::sqrt(2 * g * H0);
  fluid::Limits limits;
  limits.speed = std::max(kSpeedFactor * v_free, 2 * (v_free + g * t_end));
  limits.energy_factor = kEnergyFactor;
  // The settling of the discretized hydrostatic column moves water before gravity has
  // released anything: its budget is the elastic energy of the hydrostatic state.
  Eigen::VectorXd p0(n);
  for (int I = 0; I < n; ++I)
    p0[I] = is_water[I] ? water_.rho0 * g * std::max(H0 - ps.x(1, I), 0.0) : 0.0;
  limits.energy_floor = fluid::stored_energy(ps.volume, p0, water_);
  const double potential0 = fluid::potential_energy(ps.x, mass, g);

  struct Track {
    std::unique_ptr<fluid::Watch> watch;
    long steps = 0, stride = 0;
    std::string blown;
    double blow_up_time = NAN;
    Eigen::Vector2d blow_up_at{NAN, NAN}, blow_up_from{NAN, NAN};
    int min_neighbours = std::numeric_limits<int>::max();
    std::vector<double> t, drained;  ///< at every watch sample
    /// Density range of the particles in the funnel (above the outlet, y > 0) over the
    /// samples; the jet below stretches through its contraction and then falls freely and
    /// breaks up, feeling no pressure, so its density is no measure of the funnel's flow
    /// (its range is reported as "all points").
    double rho_min = INFINITY, rho_max = -INFINITY;
    double probe_t = NAN, probe_below = 0;  ///< the previous probe (outflow rate)
    double at_catalogue_end = NAN;  ///< drained fraction at 0.5 s (NaN: not reached)
  };
  auto track = std::make_shared<Track>();
  track->watch = std::make_unique<fluid::Watch>(mass, g, potential0, limits);
  if (wall_particles) track->watch->watch_density_at(water_points);
  track->t.push_back(0);
  track->drained.push_back(0);

  const double below = 0;
  auto sample = [=](const ExplicitDynamics& sim) {
    track->watch->sample(sim);
    const Eigen::MatrixXd x = sim.particle_positions();
    track->t.push_back(sim.time());
    track->drained.push_back(funnel::drained_fraction(x, mass));
    const Eigen::VectorXd rho = sim.point_state("density");
    const std::vector<int>& near = sim.particle_points();
    if (rho.size() == 0) return;
    for (int I = 0; I < n; ++I) {
      if (!(x(1, I) > below) || !is_water[I]) continue;
      const double r = rho[near[I]];
      track->rho_min = std::min(track->rho_min, r);
      track->rho_max = std::max(track->rho_max, r);
    }
  };

  def.unstable = [=](const ExplicitDynamics& sim) {
    std::string why = track->watch->check(sim);
    if (!why.empty()) {
      // Where it happened: the fastest particle (its place now and at t = 0).
      Eigen::Index f = 0;
      sim.particle_velocity().colwise().norm().maxCoeff(&f);
      const Eigen::Vector2d at = sim.particle_positions().col(f);
      track->blow_up_at = at;
      track->blow_up_from = ps.x.col(f);
      why += fmt::format(" (fastest particle at ({:.1f}, {:.1f}) mm, from ({:.1f}, {:.1f}) mm)",
                         at.x() * 1e3, at.y() * 1e3, ps.x(0, f) * 1e3, ps.x(1, f) * 1e3);
      track->blown = why;
      track->blow_up_time = sim.time();
      sample(sim);
    }
    return why;
  };
  def.stop = [=](const ExplicitDynamics& sim) {
    ++track->steps;
    if (track->stride == 0) {
      // The first step tells the step size: about kWatchSamples samples per run.
      const double dt = sim.time();
      track->stride = std::max(1L, std::lround(t_end / dt / kWatchSamples));
    }
    track->min_neighbours = std::min(track->min_neighbours, sim.min_neighbours());
    if (track->steps % track->stride == 0 && track->blown.empty()) sample(sim);
    return !track->blown.empty();
  };

  def.probe_names = {"drained fraction",
                     "drained fraction, Torricelli fast edge",
                     "drained fraction, Torricelli slow edge",
                     "level (m)",
                     "outflow (kg/s per m)",
                     "potential energy released (J/m)",
                     "max speed (m/s)"};
  def.probes = [=](const ExplicitDynamics& sim) {
    const Eigen::MatrixXd x = sim.particle_positions();
    const double f = funnel::drained_fraction(x, mass);
    const double t = sim.time();
    const double below = f * total_mass;
    const double rate = std::isfinite(track->probe_t) && t > track->probe_t
                            ? (below - track->probe_below) / (t - track->probe_t)
                            : 0.0;
    track->probe_t = t;
    track->probe_below = below;
    const Eigen::MatrixXd v = sim.particle_velocity();
    return std::vector<double>{f,
                               band_at(fast_f, t),
                               band_at(slow_f, t),
                               funnel::level_from_drained(geometry, H0, f),
                               rate,
                               potential0 - fluid::potential_energy(x, mass, g),
                               v.cols() ? v.colwise().norm().maxCoeff() : 0.0};
  };

  def.at_checkpoint = [=](const ExplicitDynamics& sim, int, TransientMeasures&) {
    if (std::abs(sim.time() - kCatalogueEnd) < 1e-9 * kCatalogueEnd + 1e-12)
      track->at_catalogue_end = funnel::drained_fraction(sim.particle_positions(), mass);
  };

  def.frame_data = [=](const ExplicitDynamics& sim,
                       std::vector<std::pair<std::string, Eigen::MatrixXd>>& out) {
    const Eigen::MatrixXd s = sim.particle_cauchy_stress();
    const Eigen::VectorXd rho = sim.point_state("density");
    const Eigen::VectorXi nb = sim.point_neighbours();
    const std::vector<int>& near = sim.particle_points();
    Eigen::MatrixXd pressure(1, n), density(1, n), neighbours(1, n);
    for (int I = 0; I < n; ++I) {
      pressure(0, I) = -0.5 * (s(0, I) + s(3, I));
      density(0, I) = rho.size() ? rho[near[I]] : NAN;
      neighbours(0, I) = nb[near[I]];
    }
    out.emplace_back("pressure (Pa)", std::move(pressure));
    out.emplace_back("density (kg/m3)", std::move(density));
    out.emplace_back("neighbours", std::move(neighbours));
  };

  const std::string frame = in.dynamics.text("frame");
  const double rho0 = water_.rho0;
  const double cc_fast = fast.cc, cc_slow = slow.cc;
  def.finish = [=](const ExplicitDynamics& sim, const TransientOutcome& out,
                   TransientMeasures& m) {
    const fluid::Watch& watch = *track->watch;
    if (track->blown.empty() && !out.unstable) sample(sim);
    const double t_reached = track->t.back();
    const double f_end = track->drained.back();
    m.headline["unstable"] = out.unstable ? 1.0 : 0.0;
    m.headline["blow-up time (s)"] = out.unstable ? out.unstable_time : NAN;
    m.headline["speed growth rate (1/s)"] =
        out.unstable ? watch.speed_growth_rate(kGrowthWindow) : NAN;
    m.headline["time reached (s)"] = t_reached;
    m.headline["blow-up particle x (mm)"] = track->blow_up_at.x() * 1e3;
    m.headline["blow-up particle y (mm)"] = track->blow_up_at.y() * 1e3;
    m.headline["drained fraction"] = out.stopped_early ? NAN : f_end;
    // What had drained when the run ended, blown up or not (issue 43's remedies table).
    m.headline["drained fraction at time reached"] = f_end;
    if (t_end > kCatalogueEnd) {
      m.headline["drained fraction at 0.5 s"] = track->at_catalogue_end;
      m.headline["drained fraction at 0.5 s, band low"] = slow.drained({kCatalogueEnd}).front();
      m.headline["drained fraction at 0.5 s, band high"] = fast.drained({kCatalogueEnd}).front();
    }
    // The band at the time the run reached (whole steps land within a step of end_time);
    // at end_time for a run stopped early.
    const double t_band = out.stopped_early ? t_end : t_reached;
    const double band_low = slow.drained({t_band}).front();
    const double band_high = fast.drained({t_band}).front();
    m.headline["drained fraction band low"] = band_low;
    m.headline["drained fraction band high"] = band_high;
    m.headline["level at the end (m)"] =
        out.stopped_early ? NAN : funnel::level_from_drained(geometry, H0, f_end);
    const double half = funnel::first_crossing(track->t, track->drained, 0.5);
    m.headline["half-drain time (s)"] = half;
    m.headline["half-drain time band low (s)"] = half_fast;
    m.headline["half-drain time band high (s)"] = half_slow;
    m.headline["contraction coefficient, flat wall"] = cc_slow;
    m.headline["contraction coefficient, 45° walls"] = cc_fast;
    // Mean outflow after the start-up (from 0.1 s or a fifth of the run), against the band's.
    const double t_a = std::min(0.1, 0.2 * t_end);
    double drained_a = NAN;
    for (std::size_t k = 1; k < track->t.size(); ++k)
      if (track->t[k] >= t_a) {
        const double s = (t_a - track->t[k - 1]) / (track->t[k] - track->t[k - 1]);
        drained_a = track->drained[k - 1] + s * (track->drained[k] - track->drained[k - 1]);
        break;
      }
    const double mean_outflow = out.stopped_early ? NAN
                                                  : total_mass * (f_end - drained_a) /
                                                        (t_reached - t_a);
    m.headline["mean outflow (kg/s per m)"] = mean_outflow;
    const double fa_fast = fast.drained({t_a}).front(), fa_slow = slow.drained({t_a}).front();
    m.headline["mean outflow band low (kg/s per m)"] =
        total_mass * (band_low - fa_slow) / (t_band - t_a);
    m.headline["mean outflow band high (kg/s per m)"] =
        total_mass * (band_high - fa_fast) / (t_band - t_a);
    const double err = watch.worst_energy_error();
    m.headline["energy error"] = err;
    double rho_min = INFINITY, rho_max = -INFINITY, v_max = 0;
    for (const auto& s : watch.samples()) {
      rho_min = std::min(rho_min, s.density_min);
      rho_max = std::max(rho_max, s.density_max);
      v_max = std::max(v_max, s.max_speed);
    }
    m.headline["density min / rho0, all points"] = rho_min / rho0;
    m.headline["density max / rho0, all points"] = rho_max / rho0;
    rho_min = track->rho_min;
    rho_max = track->rho_max;
    m.headline["density min / rho0"] = rho_min / rho0;
    m.headline["density max / rho0"] = rho_max / rho0;
    m.headline["max speed (m/s)"] = v_max;
    m.headline["speed bound (m/s)"] = limits.speed;
    m.headline["min neighbours"] = track->min_neighbours;
    m.headline["degenerate points peak"] = static_cast<double>(sim.counters().degenerate_peak);
    m.headline["particles"] = n;
    m.headline["particle-steps per second"] =
        out.cpu_loop > 0 ? n * static_cast<double>(out.steps) / out.cpu_loop : NAN;
    // Verdict parts (computed; the findings read them).
    const bool finite = !out.unstable && !out.stopped_early;
    const bool density_ok = rho_min >= (1 - kDensityBound) * rho0 &&
                            rho_max <= (1 + kDensityBound) * rho0;
    const bool drained_ok = finite && f_end >= band_low && f_end <= band_high;
    const bool half_ok = std::isfinite(half) && half >= half_fast && half <= half_slow;
    m.headline["energy within bound"] = err <= kEnergyBound ? 1.0 : 0.0;
    m.headline["density within bound"] = density_ok ? 1.0 : 0.0;
    m.headline["drained in band"] = drained_ok ? 1.0 : 0.0;
    m.headline["half-drain in band"] = half_ok ? 1.0 : 0.0;
    m.headline["drains in band"] =
        finite && err <= kEnergyBound && density_ok && drained_ok && half_ok ? 1.0 : 0.0;

    const std::string who = frame + " kernel";
    std::vector<double> level;
    for (double f : track->drained) level.push_back(funnel::level_from_drained(geometry, H0, f));
    m.profiles.push_back({"funnel: level against time, Torricelli band", "time (s)",
                          "level h (m, from the volume above the outlet)",
                          {who,
                           fmt::format("Torricelli band: C_c = {:.3f} (45°, quasi-steady) to "
                                       "{:.3f} (flat, start-up from rest)",
                                       cc_fast, cc_slow),
                           "Torricelli slow edge"},
                          {track->t, band_t, band_t},
                          {level, fast_h, slow_h},
                          {SeriesRole::computed, SeriesRole::band, SeriesRole::band}});
    m.profiles.push_back({"funnel: drained fraction against time, Torricelli band", "time (s)",
                          "mass below y = 0 / total",
                          {who, "Torricelli band (fast to slow edge)", "Torricelli slow edge"},
                          {track->t, band_t, band_t},
                          {track->drained, fast_f, slow_f},
                          {SeriesRole::computed, SeriesRole::band, SeriesRole::band}});
    std::vector<double> kinetic, potential, internal, balance;
    std::vector<double> st;
    for (const auto& s : watch.samples()) {
      st.push_back(s.t);
      kinetic.push_back(s.kinetic);
      potential.push_back(potential0 - s.potential);
      internal.push_back(s.internal_work);
      balance.push_back(s.balance);
    }
    m.profiles.push_back({"funnel: energies against time", "time (s)", "energy (J/m)",
                          {who + ": kinetic", who + ": potential released",
                           who + ": internal work", who + ": balance"},
                          {st, st, st, st},
                          {kinetic, potential, internal, balance}});
  };
  return def;
}

std::vector<Finding> Funnel::findings() const {
  std::vector<Finding> f;
  f.push_back(
      {"001 §9.7, Fig. 20",
       "water in a funnel, KBM si: the Eulerian kernel flows out of the funnel; with the "
       "Lagrangian kernel the velocities explode",
       fmt::format(
           "for each pair of kbm-si studies (Lagrangian and Eulerian kernel, same resolution and "
           "method parameters): the Eulerian run reaches the end with finite fields, energy "
           "balance within {:g} of the released potential energy, density within ±{:g} % of ρ0 at the particles in the funnel (above the outlet; the jet below stretches, falls freely and breaks up), "
           "and its drained fraction at the end and half-drain time inside the Torricelli band "
           "(C_c from the flat wall's, start-up from rest included, to the 45° walls', "
           "quasi-steady); the Lagrangian run's blow-up is detected (non-finite fields, det F ≤ "
           "0, a particle faster than max({:g} √(2 g H0), 2 (√(2 g H0) + g t_end)), or kinetic "
           "energy above {:g} × (the released potential energy plus the hydrostatic state's elastic energy)) before the band's earliest "
           "half-drain time",
           kEnergyBound, kDensityBound * 100, kSpeedFactor, kEnergyFactor),
       [](const std::vector<StudySummary>& all) {
         Tally pairs;
         for (const auto* l : finding::studies_in_frame(all, "lagrangian", "kbm-si"))
           for (const auto* e : finding::studies_in_frame(all, "eulerian", "kbm-si")) {
             if (l->resolved.to_string() != e->resolved.to_string() ||
                 l->finest_nodes != e->finest_nodes)
               continue;
             const bool drains = last(*e, "drains in band") == 1;
             const double blow = last(*l, "blow-up time (s)");
             const double earliest = last(*l, "half-drain time band low (s)");
             const bool explodes = last(*l, "unstable") == 1 && blow < earliest;
             pairs.add_numbers(*e, drains && explodes,
                       fmt::format(
                           "Eulerian: drained {} (band {}–{}), half-drain {} s (band {}–{} s), "
                           "energy error {}, density {}–{} ρ0{}; Lagrangian: {}",
                           fmt_or_dash(last(*e, "drained fraction")),
                           fmt_or_dash(last(*e, "drained fraction band low")),
                           fmt_or_dash(last(*e, "drained fraction band high")),
                           fmt_or_dash(last(*e, "half-drain time (s)")),
                           fmt_or_dash(last(*e, "half-drain time band low (s)")),
                           fmt_or_dash(last(*e, "half-drain time band high (s)")),
                           fmt_or_dash(last(*e, "energy error")),
                           fmt_or_dash(last(*e, "density min / rho0"), "{:.4f}"),
                           fmt_or_dash(last(*e, "density max / rho0"), "{:.4f}"),
                           last(*e, "unstable") == 1
                               ? fmt::format(", blew up at {} s",
                                             fmt_or_dash(last(*e, "blow-up time (s)")))
                               : "",
                           last(*l, "unstable") == 1
                               ? fmt::format("blew up at {} s (speed growth rate {} /s), "
                                             "earliest band half-drain {} s",
                                             fmt_or_dash(blow),
                                             fmt_or_dash(last(*l, "speed growth rate (1/s)")),
                                             fmt_or_dash(earliest))
                               : fmt::format("no blow-up to {} s (drained {})",
                                             fmt_or_dash(last(*l, "time reached (s)")),
                                             fmt_or_dash(last(*l, "drained fraction")))),
                       {finding::headline_per_resolution(*e, "drained fraction"),
                        finding::headline_per_resolution(*e, "half-drain time (s)"),
                        finding::headline_per_resolution(*l, "blow-up time (s)")});
           }
         return pairs.verdict("needs a Lagrangian and an Eulerian kbm-si study of the funnel");
       },
       "kbm-si-eulerian-drains-lagrangian-explodes"});
  return f;
}

std::string Funnel::studies_table(const std::vector<StudySummary>& all) const {
  auto shown = [](double v, const char* spec) {
    return std::isfinite(v) ? fmt::format(fmt::runtime(spec), v) : std::string("–");
  };
  std::string md =
      "**Methods × kernels.** Drained fraction at the end and half-drain time against the "
      "Torricelli band, the blow-up (time, speed growth rate), the worst energy balance over "
      "the released potential energy, the density range and the speed of the time loop.\n\n"
      "| study | kernel | particles | drained | band | half-drain (s) | band (s) | blow-up (s) | "
      "growth (1/s) | energy error | density / ρ0 | particle-steps/s | verdict |\n"
      "|:--|:--|--:|--:|:--|--:|:--|--:|--:|--:|:--|--:|:--|\n";
  int rows = 0;
  for (const char* frame : {"eulerian", "lagrangian"})
    for (const auto* s : finding::studies_in_frame(all, frame)) {
      const bool unstable = last(*s, "unstable") == 1;
      md += fmt::format(
          "| {} | {} | {} | {} | {}–{} | {} | {}–{} | {} | {} | {} | {}–{} | {} | {} |\n",
          s->label, frame, shown(last(*s, "particles"), "{:.0f}"),
          shown(last(*s, "drained fraction"), "{:.3f}"),
          shown(last(*s, "drained fraction band low"), "{:.3f}"),
          shown(last(*s, "drained fraction band high"), "{:.3f}"),
          shown(last(*s, "half-drain time (s)"), "{:.3f}"),
          shown(last(*s, "half-drain time band low (s)"), "{:.3f}"),
          shown(last(*s, "half-drain time band high (s)"), "{:.3f}"),
          shown(last(*s, "blow-up time (s)"), "{:.4f}"),
          shown(last(*s, "speed growth rate (1/s)"), "{:.3g}"),
          shown(last(*s, "energy error"), "{:.3g}"),
          shown(last(*s, "density min / rho0"), "{:.4f}"),
          shown(last(*s, "density max / rho0"), "{:.4f}"),
          shown(last(*s, "particle-steps per second"), "{:.3g}"),
          unstable ? "blew up" : last(*s, "drains in band") == 1 ? "drains in band" : "outside");
      ++rows;
    }
  return rows == 0 ? std::string() : md + "\n";
}

std::vector<std::string> Funnel::published_notes() const {
  const double cc_flat = funnel::contraction_coefficient(M_PI / 2);
  const double cc_45 = funnel::contraction_coefficient(M_PI / 4);
  const funnel::Torricelli fast = fast_edge(), slow = slow_edge();
  return {
      "001 §9.7 shows the Eulerian kernel's water flowing out of a funnel (Fig. 20) and says "
      "that with the Lagrangian kernel the computation becomes unstable and the velocities "
      "explode; it gives no geometry, gravity, walls, resolution or times.",
      fmt::format(
          "Our choices (catalogue §funnel): 2D, gravity {:g} m/s² downwards, outlet D = {:g} mm "
          "at y = 0, walls at 45° to the vertical up to y = {:g} m then vertical at x = ±{:g} m "
          "up to {:g} m, water at rest to H0 = level (default 0.25 m) with hydrostatic density; "
          "the outlet's gate is removed at t = 0 (no wall across the outlet); frictionless "
          "penalty walls (problems/fluid.hpp); Tait water (001 eq 77); Monaghan artificial "
          "viscosity α = 0.1, β = 0; square lattice, every particle at least Δx/2 from the walls, "
          "stress points at the centres of the lattice cells (kbm-si), the cells as Gauss cells "
          "(efg-ci). No particle is deleted: water below the outlet falls freely (no floor) and "
          "counts as drained.",
          water_.g, geometry_.outlet * 1e3, geometry_.cone, 0.5 * geometry_.width(geometry_.cone),
          geometry_.top),
      fmt::format(
          "Torricelli band: C_c = {:.4f} for a flat wall (β = π/2) to {:.4f} for the 45° "
          "funnel walls (β = π/4), from the free-streamline formula (GSL QAGS; 0.5 at β = π, "
          "Borda). Fast edge: quasi-steady w(h) dh/dt = −C_c D √(2gh) at C_c(π/4), half-drain at "
          "{:.3f} s; slow edge: C_c(π/2) with the start-up from rest (unsteady Bernoulli through "
          "the column's inertance ∫ dy/w), half-drain at {:.3f} s. The catalogue's end time of "
          "0.5 s would not reach the slow edge's half-drain time: end_time defaults to 0.6 s, and "
          "the drained fraction at the end is compared with the band at the same time.",
          cc_flat, cc_45, fast.time_to_drain(0.5, 5.0), slow.time_to_drain(0.5, 5.0)),
  };
}

}  // namespace

void register_funnel(ProblemRegistry& r) {
  r.add("funnel",
        "water (Tait, 001 eq 77) draining from a 2D funnel under gravity, hydrostatic at t = 0, "
        "penalty walls, outlet gate removed at t = 0: drained fraction, half-drain time and "
        "outflow against Torricelli with the free-streamline contraction band; the Lagrangian "
        "kernel's blow-up (001 §9.7)",
        {ParamSpec::positive("end_time", 0.6,
                             "end of the run (s, at most 5; 0.6 reaches the band's half-drain "
                             "times)"),
         ParamSpec::positive("level", 0.25, "water level H0 at t = 0 (m, in [0.05, 0.35])"),
         ParamSpec::choice("walls", "penalty", {"penalty", "particles"},
                           "penalty: frictionless penalty walls (problems/fluid.hpp); particles: "
                           "layers of the lattice outside the walls held still, as "
                           "hydrostatic-column's dummy wall particles (issue 43)"),
         ParamSpec::count("wall_layers", 3, 1,
                          "walls=particles: the wall band's thickness in spacings (at most 10)")},
        [](const Params& p) { return std::make_unique<Funnel>(p); });
}

}  // namespace mfv
