/// `dam-break`: the 2D collapse of a water column of width a and height 2a (n² = 2) on a dry
/// floor, against Martin & Moyce's (1952) measurements (problems/fluid_measures.hpp), with
/// any 2D method and either kernel. What it measures:
/// - the surge front Z(t)/a (the largest x of the particles touching the floor plus half a
///   spacing) and the residual column height H(t)/a at the left wall, in T = t √(2g/a) (Martin
///   & Moyce's T = n t √(g/a) for n² = 2), against the experiment: RMS and max of
///   |Z(T_k)/a − Z_k/a| over the data points (the run's history interpolated linearly in time);
/// - a time-shifted comparison as a labelled diagnostic only (the shift that minimizes the
///   RMS; the experiment's release lag is the known reason simulations run ahead early);
/// - the front's speed against the shallow-water bound 2 √(g h0), h0 = 2a (Ritter 1892: the
///   dam-break front on a dry bed), which is dZ/dT = 2 in these units;
/// - energy (K + W_int − W_ext over the released potential energy), density range, blow-up
///   watch (problems/fluid.hpp).
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include <fmt/format.h>

#include "methods/core/errors.hpp"
#include "problems/finding_tally.hpp"
#include "problems/fluid.hpp"
#include "problems/fluid_measures.hpp"
#include "problems/problem.hpp"
#include "problems/transient_problem.hpp"

namespace mfv {

namespace {

using finding::fmt_or_dash;
using finding::last;
using finding::Tally;

/// Martin & Moyce's column: a = 2.25 in.
constexpr double kColumnWidth = 0.05715;
/// Bands of the front against the experiment (Z/a): RMS and max over the data points. The
/// experiment's front lags at early times (the release took a finite time; Koshizuka & Oka
/// 1996, Nucl. Sci. Eng. 123, 421–434, and Colagrossi & Landrini 2003, J. Comput. Phys. 191,
/// 448–475, compare with these data and run ahead of them), so an instantaneous release runs
/// ahead. The bands allow a release lag of kReleaseLag in T (16 ms at a = 57 mm) and no more:
/// times the data's front speed (dZ/dT from 0.3 early to 1.7 late, 1.0 on average) it is an
/// RMS of about 0.4 and a largest error of about 0.5; times the height's fall (|dH/dT| about
/// 0.45 in Table 6) an RMS of about 0.15.
constexpr double kReleaseLag = 0.3;
constexpr double kFrontRms = 0.4;
constexpr double kFrontMax = 0.6;
constexpr double kHeightRms = 0.15;
/// The energy balance over the released potential energy and the density's departure from ρ0.
constexpr double kBalanceTolerance = 0.05;
constexpr double kDensityTolerance = 0.03;
/// Front and height samples per run, and the watch's samples.
constexpr int kHistory = 1000;
constexpr int kSamples = 200;
/// The front speed is measured over windows of this many T units (a particle that joins the
/// floor row moves the front by one spacing in one step: a single step is no speed).
constexpr double kSpeedWindow = 0.25;

class DamBreak final : public TransientProblem {
 public:
  explicit DamBreak(const Params& p) : p_(p) {
    if (!(p.number("width") >= 1e-3))
      throw InputError(fmt::format("dam-break: width = {} m is below 1 mm (the Tait water's "
                                   "sound crossing of a particle spacing would need more steps "
                                   "than a run may take); give e.g. 0.05715",
                                   p.number("width")));
    if (!(p.number("tank") >= 2))
      throw InputError(fmt::format("dam-break: tank = {} must be at least 2 (the right wall at "
                                   "tank × a, beyond the column's width a and its collapse); "
                                   "give e.g. 6",
                                   p.number("tank")));
  }

  Domain domain() const override { return Domain::rectangle(0, 0, a(), 2 * a()); }
  std::string resolution_name() const override { return "particles across the column width a"; }
  int components() const override { return 2; }

  std::vector<int> resolutions(Level level) const override {
    // a = 57.15 mm: 20 across is Δx = 2.9 mm, 40 is 1.4 mm.
    if (level == Level::full) return {20, 40};
    return {20};
  }

  Params analysis_defaults(const std::string& analysis) const override {
    if (analysis != "transient") return {};
    return fluid::transient_defaults(12);
  }

  ParticleSet particles(int nodes, double perturbation) const override {
    if (nodes < 4 || nodes > 2000)
      throw InputError(fmt::format("dam-break: {} particles across the column is outside "
                                   "[4, 2000]; give e.g. 20",
                                   nodes));
    ParticleSet water = rectangle_lattice(domain(), nodes, 2 * nodes, Placement::inset,
                                          perturbation);
    if (p_.text("walls") != "particles") return water;
    // Dummy wall particles on the same spacing, appended after the water (so the water keeps
    // its indices): `layers` rows under the tank's floor from the left wall's outer layer to
    // the right wall's, and `layers` columns beside the tank up to 1.5 times the column's
    // height.
    const double dx = a() / nodes;
    const int layers = p_.integer("wall_layers"), M = tank_cells(nodes), up = 3 * nodes;
    std::vector<Eigen::Vector2d> wall;
    for (int k = 0; k < layers; ++k)
      for (int i = -layers; i < M + layers; ++i) wall.emplace_back((i + 0.5) * dx, -(k + 0.5) * dx);
    for (int j = 0; j < up; ++j)
      for (int k = 0; k < layers; ++k) {
        wall.emplace_back(-(k + 0.5) * dx, (j + 0.5) * dx);
        wall.emplace_back((M + k + 0.5) * dx, (j + 0.5) * dx);
      }
    const int nw = water.size(), n = nw + static_cast<int>(wall.size());
    ParticleSet ps = water;
    ps.x.conservativeResize(2, n);
    ps.volume.conservativeResize(n);
    for (int k = nw; k < n; ++k) {
      ps.x.col(k) = wall[k - nw];
      ps.volume[k] = dx * dx;
    }
    // The methods set the dilations (prepare()); every per-particle vector has n entries.
    ps.dilation = Eigen::VectorXd::Constant(n, ps.dilation.size() > 0 ? ps.dilation[0] : dx);
    if (ps.local_spacing.size() > 0) ps.local_spacing = Eigen::VectorXd::Constant(n, dx);
    ps.sides.resize(n, 0u);
    // No longer one lattice: lattice-cell rules (stress points, Gauss cells) refuse the set.
    ps.lattice = Eigen::Vector2i::Zero();
    return ps;
  }

  Domain discretized_domain(int nodes) const override {
    if (p_.text("walls") != "particles") return domain();
    const double dx = a() / nodes, e = p_.integer("wall_layers") * dx;
    return Domain::rectangle(-e, -e, tank_cells(nodes) * dx + e, 3 * a());
  }

  TransientDefinition define(const Discretization& d, const TransientInputs& in) const override;
  std::vector<Finding> findings() const override;
  std::vector<std::string> published_notes() const override;
  std::vector<std::string> comparison_headlines() const override {
    return {"front RMS error (Z/a)", "front max error (Z/a)", "height RMS error (H/a)",
            "front at end (Z/a)", "front speed / Ritter bound", "energy balance / released",
            "max density deviation", "T reached"};
  }

 private:
  double a() const { return p_.number("width"); }
  double tank() const { return p_.number("tank") * a(); }
  /// walls=particles: the tank's length in whole spacings (the right wall's particles stand
  /// on the lattice: the tank is tank_cells Δx long, tank a to half a spacing).
  int tank_cells(int nodes) const { return static_cast<int>(std::lround(p_.number("tank") * nodes)); }
  /// T = t √(2g/a) → t.
  double time_of(double T) const { return T / std::sqrt(2 * fluid::Water{}.g / a()); }

  Params p_;
};

TransientDefinition DamBreak::define(const Discretization& d, const TransientInputs& in) const {
  const ParticleSet& ps = d.particles;
  const int n = ps.size();
  const double dx = ps.spacing, A = a(), L = tank();
  // The water's particles come first; walls=particles appends the wall's (particles()).
  const int nodes = static_cast<int>(std::lround(A / dx));
  const bool wall_particles = p_.text("walls") == "particles";
  const int nw = wall_particles ? 2 * nodes * nodes : n;
  // The floor and left-wall bands of the front and height measures: one spacing, or three
  // over dummy wall particles, whose pressure holds a moving front 1.3-1.9 spacings above the
  // floor (measured with sph at T = 0.5-2; the water at rest keeps its half spacing).
  const double band = wall_particles ? 3 * dx : dx;
  fluid::Setup setup;
  setup.surface = 2 * A;
  // Left wall and floor of the tank, the right wall at `tank` a; the walls are twice the
  // column's height (the run-up at the right wall, if the run is long enough to reach it,
  // stays below).
  if (!wall_particles) setup.walls = {{{0, 0}, {L, 0}}, {{0, 0}, {0, 4 * A}}, {{L, 0}, {L, 4 * A}}};
  TransientDefinition def;
  def.model = fluid::water_model(d, in.materials, setup);
  // Dummy wall particles (as hydrostatic-column's walls=particles): held still, water
  // otherwise (hydrostatic density continued below the floor).
  for (int I = nw; I < n; ++I)
    for (int c = 0; c < 2; ++c) def.model.prescribed.push_back({I, c, 0.0});
  // Their points (the nodal rule's: the particles themselves) carry no tension: a wall does not
  // pull water (DynamicsModel::tensionless_points; with tension a film of water clung to the
  // left wall's particles up to the column's first height).
  if (wall_particles) {
    if (d.quadrature.nodal_points < n)
      throw InputError("dam-break walls=particles needs a method integrating at the particles "
                       "(a nodal rule: sph, rlm, kbm-ni, efg-ni)");
    for (int I = nw; I < n; ++I) def.model.tensionless_points.push_back(I);
  }
  const fluid::Water water = setup.water;
  const double scale = std::sqrt(2 * water.g / A);  // T = t · scale
  def.end_time = time_of(p_.number("end_T"));
  def.checkpoints = {def.end_time};
  def.label = "dam-break";
  def.notes = fmt::format("water column a = {:g} m × 2a released at t = 0 in a tank {:g} a long",
                          A, p_.number("tank"));
  const Eigen::VectorXd mass = def.model.mass;
  const double pe0 = fluid::potential_energy(ps.x, mass, water.g);
  const double ritter = 2 * std::sqrt(water.g * 2 * A);  // m/s
  // The kinetic-energy budget starts from the elastic energy of the hydrostatic column: the
  // release turns it into motion before any potential energy has been released.
  Eigen::VectorXd p0(nw);
  for (int I = 0; I < nw; ++I) p0[I] = water.rho0 * water.g * (2 * A - ps.x(1, I));
  const fluid::Limits limits{5 * std::sqrt(2 * water.g * 2 * A), 2,
                             fluid::stored_energy(ps.volume.head(nw), p0, water)};
  const double history_every = def.end_time / kHistory, sample_every = def.end_time / kSamples;

  struct Track {
    std::unique_ptr<fluid::Watch> watch;
    double next_history = 0, next_sample = 0;
    std::vector<double> T, Z, H;
    Eigen::Vector2d blow_up_at{NAN, NAN};  ///< over a
  };
  auto track = std::make_shared<Track>();
  track->watch = std::make_unique<fluid::Watch>(mass, water.g, pe0, limits);
  if (wall_particles) {  // the density range of the water (the nodal rule: its particles)
    std::vector<int> water_points(nw);
    for (int I = 0; I < nw; ++I) water_points[I] = I;
    track->watch->watch_density_at(std::move(water_points));
  }
  auto record = [=](const ExplicitDynamics& sim) {
    const Eigen::MatrixXd x = sim.particle_positions().leftCols(nw);
    if (!x.allFinite()) return;
    track->T.push_back(sim.time() * scale);
    track->Z.push_back(fluid::surge_front(x, dx, band) / A);
    track->H.push_back(fluid::column_height(x, dx, band) / A);
  };
  def.probe_names = {"T = t sqrt(2g/a)", "front Z/a", "height H/a"};
  def.probes = [=](const ExplicitDynamics& sim) {
    const Eigen::MatrixXd x = sim.particle_positions().leftCols(nw);
    return std::vector<double>{sim.time() * scale, fluid::surge_front(x, dx, band) / A,
                               fluid::column_height(x, dx, band) / A};
  };
  def.unstable = [=](const ExplicitDynamics& sim) {
    std::string why = track->watch->check(sim);
    if (!why.empty() && !std::isfinite(track->blow_up_at[0])) {
      // Where it went: the fastest particle's current position.
      Eigen::Index fastest = 0;
      sim.particle_velocity().colwise().norm().maxCoeff(&fastest);
      track->blow_up_at = sim.particle_positions().col(fastest) / A;
    }
    return why;
  };
  def.stop = [=](const ExplicitDynamics& sim) {
    if (sim.time() + 1e-9 * history_every >= track->next_history) {
      if (track->T.empty()) {
        // t = 0: the lattice as released.
        track->T.push_back(0);
        track->Z.push_back(fluid::surge_front(ps.x.leftCols(nw), dx, band) / A);
        track->H.push_back(fluid::column_height(ps.x.leftCols(nw), dx, band) / A);
      }
      track->next_history += history_every;
      record(sim);
    }
    if (sim.time() + 1e-9 * sample_every >= track->next_sample) {
      track->next_sample += sample_every;
      track->watch->sample(sim);
    }
    return false;
  };
  def.frame_data = fluid::frame_fields;

  const std::string frame = in.dynamics.text("frame");
  const double end_T = p_.number("end_T");
  def.finish = [=](const ExplicitDynamics& sim, const TransientOutcome& out,
                   TransientMeasures& m) {
    record(sim);
    const fluid::ExperimentSeries front = fluid::martin_moyce_front();
    const fluid::ExperimentSeries height = fluid::martin_moyce_height();
    m.headline["unstable"] = out.unstable ? 1.0 : 0.0;
    m.headline["unstable at (T)"] = out.unstable ? out.unstable_time * scale : NAN;
    m.headline["blow-up particle x/a"] = track->blow_up_at[0];
    m.headline["blow-up particle y/a"] = track->blow_up_at[1];
    const double T_reached = track->T.empty() ? 0.0 : track->T.back();
    m.headline["T reached"] = T_reached;
    const fluid::SeriesError ef = fluid::series_error(track->T, track->Z, front);
    const fluid::SeriesError eh = fluid::series_error(track->T, track->H, height);
    // Every data point up to the end time must be compared; fewer means the run stopped.
    int due = 0;
    for (double T : front.T) due += T <= end_T + 1e-9;
    m.headline["front points compared"] = ef.points;
    m.headline["front points due"] = due;
    m.headline["front RMS error (Z/a)"] = ef.rms;
    m.headline["front max error (Z/a)"] = ef.max;
    m.headline["height RMS error (H/a)"] = eh.rms;
    m.headline["height max error (H/a)"] = eh.max;
    m.errors.l2_rel = NAN;
    // Diagnostic only: the lead that a late experimental start would explain.
    const double shift = fluid::best_shift(track->T, track->Z, front, 1.0);
    m.headline["diagnostic: best time shift (T)"] = shift;
    m.headline["diagnostic: front RMS after the shift (Z/a)"] =
        std::isfinite(shift) ? fluid::series_error(track->T, track->Z, front, shift).rms : NAN;
    m.headline["front at end (Z/a)"] = track->Z.empty() ? NAN : track->Z.back();
    m.headline["height at end (H/a)"] = track->H.empty() ? NAN : track->H.back();
    // The fastest front over windows of kSpeedWindow in T, in units of Ritter's 2 √(g h0)
    // (dZ/dT = 2 in Z/a per T).
    double fastest = 0;
    for (std::size_t k = 0, j = 0; k < track->T.size(); ++k) {
      while (j < k && track->T[k] - track->T[j] > kSpeedWindow) ++j;
      if (track->T[k] - track->T[j] >= 0.5 * kSpeedWindow)
        fastest = std::max(fastest, (track->Z[k] - track->Z[j]) / (track->T[k] - track->T[j]));
    }
    m.headline["front speed / Ritter bound"] = fastest * A * scale / ritter;
    m.headline["max density deviation"] = track->watch->max_density_deviation(water.rho0);
    m.headline["energy balance / released"] = track->watch->worst_energy_error();
    m.headline["min neighbours"] = sim.min_neighbours();
    m.headline["degenerate points (peak)"] = sim.counters().degenerate_peak;
    m.headline["particles"] = n;
    m.headline["wall particles"] = n - nw;

    const std::string who = frame + " kernel";
    m.profiles.push_back({"surge front against Martin & Moyce (1952), n² = 2",
                          "T = t √(2g/a)", "Z / a", {who, "Martin & Moyce 1952, Table 2"},
                          {track->T, front.T}, {track->Z, front.value},
                          {SeriesRole::computed, SeriesRole::data}});
    m.profiles.push_back({"column height at the left wall against Martin & Moyce (1952)",
                          "T = t √(2g/a)", "H / a", {who, "Martin & Moyce 1952, Table 6"},
                          {track->T, height.T}, {track->H, height.value},
                          {SeriesRole::computed, SeriesRole::data}});
    std::vector<double> t, k, bal;
    const double released = std::max(track->watch->released_energy(), 1e-300);
    for (const auto& s : track->watch->samples()) {
      t.push_back(s.t * scale);
      k.push_back(s.kinetic / released);
      bal.push_back(s.balance / released);
    }
    m.profiles.push_back({"energy over the released potential energy", "T = t √(2g/a)",
                          "E / ΔE_pot", {who + ": kinetic", who + ": balance"}, {t, t}, {k, bal}});
  };
  return def;
}

std::vector<Finding> DamBreak::findings() const {
  std::vector<Finding> f;
  f.push_back(
      {"Martin & Moyce 1952",
       "the surge front of a collapsing water column (n² = 2) follows Martin & Moyce's "
       "measurements (Table 2) in T = t √(2g/a)",
       fmt::format("every Eulerian study reaches every data point up to end_T with no blow-up, "
                   "and |Z/a − Z_exp/a| over the data points has RMS ≤ {:g} and max ≤ {:g} "
                   "(no time shift; the band allows the lead of an instantaneous release over the "
                   "experiment's, up to {:g} in T). Lagrangian studies are listed, not judged",
                   kFrontRms, kFrontMax, kReleaseLag),
       [](const std::vector<StudySummary>& all) {
         Tally t;
         for (const auto* s : finding::studies_in_frame(all, "eulerian")) {
           const double rms = last(*s, "front RMS error (Z/a)");
           const double mx = last(*s, "front max error (Z/a)");
           const bool all_points =
               last(*s, "front points compared") >= last(*s, "front points due");
           t.add_headlines(*s, last(*s, "unstable") == 0 && all_points && rms <= kFrontRms && mx <= kFrontMax,
                 fmt::format("RMS {}, max {} over {} points (diagnostic: {} after a shift of {} "
                             "in T)",
                             fmt_or_dash(rms), fmt_or_dash(mx),
                             fmt_or_dash(last(*s, "front points compared"), "{:.0f}"),
                             fmt_or_dash(last(*s, "diagnostic: front RMS after the shift (Z/a)")),
                             fmt_or_dash(last(*s, "diagnostic: best time shift (T)"))),
                 {"front RMS error (Z/a)", "front max error (Z/a)"});
         }
         Verdict v = t.verdict("no Eulerian dam-break study");
         for (const auto* s : finding::studies_in_frame(all, "lagrangian"))
           v.ours += fmt::format("; not judged: {} (lagrangian): front RMS {}, {}", s->label,
                                 fmt_or_dash(last(*s, "front RMS error (Z/a)")),
                                 last(*s, "unstable") == 1
                                     ? fmt::format("blew up at T = {}",
                                                   fmt_or_dash(last(*s, "unstable at (T)")))
                                     : std::string("ran to the end"));
         return v;
       },
       "surge-front"});
  f.push_back(
      {"Martin & Moyce 1952",
       "the residual column height at the wall follows Martin & Moyce's measurements (Table 6)",
       fmt::format("every Eulerian study with no blow-up: |H/a − H_exp/a| over the data points up "
                   "to end_T has RMS ≤ {:g}",
                   kHeightRms),
       [](const std::vector<StudySummary>& all) {
         Tally t;
         for (const auto* s : finding::studies_in_frame(all, "eulerian")) {
           const double rms = last(*s, "height RMS error (H/a)");
           t.add_headlines(*s, last(*s, "unstable") == 0 && rms <= kHeightRms,
                 fmt::format("RMS {}, max {}", fmt_or_dash(rms),
                             fmt_or_dash(last(*s, "height max error (H/a)"))),
                 {"height RMS error (H/a)"});
         }
         return t.verdict("no Eulerian dam-break study");
       },
       "column-height"});
  f.push_back(
      {"Ritter 1892",
       "no front on a dry bed outruns the shallow-water dam-break front speed 2 √(g h0), "
       "h0 = 2a",
       fmt::format("every study, either kernel, with no blow-up: the fastest front over windows "
                   "of {:g} in T is below 2 √(g h0) (dZ/dT < 2), and the front moved forward",
                   kSpeedWindow),
       [](const std::vector<StudySummary>& all) {
         Tally t;
         for (const char* frame : {"lagrangian", "eulerian"})
           for (const auto* s : finding::studies_in_frame(all, frame)) {
             if (last(*s, "unstable") == 1) continue;
             const double v = last(*s, "front speed / Ritter bound");
             t.add_headlines(*s, v > 0 && v < 1, fmt::format("{} of the bound", fmt_or_dash(v)),
                             {"front speed / Ritter bound"});
           }
         return t.verdict("no dam-break study ran to the end");
       },
       "ritter-bound"});
  f.push_back(
      {"Martin & Moyce 1952",
       "the Eulerian kernel carries the collapse soundly: energy conserved and the water nearly "
       "incompressible",
       fmt::format("every Eulerian study: no blow-up, energy balance |K + W_int − W_ext| ≤ {:g} × "
                   "the released potential energy, density within {:g} of ρ0",
                   kBalanceTolerance, kDensityTolerance),
       [](const std::vector<StudySummary>& all) {
         Tally t;
         for (const auto* s : finding::studies_in_frame(all, "eulerian")) {
           const double e = last(*s, "energy balance / released");
           const double rho = last(*s, "max density deviation");
           t.add_headlines(*s, last(*s, "unstable") == 0 && e <= kBalanceTolerance && rho <= kDensityTolerance,
                 fmt::format("balance {} of the released energy, density within {}",
                             fmt_or_dash(e), fmt_or_dash(rho)),
                 {"energy balance / released", "max density deviation"});
         }
         return t.verdict("no Eulerian dam-break study");
       },
       "sound-collapse"});
  return f;
}

std::vector<std::string> DamBreak::published_notes() const {
  const fluid::Water w;
  std::string table =
      "Martin & Moyce's surge front (Table 2) and column height (Table 6, converted), n² = 2, "
      "a = 2.25 in:\n\n| T = t √(2g/a) | Z/a |\n| --: | --: |\n";
  const auto front = fluid::martin_moyce_front();
  for (std::size_t k = 0; k < front.T.size(); ++k)
    table += fmt::format("| {:.2f} | {:.2f} |\n", front.T[k], front.value[k]);
  table += "\n| T = √2 τ | H/a = 2 η |\n| --: | --: |\n";
  const auto height = fluid::martin_moyce_height();
  for (std::size_t k = 0; k < height.T.size(); ++k)
    table += fmt::format("| {:.3f} | {:.2f} |\n", height.T[k], height.value[k]);
  return {
      fmt::format(
          "No paper of ours has this problem; the experiment is {}. Martin & Moyce scale the "
          "front's time as T = n t √(g/a) with n² the column's height over its width: for "
          "n² = 2, T = t √(2g/a); the height's time is τ = t √(g/a) and the height is given "
          "over n² a (both converted here to T and H/a).",
          fluid::martin_moyce_citation()),
      table,
      fmt::format(
          "Our choices: water of 001 §9.7 (Tait, eq 77, c0 = {:.1f} m/s, about 54 √(g · 2a) at the "
          "default a: the flow's Mach number stays below 0.04), g = {:g} m/s²; a column of width a = "
          "width (default {:g} m, Martin & Moyce's 2.25 in) and height 2a, particles at the "
          "centres of square cells, hydrostatic at t = 0 (the gate removed at t = 0, "
          "instantly); penalty walls (problems/fluid.hpp): the floor and the left wall at x = 0 "
          "and a right wall at tank = {:g} a (the front reaches about 4.1 a in the experiment "
          "by T = 3.33 and runs at most 2 a per unit T, Ritter's bound, so it does not reach "
          "the wall before end_T = {:g} unless end_T is raised); Monaghan artificial viscosity "
          "α = 0.1, β = 0 (analysis default). Front: the largest x of the particles whose "
          "current y is below one spacing (the bottom row stands half a spacing above the "
          "floor), plus half a spacing; height: the largest y of the particles within one "
          "spacing of the left wall, plus half a spacing.",
          w.sound_speed(), w.g, kColumnWidth, p_.number("tank"), p_.number("end_T")),
      fmt::format(
          "Bands: front RMS ≤ {:g} a and max ≤ {:g} a, height RMS ≤ {:g} a, no time shift. "
          "Simulations of this experiment run ahead of the measured front at early times: the "
          "release took a finite time (Koshizuka & Oka 1996 and Colagrossi & Landrini 2003 "
          "compare with these data and discuss it), which an instantaneous gate removal does "
          "not model. The bands allow a release lag of {:g} in T (16 ms at a = 57 mm): times "
          "the data's front speed (dZ/dT 0.3 early to 1.7 late, 1.0 on average) and the "
          "height's fall (|dH/dT| ≈ 0.45) it gives the bands above. The shift that minimizes "
          "the front's RMS is reported as a diagnostic only (searched in [0, 1]), never used "
          "for the verdict.",
          kFrontRms, kFrontMax, kHeightRms, kReleaseLag),
  };
}

}  // namespace

void register_dam_break(ProblemRegistry& r) {
  r.add("dam-break",
        "2D collapse of a water column (width a, height 2a; Tait water of 001 §9.7, gravity, "
        "penalty walls) on a dry floor, released at t = 0: surge front and column height "
        "against Martin & Moyce (1952)",
        {capped(ParamSpec::positive("width", kColumnWidth,
                                    "column width a (m; Martin & Moyce: 0.05715 = 2.25 in), at "
                                    "most 10"),
                10),
         capped(ParamSpec::positive("tank", 6.0,
                                    "length of the tank over a (the right wall's x / a), in "
                                    "[2, 100]"),
                100),
         capped(ParamSpec::positive("end_T", 3.33,
                                    "end time in T = t sqrt(2g/a) (default: the last data "
                                    "point), at most 20"),
                20),
         ParamSpec::choice("walls", "penalty", {"penalty", "particles"},
                           "penalty: frictionless penalty walls (problems/fluid.hpp); "
                           "particles: wall_layers layers of dummy wall particles held still "
                           "under the floor and beside the tank (Crespo et al. 2007; an "
                           "unstructured set: methods integrating on lattice cells or stress "
                           "points refuse it)"),
         capped(ParamSpec::count("wall_layers", 3, 1,
                                 "walls=particles: layers of wall particles (at most 10)"),
                10)},
        [](const Params& p) { return std::make_unique<DamBreak>(p); });
}

}  // namespace mfv
