/// `compressed-plate`: the shear band of 001 §9.4, a square plate in plane strain compressed
/// at a constant nominal rate ε̇ = V/L by rigid, shear-free platens, run with any 2D method
/// and either kernel. 001 shows pictures only (Figs. 15–16); what we measure (catalogue §plate):
/// - the band's angle to the compression axis, fitted by a Radon projection of ε̄
///   (problems/plate_measures.hpp), against the slip lines' ±45° of a von Mises material in
///   plane strain (Hill 1950, The Mathematical Theory of Plasticity, ch. VI: the
///   characteristics bisect the principal stress directions);
/// - the stress–strain curve σ̄(ε̄) of the band point, the largest ε̄ at the end in the central
///   half of the plate outside the weak spot (001 Fig. 15; σ̄ = √3 τ_max), and the growth rate of its oscillation about the trend in the softening range, fitted as
///   ln(envelope) ≈ a + g ε_n over half-period peaks (ε_n = V t / L the nominal strain);
/// - a blow-up detector (an inverted point, a particle faster than kSpeedBound × V) that stops
///   the run and says when and where.
#include <algorithm>
#include <cmath>
#include <memory>

#include <fmt/format.h>

#include "methods/core/errors.hpp"
#include "methods/materials/j2_viscoplastic.hpp"
#include "problems/plate_measures.hpp"
#include "problems/finding_tally.hpp"
#include "problems/problem.hpp"
#include "problems/transient_problem.hpp"

namespace mfv {

namespace {

using finding::fmt_or_dash;
using finding::last;
using finding::Tally;
using finding::headline_per_resolution;

/// Plate side L (m), density ρ (kg/m³): a steel plate of 10 mm (our choice; 001 gives neither;
/// ρ is also needleman_1989_parameters()'s density).
constexpr double kSide = 0.01;
constexpr double kDensity = 7800;
/// A particle faster than this multiple of the platens' closing speed V means a blow-up (about
/// a tenth of the steel's wave speed at V = 10 m/s). A numerical blow-up grows exponentially and
/// passes any such bound within a few steps; the bound is loose because a platen corner whose
/// material has lost its strength (σ_Y = 0) is squeezed out sideways at tens of V, which is
/// the model's physics, not an instability.
constexpr double kSpeedBound = 50.0;
/// Values of the stress–strain record kept in memory (two floats each): beyond it the
/// record keeps every other sample and halves its rate.
constexpr double kRecordValues = 1e7;
/// The detrending window of the oscillation fit, as a fraction of the run's nominal strain:
/// the trend (hardening, softening) varies over the whole run, spurious oscillations have
/// periods of a few wave transits of a particle spacing, far below this.
constexpr double kTrendWindow = 0.05;
/// The softening range ends where the band point's trend has fallen below this fraction of
/// its peak, and an oscillation peak smaller than kOscillationFloor of the peak stress is not
/// an oscillation (a smooth curve's residual about its moving average is round-off).
constexpr double kSpentStrength = 0.1;
constexpr double kOscillationFloor = 0.005;
/// Default nominal strains at the end, per material (Plate::end_strain).
constexpr double kSofteningEndStrain = 0.02;
constexpr double kViscoplasticEndStrain = 0.2;
/// Points above this fraction of the band point's ε̄ form the band core of the angle fit.
constexpr double kBandFloor = 0.5;
/// The Eulerian oscillation "grows" when its envelope at least doubles over the softening
/// range; the Lagrangian one is "slight at most" when it does not double.
constexpr double kGrowFactor = 2.0;
/// Band angle to the compression axis counted as the slip lines' 45°.
constexpr double kAngleTolerance = 10.0;

/// A material whose yield stress is lowered by `depth` (relative) at the integration points
/// within `radius` of `centre`: the weak spot that triggers the band. It writes the wrapped
/// material's history slot "yield_factor_minus_1" (σ_Y0 · (1 + slot), σ0 of j2-viscoplastic)
/// at t = 0 and otherwise passes every call through (with the step's dt).
class WeakSpot final : public Material {
 public:
  WeakSpot(std::shared_ptr<const Material> inner, Eigen::MatrixXd points, Eigen::Vector2d centre,
           double radius, double depth)
      : inner_(std::move(inner)), points_(std::move(points)), centre_(centre), radius_(radius),
        depth_(depth) {
    const auto names = inner_->state_names(2);
    const auto it = std::find(names.begin(), names.end(), "yield_factor_minus_1");
    if (it == names.end())
      throw InputError(fmt::format("compressed-plate: imperfection=spot lowers σ_Y0 through the "
                                   "material's history slot yield_factor_minus_1, which '{}' does "
                                   "not have; use imperfection=random",
                                   inner_->description(2)));
    slot_ = static_cast<int>(it - names.begin());
  }
  int state_size(int dim) const override { return inner_->state_size(dim); }
  std::vector<std::string> state_names(int dim) const override { return inner_->state_names(dim); }
  void initial_state(int dim, int n, double* state) const override {
    inner_->initial_state(dim, n, state);
    if (n != points_.cols())
      throw std::logic_error("compressed-plate: the weak spot's points are not the engine's");
    const long ns = inner_->state_size(dim);
    for (int q = 0; q < n; ++q)
      if ((points_.col(q) - centre_).norm() <= radius_) {
        double& f = state[ns * q + slot_];
        f = (1 + f) * (1 - depth_) - 1;
      }
  }
  void first_piola(int dim, int n, const double* F, double* P, double* state) const override {
    inner_->first_piola(dim, n, F, P, state);
  }
  void first_piola(int dim, int n, const double* F, double* P, double* state,
                   double dt) const override {
    inner_->first_piola(dim, n, F, P, state, dt);
  }
  bool rate_dependent() const override { return inner_->rate_dependent(); }
  double wave_speed(int dim, double density) const override {
    return inner_->wave_speed(dim, density);
  }
  std::string description(int dim) const override {
    return fmt::format("{}, σ_Y0 lowered by {:g} % within r = {:g} mm of the centre",
                       inner_->description(dim), depth_ * 100, radius_ * 1e3);
  }

 private:
  std::shared_ptr<const Material> inner_;
  Eigen::MatrixXd points_;
  Eigen::Vector2d centre_;
  double radius_, depth_;
  int slot_ = 0;
};

/// σ̄ and ε̄ at every integration point, sampled every `stride` steps; when full it keeps
/// every other sample and doubles the stride, so memory stays bounded at any size.
struct StressStrainRecord {
  int points = 0;
  std::size_t capacity = 0;
  long stride = 1, calls = 0;
  std::vector<double> strain;  ///< nominal strain of each sample
  std::vector<float> stress, plastic;  ///< sample-major: points values per sample

  /// Counts a step; true when this one is to be sampled.
  bool due() { return calls++ % stride == 0; }
  void add(double nominal, const Eigen::MatrixXd& sigma, const Eigen::VectorXd& ebar) {
    strain.push_back(nominal);
    for (int q = 0; q < points; ++q) {
      // σ̄ = √3 τ_max: the von Mises stress when σzz is the in-plane mean, as in plastic
      // plane-strain flow; it needs only the in-plane Cauchy stress (column-major 2×2).
      const double half_diff = 0.5 * (sigma(0, q) - sigma(3, q));
      stress.push_back(static_cast<float>(std::sqrt(3.0) * std::hypot(half_diff, sigma(1, q))));
      plastic.push_back(ebar.size() == points ? static_cast<float>(ebar[q]) : 0.0f);
    }
    if (strain.size() < capacity) return;
    const std::size_t kept = (strain.size() + 1) / 2;
    for (std::size_t k = 0; k < kept; ++k) {
      strain[k] = strain[2 * k];
      std::copy_n(stress.begin() + 2 * k * points, points, stress.begin() + k * points);
      std::copy_n(plastic.begin() + 2 * k * points, points, plastic.begin() + k * points);
    }
    strain.resize(kept);
    stress.resize(kept * points);
    plastic.resize(kept * points);
    stride *= 2;
  }
};

class Plate final : public TransientProblem {
 public:
  explicit Plate(const Params& p) : p_(p) {
    material_ = p.text("material");
    imperfection_ = p.text("imperfection");
    // The schema refuses 0, negative and NaN values of the positive parameters; these are
    // the other ends, where the run stops being the problem.
    if (!(p.number("end_strain") >= 0 && p.number("end_strain") <= 0.5))
      throw InputError(fmt::format("compressed-plate: end_strain = {} is outside [0, 0.5] (0: "
                                   "the material's own; above 0.5 the plate is flattened to half "
                                   "its height); give e.g. 0.02",
                                   p.number("end_strain")));
    if (!(p.number("velocity") <= 1000))
      throw InputError(fmt::format("compressed-plate: velocity = {} m/s is above 1000 m/s (a "
                                   "shock, not a compression); give e.g. 10",
                                   p.number("velocity")));
    if (!(p.number("imperfection_depth") < 1))
      throw InputError(fmt::format("compressed-plate: imperfection_depth = {} must be below 1 "
                                   "(a relative reduction of σ_Y0); give e.g. 0.05",
                                   p.number("imperfection_depth")));
    if (!(p.number("imperfection_radius") <= 0.5))
      throw InputError(fmt::format("compressed-plate: imperfection_radius = {} must be at most "
                                   "0.5 (of the side L); give e.g. 0.05",
                                   p.number("imperfection_radius")));
    // j2-softening's E = 2e11, ν = 0.3: the radial return needs 3μ + H > 0.
    constexpr double kThreeMu = 3 * 2e11 / (2 * 1.3);
    if (!(p.number("hardening") < 0) || !(p.number("hardening") > -kThreeMu))
      throw InputError(fmt::format("compressed-plate: hardening = {} must be negative and above "
                                   "−3μ = −2.3e11 (material=j2-softening softens linearly); give "
                                   "e.g. -1e9",
                                   p.number("hardening")));
    if (!(p.number("yield") < 1e12))
      throw InputError(fmt::format("compressed-plate: yield = {} Pa is above 1e12; give σ_Y0 in "
                                   "Pa, e.g. 2e8",
                                   p.number("yield")));
  }

  Domain domain() const override {
    return Domain::rectangle(-kSide / 2, -kSide / 2, kSide / 2, kSide / 2);
  }
  std::string resolution_name() const override { return "particles per side"; }
  int components() const override { return 2; }

  std::vector<int> resolutions(Level level) const override {
    // 001 uses 250,000 particles: 501 per side.
    if (level == Level::full) return {41, 101, 251, 501};
    if (level == Level::standard) return {41, 101};
    return {41};
  }

  Params analysis_defaults(const std::string& analysis) const override {
    Params p;
    if (analysis != "transient") return p;
    p.set("safety", 0.5);
    p.set("frames", 8);
    return p;
  }

  ParticleSet particles(int nodes, double perturbation) const override {
    if (nodes < 5 || nodes > 5000)
      throw InputError(fmt::format("compressed-plate: {} particles per side is outside [5, 5000]; "
                                   "give e.g. 41",
                                   nodes));
    return rectangle_lattice(domain(), nodes, nodes, Placement::boundary, perturbation);
  }

  TransientDefinition define(const Discretization& d, const TransientInputs& in) const override;
  std::vector<Finding> findings() const override;
  std::vector<std::string> published_notes() const override;
  std::vector<std::string> comparison_headlines() const override {
    return {"unstable at (nominal strain)", "band angle (deg)", "band families",
            "max plastic strain", "softening from (nominal strain)", "oscillation growth rate",
            "oscillation growth factor", "oscillation amplitude ratio", "min det F"};
  }

 private:
  std::shared_ptr<const Material> material(const MaterialRegistry& m,
                                           const Eigen::MatrixXd& points) const;
  /// The nominal strain at the end: end_strain, or the material's own when it is 0 — the
  /// linear softening's band has lost most of its strength by 0.02; Needleman's law peaks
  /// near ε̄ = 0.2 in the band (eps1 = 0.436) and needs the plate compressed further.
  double end_strain() const {
    if (p_.number("end_strain") > 0) return p_.number("end_strain");
    return material_ == "viscoplastic" ? kViscoplasticEndStrain : kSofteningEndStrain;
  }
  double end_time() const { return end_strain() * kSide / p_.number("velocity"); }

  Params p_;
  std::string material_, imperfection_;
};

std::shared_ptr<const Material> Plate::material(const MaterialRegistry& m,
                                                const Eigen::MatrixXd& points) const {
  const double depth = p_.number("imperfection_depth");
  std::shared_ptr<const Material> base;
  if (material_ == "viscoplastic") {
    if (!m.contains("j2-viscoplastic"))
      throw InputError("compressed-plate: material=viscoplastic needs the material "
                       "'j2-viscoplastic' (Needleman 1989), which is not registered in this "
                       "build; use material=j2-softening");
    Params mp;
    if (imperfection_ == "random") mp.set("imperfection", depth);
    base = m.create("j2-viscoplastic", mp);
  } else {
    Params mp;
    mp.set("E", 2e11);
    mp.set("nu", 0.3);
    mp.set("yield", p_.number("yield"));
    mp.set("hardening", p_.number("hardening"));
    mp.set("imperfection", imperfection_ == "random" ? depth : 0.0);
    mp.set("seed", static_cast<double>(p_.integer("seed")));
    base = m.create("j2-jaumann", mp);
  }
  if (imperfection_ != "spot") return base;
  return std::make_shared<WeakSpot>(base, points, Eigen::Vector2d::Zero(),
                                    p_.number("imperfection_radius") * kSide, depth);
}

TransientDefinition Plate::define(const Discretization& d, const TransientInputs& in) const {
  const ParticleSet& ps = d.particles;
  const int n = ps.size();
  const double V = p_.number("velocity"), L = kSide;
  TransientDefinition def;
  DynamicsModel& model = def.model;
  model.material = material(in.materials, d.quadrature.points);
  model.density = kDensity;
  model.mass = lumped_masses(ps, kDensity, MassLumping::volume);
  // Platens: y velocities ∓V/2 on the top and bottom rows, x free (shear-free, as Needleman
  // 1989's block ends), x held only at the middle particle of each row (the plate's axis of
  // symmetry) so the plate cannot drift sideways.
  std::vector<int> top, bottom;
  for (int I = 0; I < n; ++I) {
    if (ps.sides[I] & Side::top) top.push_back(I);
    if (ps.sides[I] & Side::bottom) bottom.push_back(I);
  }
  if (top.empty() || bottom.empty())
    throw InputError("compressed-plate: the particle set has no top or bottom row");
  auto middle = [&](const std::vector<int>& row) {
    return *std::min_element(row.begin(), row.end(), [&](int a, int b) {
      return std::abs(ps.x(0, a)) < std::abs(ps.x(0, b));
    });
  };
  for (int I : top) model.prescribed.push_back({I, 1, -V / 2});
  for (int I : bottom) model.prescribed.push_back({I, 1, V / 2});
  if (p_.text("platens") == "sticking") {
    for (int I : top) model.prescribed.push_back({I, 0, 0.0});
    for (int I : bottom) model.prescribed.push_back({I, 0, 0.0});
  } else {
    model.prescribed.push_back({middle(top), 0, 0.0});
    model.prescribed.push_back({middle(bottom), 0, 0.0});
  }
  // No shock at t = 0: the plate starts with the velocity field of uniform compression,
  // v_y = −ε̇ y, and the lateral expansion of the elastic plane-strain plate with free sides,
  // v_x = ν/(1 − ν) ε̇ x (ν = 0.3), which the platens' constant velocity then sustains.
  const double rate = V / L, lateral = 0.3 / 0.7;
  def.initial_velocity.resize(2, n);
  for (int I = 0; I < n; ++I) {
    def.initial_velocity(0, I) = lateral * rate * ps.x(0, I);
    def.initial_velocity(1, I) = -rate * ps.x(1, I);
  }
  def.end_time = end_time();
  def.checkpoints = {def.end_time};
  def.label = fmt::format("compressed-plate {}", material_);
  def.notes = fmt::format("{} platens closing at {:g} m/s, imperfection {}",
                          p_.text("platens"), V, imperfection_);

  const Eigen::MatrixXd Xq = d.quadrature.points;
  const int nq = static_cast<int>(Xq.cols());
  auto record = std::make_shared<StressStrainRecord>();
  record->points = nq;
  record->capacity =
      static_cast<std::size_t>(std::max(64.0, kRecordValues / std::max(nq, 1)));
  struct Track {
    double min_jacobian = INFINITY;
    int min_neighbours = std::numeric_limits<int>::max();
    /// The run has blown up (a point inverted or a particle passed the speed bound): it stops,
    /// and the band and the stress–strain record are those at the blow-up.
    bool blown = false;
    double peak_force = 0, strain_at_peak = NAN;
    double last_frame_time = NAN;
    Eigen::VectorXd last_frame_ebar;
    /// Where (reference position) the fastest particle was when the speed bound was passed.
    Eigen::Vector2d blow_up_at{NAN, NAN};
  };
  auto track = std::make_shared<Track>();
  const double v_bound = kSpeedBound * V;
  const bool has_rate = [&] {
    const auto names = model.material->state_names(2);
    return std::find(names.begin(), names.end(), "plastic_strain_rate") != names.end();
  }();

  // The platen force per unit thickness from the whole plate: in a quasi-static compression
  // every horizontal section carries it, so F = −∫σyy da / H with H = L − V t the current
  // height (∫σ da = ∫τ dA₀ ≈ Σ w₀ σ, as J stays within the elastic volume change of 1). The
  // boundary rows' own stresses, the least accurate of the nodal rules, do not enter.
  const Eigen::VectorXd w0 = d.quadrature.weights;
  auto platen_force = [w0, V, L](const ExplicitDynamics& sim) {
    const Eigen::MatrixXd s = sim.point_cauchy_stress();
    return -s.row(3).dot(w0) / (L - V * sim.time());
  };

  def.probe_names = {"nominal strain", "platen force (N/m)", "max plastic strain"};
  def.probes = [=](const ExplicitDynamics& sim) {
    const Eigen::VectorXd e = sim.point_state("plastic_strain");
    return std::vector<double>{sim.time() * V / L, platen_force(sim),
                               e.size() > 0 ? e.maxCoeff() : 0.0};
  };

  def.unstable = [=](const ExplicitDynamics& sim) {
    const double jmin = sim.min_jacobian();
    track->min_jacobian = std::min(track->min_jacobian, jmin);
    if (!(jmin > 0)) {
      track->blown = true;
      return fmt::format("an integration point inverted (det F = {:.3g}) at nominal strain "
                         "{:.4f}",
                         jmin, sim.time() * V / L);
    }
    Eigen::Index fastest = 0;
    const double vmax = sim.particle_velocity().colwise().norm().maxCoeff(&fastest);
    if (!(vmax <= v_bound)) {
      track->blown = true;
      track->blow_up_at = ps.x.col(fastest);
      return fmt::format("a particle moves at {:.3g} m/s, above {:g} × the platens' closing "
                         "speed {:g} m/s, at nominal strain {:.4f}",
                         vmax, kSpeedBound, V, sim.time() * V / L);
    }
    return std::string();
  };

  def.stop = [=](const ExplicitDynamics& sim) {
    track->min_neighbours = std::min(track->min_neighbours, sim.min_neighbours());
    const double nominal = sim.time() * V / L;
    if (track->blown) return true;
    if (!record->due()) return false;
    const Eigen::MatrixXd sigma = sim.point_cauchy_stress();
    if (!sigma.allFinite()) return false;
    record->add(nominal, sigma, sim.point_state("plastic_strain"));
    const double f = platen_force(sim);
    if (f > track->peak_force) {
      track->peak_force = f;
      track->strain_at_peak = nominal;
    }
    return false;
  };

  def.frame_data = [=](const ExplicitDynamics& sim,
                       std::vector<std::pair<std::string, Eigen::MatrixXd>>& out) {
    const std::vector<int>& near = sim.particle_points();
    const Eigen::VectorXd e = sim.point_state("plastic_strain");
    if (e.size() == 0) return;
    Eigen::MatrixXd ebar(1, n), rate_out(1, n);
    const Eigen::VectorXd r = has_rate ? sim.point_state("plastic_strain_rate") : Eigen::VectorXd();
    for (int I = 0; I < n; ++I) {
      ebar(0, I) = e[near[I]];
      // Without the material's own rate: the mean rate since the previous frame.
      if (has_rate)
        rate_out(0, I) = r[near[I]];
      else if (track->last_frame_ebar.size() == e.size() && sim.time() > track->last_frame_time)
        rate_out(0, I) = (e[near[I]] - track->last_frame_ebar[near[I]]) /
                         (sim.time() - track->last_frame_time);
      else
        rate_out(0, I) = 0;
    }
    track->last_frame_ebar = e;
    track->last_frame_time = sim.time();
    out.emplace_back("plastic strain", std::move(ebar));
    out.emplace_back("plastic strain rate (1/s)", std::move(rate_out));
  };

  const int side = ps.lattice[0] > 0 ? ps.lattice[0] : static_cast<int>(std::sqrt(n));
  const std::string frame = in.dynamics.text("frame");
  const double end_strain = this->end_strain();
  const double spot_radius = imperfection_ == "spot" ? p_.number("imperfection_radius") * L : 0.0;
  def.finish = [=](const ExplicitDynamics& sim, const TransientOutcome& out,
                   TransientMeasures& m) {
    m.headline["unstable"] = out.unstable ? 1.0 : 0.0;
    m.headline["unstable at (nominal strain)"] = out.unstable ? out.unstable_time * V / L : NAN;
    m.headline["blow-up particle x (mm)"] = track->blow_up_at[0] * 1e3;
    m.headline["blow-up particle y (mm)"] = track->blow_up_at[1] * 1e3;
    m.headline["min det F"] = track->min_jacobian;
    m.headline["min neighbours"] = track->min_neighbours;
    m.headline["peak platen force (N/m)"] = track->peak_force;
    m.headline["nominal strain at peak force"] = track->strain_at_peak;
    m.headline["nominal strain reached"] = sim.time() * V / L;

    // The band: the last recorded ε̄ (the engine's may be non-finite after a blow-up).
    const std::size_t samples = record->strain.size();
    if (samples == 0) return;
    Eigen::VectorXd ebar(nq);
    for (int q = 0; q < nq; ++q) ebar[q] = record->plastic[(samples - 1) * nq + q];
    m.headline["max plastic strain"] = ebar.maxCoeff();
    // The band point: the largest ε̄ in the central half of the plate (|x|, |y| ≤ L/4) outside
    // the weak spot, a point in the middle of a band (001 Fig. 15); the platens' corners,
    // where the bands end, concentrate far more strain and are not what 001 plots.
    int q_band = -1;
    for (int q = 0; q < nq; ++q) {
      const double r = Xq.col(q).norm();
      if (Xq.col(q).cwiseAbs().maxCoeff() > L / 4 + 1e-12 * L || r <= spot_radius) continue;
      if (q_band < 0 || ebar[q] > ebar[q_band]) q_band = q;
    }
    if (q_band < 0) return;
    // The fit weighs ε̄ capped at the band point's value, so the corners do not dominate it.
    const Eigen::VectorXd capped_ebar = ebar.cwiseMin(ebar[q_band]);
    const PlateBandFit fit = fit_band_angles(Xq, capped_ebar, side, kBandFloor);
    m.headline["band angle (deg)"] = fit.angle;
    m.headline["band angle + (deg)"] = fit.angle_plus;
    m.headline["band angle − (deg)"] = fit.angle_minus;
    m.headline["band strength +"] = fit.strength_plus;
    m.headline["band strength −"] = fit.strength_minus;
    m.headline["band families"] = fit.families;

    std::vector<double> eps(samples), sig(samples), ep(samples);
    for (std::size_t k = 0; k < samples; ++k) {
      eps[k] = record->strain[k];
      sig[k] = record->stress[k * nq + q_band];
      ep[k] = record->plastic[k * nq + q_band];
    }
    m.headline["band point plastic strain"] = ep.back();
    m.headline["band point x (mm)"] = Xq(0, q_band) * 1e3;
    m.headline["band point y (mm)"] = Xq(1, q_band) * 1e3;
    m.headline["stress-strain samples"] = static_cast<double>(samples);
    const int window = std::max(
        5, static_cast<int>(std::lround(kTrendWindow * end_strain / (eps.back() / samples))) | 1);
    const std::vector<double> trend = moving_average(sig, window);
    const std::size_t peak = std::max_element(trend.begin(), trend.end()) - trend.begin();
    m.headline["band point peak stress (Pa)"] = trend[peak];
    m.headline["softening from (nominal strain)"] = eps[peak];
    // The softening range: from the trend's peak until it falls below kSpentStrength of it
    // (then the band has no strength left and what remains is round-off).
    std::size_t spent = peak;
    while (spent < samples && trend[spent] >= kSpentStrength * trend[peak]) ++spent;
    m.headline["softening to (nominal strain)"] = eps[std::min(spent, samples - 1)];
    const std::vector<double> t_soft(eps.begin() + peak, eps.begin() + spent),
        y_soft(sig.begin() + peak, sig.begin() + spent);
    const OscillationFit osc =
        oscillation_growth(t_soft, y_soft, window, kOscillationFloor * trend[peak]);
    m.headline["oscillation growth rate"] = osc.growth_rate;
    m.headline["oscillation growth factor"] = osc.growth_factor;
    m.headline["oscillation amplitude ratio"] = osc.amplitude_ratio;
    m.headline["oscillation half-periods"] = osc.half_periods;
    m.headline["oscillation relative amplitude"] = osc.relative_amplitude;

    const std::string who = frame + " kernel";
    m.profiles.push_back({"band point: stress–strain curve (001 Fig. 15)",
                          "effective plastic strain ε̄", "σ̄ = √3 τ_max (Pa)", {who}, {ep}, {sig}});
    m.profiles.push_back({"band point: σ̄ against the nominal strain", "nominal strain V t / L",
                          "σ̄ = √3 τ_max (Pa)", {who, who + ", trend (moving average)"}, {eps, eps},
                          {sig, trend}});
  };
  return def;
}

}  // namespace

std::vector<Finding> Plate::findings() const {
  std::vector<Finding> f;
  f.push_back(
      {"001 §9.4, Fig. 16",
       "compressed plate (Needleman viscoplasticity): the shear band agrees with the references "
       "(Needleman 1989; Belytschko, Chiang & Plaskacz 1994): bands at about ±45° to the "
       "compression axis",
       fmt::format("every study, either kernel: the stronger band family's angle to the "
                   "compression axis within 45° ± {:g}° (slip lines of a von Mises material in "
                   "plane strain, Hill 1950 ch. VI; Radon fit of ε̄ above {:g} × the band point's, "
                   "problems/plate_measures.hpp), at the end or, for a run that blew up, at the "
                   "blow-up (the band had formed by then: it is listed with its nominal strain)",
                   kAngleTolerance, kBandFloor),
       [](const std::vector<StudySummary>& all) {
         Tally t;
         for (const char* frame : {"lagrangian", "eulerian"})
           for (const auto* s : finding::studies_in_frame(all, frame)) {
             const double a = last(*s, "band angle (deg)");
             const bool blew = last(*s, "unstable") == 1;
             t.add_headlines(*s, std::abs(a - 45) <= kAngleTolerance,
                   fmt::format("band at {}° ({} families){}", fmt_or_dash(a),
                               fmt_or_dash(last(*s, "band families"), "{:.0f}"),
                               blew ? fmt::format(", blew up at nominal strain {}",
                                                  fmt_or_dash(last(*s, "unstable at (nominal "
                                                                       "strain)")))
                                    : ""),
                   {"band angle (deg)"});
           }
         return t.verdict("no compressed-plate study");
       },
       "band-angle"});
  f.push_back(
      {"001 §9.4, Fig. 15",
       "compressed plate: at a particle in the band the Eulerian kernel's stress–strain curve "
       "oscillates with growing amplitude in the softening range; the Lagrangian kernel with "
       "stress points does not (slightly increasing oscillations at most)",
       fmt::format("material=viscoplastic (001's law), for each method run with both kernels at "
                   "the same resolution and method parameters: the Eulerian oscillation grows — its envelope at least doubles "
                   "over the softening range (from the band point's peak σ̄ until it has fallen "
                   "to {3:g} of it; fitted growth factor ≥ {0:g}), or the run blows up "
                   "after softening began with its fastest particle in the central half of the "
                   "plate, where the band point is (unbounded growth; a blow-up at a platen corner "
                   "does not count) — and the Lagrangian run reaches the "
                   "end with a growth factor below {0:g} (\"slight\": it does not double) or no "
                   "oscillation above {2:g} of the band point's peak stress. "
                   "Envelope: half-period peaks of σ̄ = √3 τ_max about its moving average over "
                   "{1:g} of the run's nominal strain, at the point of largest ε̄ in the central "
                   "half of the plate outside the weak spot",
                   kGrowFactor, kTrendWindow, kOscillationFloor, kSpentStrength),
       [](const std::vector<StudySummary>& all) {
         Tally pairs;
         for (const auto* l : finding::studies_in_frame(all, "lagrangian"))
           for (const auto* e : finding::studies_in_frame(all, "eulerian", l->method)) {
             if (l->resolved.to_string() != e->resolved.to_string() ||
                 l->finest_nodes != e->finest_nodes ||
                 l->problem_resolved.text("material") != "viscoplastic" ||
                 e->problem_resolved.text("material") != "viscoplastic")
               continue;
             const double gl = last(*l, "oscillation growth factor");
             const double ge = last(*e, "oscillation growth factor");
             const bool e_blew = last(*e, "unstable") == 1;
             const double e_at = last(*e, "unstable at (nominal strain)");
             const double e_soft = last(*e, "softening from (nominal strain)");
             // A blow-up counts as unbounded growth only where the band point is measured
             // (the central half): a platen corner squeezed out is another failure, not the
             // band point's oscillation of 001 Fig. 15.
             const double bx = last(*e, "blow-up particle x (mm)"),
                          by = last(*e, "blow-up particle y (mm)");
             const double quarter = kSide * 1e3 / 4;
             const bool e_blew_in_band = e_blew && std::isfinite(e_soft) && e_at >= e_soft &&
                                         std::abs(bx) <= quarter && std::abs(by) <= quarter;
             const bool e_grows = ge >= kGrowFactor || e_blew_in_band;
             // No oscillation above the floor (fewer than 4 half-periods) is "slight at most".
             const bool l_slight = last(*l, "unstable") == 0 &&
                                   (gl < kGrowFactor || last(*l, "oscillation half-periods") < 4);
             pairs.add_numbers(*e, e_grows && l_slight,
                       fmt::format("Eulerian growth factor {} (rate {} per unit nominal strain){}; "
                                   "Lagrangian {} (rate {})",
                                   fmt_or_dash(ge), fmt_or_dash(last(*e, "oscillation growth rate")),
                                   e_blew ? fmt::format(", blew up at nominal strain {} (softening "
                                                        "from {}; fastest particle at ({}, {}) mm)",
                                                        fmt_or_dash(e_at), fmt_or_dash(e_soft),
                                                        fmt_or_dash(last(*e, "blow-up particle x (mm)")),
                                                        fmt_or_dash(last(*e, "blow-up particle y (mm)")))
                                          : "",
                                   fmt_or_dash(gl), fmt_or_dash(last(*l, "oscillation growth rate"))),
                       {headline_per_resolution(*e, "oscillation growth factor"),
                        headline_per_resolution(*l, "oscillation growth factor")});
           }
         return pairs.verdict(
             "needs a Lagrangian and an Eulerian study of one method with material=viscoplastic");
       },
       "eulerian-oscillations-grow"});
  return f;
}

std::vector<std::string> Plate::published_notes() const {
  const Needleman1989Parameters t = needleman_1989_parameters();
  std::string table = fmt::format(
      "material=viscoplastic (the default): j2-viscoplastic, Needleman's (1989) rate-dependent "
      "J2 flow, with these values ({} softening: {}):\n\n| parameter | value | unit | source "
      "|\n| :-- | --: | :-- | :-- |\n",
      t.softening_law, t.softening_source);
  for (const SourcedParameter& e : t.entries)
    table += fmt::format("| {} | {:g} | {} | {} |\n", e.name, e.value, e.unit, e.source);
  return {
      "001 §9.4 gives the problem in words only: a square plate under compression, plane strain, "
      "Needleman's viscoplastic model (1989) with the parameters of Belytschko, Chiang & "
      "Plaskacz (1994) and its Fig. 14 (missing from our copy), KBM with stress points and "
      "250,000 particles; Fig. 15 shows a band particle's stress–strain curve, Fig. 16 the band.",
      fmt::format(
          "Our choices: side L = {:g} mm, ρ = {:g} kg/m³; platens closing at V = velocity "
          "(default 10 m/s, ε̇ = V/L = 1000/s) to end_strain (default: 0.02 for j2-softening, 0.2 for "
          "viscoplastic), shear-free (x free; "
          "x held only at the middle particle of each platen against drift) as the ends of "
          "Needleman's block (platens=sticking holds x on the whole loaded rows instead), "
          "lateral faces free; the plate starts with the velocity field of "
          "uniform compression (v_y = −ε̇ y, v_x = ν/(1−ν) ε̇ x) so there is no shock at t = 0. "
          "The band is triggered by a weak spot at the centre (imperfection=spot: σ_Y0 lowered by "
          "imperfection_depth = 5 % within imperfection_radius = 0.05 L), the full-plate form of "
          "an imperfection at the specimen centre (a quarter model's corner); "
          "imperfection=random uses the material's seeded per-point variation instead.",
          kSide * 1e3, kDensity),
      table,
      "material=j2-softening (the alternative to Needleman's law): J2 with the Jaumann rate and "
      "linear softening: E = 2e11, ν = 0.3 of the steel ring (001 §9.5), σ_Y0 = 2e8 (000 §5.3), "
      "H = −E/200 = −1e9 (ours: the ring's −E/10 leaves a band with no strength at ε̄ = 0.01, "
      "nominal strain 0.003, and the platen corners extrude; at −E/200 the band point softens "
      "over the whole run) — a stand-in with a softening branch, not Needleman's law.",
      fmt::format("Band angle: the slip lines of a rigid–perfectly plastic von Mises material in "
                  "plane strain bisect the principal stress directions (Hill 1950, The "
                  "Mathematical Theory of Plasticity, ch. VI), so a band makes 45° with the "
                  "compression axis; we accept 45° ± {:g}°.",
                  kAngleTolerance),
  };
}

void register_plate(ProblemRegistry& r) {
  r.add("compressed-plate",
        "square plate (10 mm) in plane strain compressed by shear-free platens at a constant "
        "nominal rate, softening J2 (Needleman 1989 viscoplastic or linear softening), a weak "
        "spot at the centre: the shear band's angle and the band particle's stress-strain "
        "oscillation, Lagrangian against Eulerian kernel (001 §9.4)",
        {ParamSpec::choice("material", "viscoplastic", {"viscoplastic", "j2-softening"},
                           "viscoplastic: Needleman 1989 (j2-viscoplastic); j2-softening: "
                           "j2-jaumann with linear softening"),
         ParamSpec::choice("platens", "shear-free", {"shear-free", "sticking"},
                           "shear-free: x free on the loaded rows (Needleman 1989's block ends); "
                           "sticking: x held on the loaded rows (no slip on the platens)"),
         ParamSpec::positive("velocity", 10.0, "closing speed V of the platens (m/s; each moves "
                                               "V/2), at most 1000"),
         ParamSpec::number("end_strain", 0.0, "nominal strain V t / L at the end (≤ 0.5; 0: 0.02 "
                                              "for j2-softening, 0.2 for viscoplastic)"),
         ParamSpec::choice("imperfection", "spot", {"spot", "random", "none"},
                           "spot: σ_Y0 lowered in a disc at the centre; random: the material's "
                           "seeded per-point variation of that depth; none"),
         ParamSpec::positive("imperfection_depth", 0.05,
                             "relative reduction of σ_Y0 in the spot (random: the amplitude), < 1"),
         ParamSpec::positive("imperfection_radius", 0.05, "radius of the spot over the side L, ≤ 0.5"),
         ParamSpec::positive("yield", 2e8, "σ_Y0 of material=j2-softening (Pa; 000 §5.3)"),
         ParamSpec::number("hardening", -1e9, "H of material=j2-softening (Pa, < 0; −E/200: "
                                              "σ_Y reaches 0 at ε̄ = 0.2)"),
         capped(ParamSpec::count("seed", 1, 1, "seed of imperfection=random"), 2e9)},
        [](const Params& p) { return std::make_unique<Plate>(p); });
}

}  // namespace mfv
