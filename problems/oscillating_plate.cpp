/// `oscillating-plate`: the cantilever plate set vibrating in its first bending mode, the
/// standard small-strain test of solid SPH (Gray, Monaghan & Swift 2001, CMAME 190, §6.1),
/// here for every 2D method: a plate of length L = 0.2 m and thickness H = 0.02 m (E = 2 MPa,
/// ν = 0.3975, ρ = 1000 kg/m³, plane strain) held in a clamp of `clamp` particle columns at
/// x < 0, given the velocity of the first mode of a clamped–free thin plate,
///   v_y(x) = V_f c₀ [M (cos kx − cosh kx) − N (sin kx − sinh kx)] / Q,
///   M = sin kL + sinh kL, N = cos kL + cosh kL, Q = 2 (cos kL sinh kL − sin kL cosh kL),
/// with kL = 1.875104 and c₀ = √(K/ρ) (GMS eqs 37–38), and measured against the thin-plate
/// frequency
///   ω² = E H² k⁴ / (12 ρ (1 − ν²))                                           (GMS eq 36).
/// The period is read from the tip's vertical displacement: the zero crossings of the centre-
/// line particle at x = L, fitted as t_k = t₀ + k T/2 by least squares. The thin-plate period
/// ignores shear and rotary inertia, which lengthen a plate with H/L = 0.1 by about 1–2 %, so
/// a suite band of 5 % is wide enough for the model and narrow enough for a method. Issue 27: KBM's published force (Shepard test gradients) makes
/// energy at free surfaces; `force=variational` is the energy-consistent form.
#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "methods/core/measurement_error.hpp"
#include "problems/transient_problem.hpp"

namespace mfv {

namespace {

constexpr double kLength = 0.2, kThickness = 0.02, kE = 2.0e6, kNu = 0.3975, kDensity = 1000;
constexpr double kKL = 1.875104068711961;  // first root of cos kL cosh kL = −1
constexpr const char* kPeriodRatio = "period / thin-plate period";

double bulk_modulus() { return kE / (3 * (1 - 2 * kNu)); }
/// The thin-plate (Euler–Bernoulli, plane strain) angular frequency of the first mode.
double thin_plate_omega() {
  const double k = kKL / kLength;
  return std::sqrt(kE * kThickness * kThickness * std::pow(k, 4) /
                   (12 * kDensity * (1 - kNu * kNu)));
}

/// The first clamped–free mode shape of GMS eq 38 (1 at the free end up to its sign; 0 and
/// zero slope at x = 0).
double mode_shape(double x) {
  const double k = kKL / kLength, kl = kKL;
  const double M = std::sin(kl) + std::sinh(kl), N = std::cos(kl) + std::cosh(kl);
  const double Q = 2 * (std::cos(kl) * std::sinh(kl) - std::sin(kl) * std::cosh(kl));
  return (M * (std::cos(k * x) - std::cosh(k * x)) - N * (std::sin(k * x) - std::sinh(k * x))) /
         Q;
}

/// T from the zero crossings t_k of the tip displacement, t_k = t₀ + k T/2 (least squares);
/// NaN with fewer than two.
double period_from_crossings(const std::vector<double>& t) {
  if (t.size() < 2) return NAN;
  const double n = static_cast<double>(t.size());
  double sk = 0, st = 0, skk = 0, skt = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    sk += k, st += t[k], skk += double(k) * k, skt += k * t[k];
  }
  const double slope = (n * skt - sk * st) / (n * skk - sk * sk);
  return 2 * slope;
}

class OscillatingPlate final : public TransientProblem {
 public:
  explicit OscillatingPlate(const Params& p)
      : vf_(p.number("vf")), clamp_(p.number("clamp")), periods_(p.number("periods")) {}

  /// The plate and its clamp, [−clamp, L] × [−H/2, H/2].
  Domain domain() const override {
    return Domain::rectangle(-clamp_, -0.5 * kThickness, kLength, 0.5 * kThickness);
  }
  int components() const override { return 2; }
  std::string resolution_name() const override { return "particles through the thickness"; }

  /// `nodes` particles through the thickness, Δ = H/(nodes − 1), 10 (nodes − 1) + 1 along
  /// the free length and clamp/Δ more columns at x < 0 (the clamp; a whole number of them).
  ParticleSet particles(int nodes, double perturbation) const override {
    if (nodes < 3 || nodes > 201)
      throw InputError(fmt::format("oscillating-plate: nodes = {} particles through the "
                                   "thickness must lie in 3..201",
                                   nodes));
    const double dx = kThickness / (nodes - 1);
    const double columns = clamp_ / dx;
    if (std::abs(columns - std::round(columns)) > 1e-9 || std::round(columns) < 1)
      throw InputError(fmt::format(
          "oscillating-plate: the clamp ({:g} m) is {:.4g} spacings at nodes = {}; it must be a "
          "whole number >= 1: use --problem-params clamp={:.12g} ({} spacings) at this "
          "resolution, or nodes = 4k + 1 (5, 9, 13, 17, 21) with the default 0.015 m",
          clamp_, columns, nodes, std::max(1.0, std::ceil(columns)) * dx,
          std::max(1.0, std::ceil(columns))));
    return rectangle_lattice(domain(), 10 * (nodes - 1) + 1 + std::lround(columns), nodes,
                             Placement::boundary, perturbation);
  }

  std::vector<int> resolutions(Level level) const override {
    switch (level) {
      case Level::quick: return {5};
      case Level::standard: return {5, 9, 13};
      case Level::full: return {5, 9, 13, 21};
    }
    return {};
  }

  Params analysis_defaults(const std::string& analysis) const override {
    Params p;
    if (analysis == "transient") {
      p.set("threads", 1.0);
      p.set("frames", 0.0);
    }
    return p;
  }

  TransientDefinition define(const Discretization& d, const TransientInputs& in) const override {
    Params mp;
    mp.set("E", kE);
    mp.set("nu", kNu);
    mp.set("plane", "strain");
    TransientDefinition def;
    DynamicsModel& model = def.model;
    model.material = in.materials.create("svk", mp);
    def.material_name = "svk";
    def.material_params = mp;
    model.density = kDensity;
    model.mass = lumped_masses(d.particles, kDensity, MassLumping::volume);
    const ParticleSet& X = d.particles;
    const int n = X.size();
    const double dx = X.spacing;
    // The clamp: both velocity components of the particles at x < 0 held at zero (GMS hold
    // their clamp particles fixed); the plate's root x = 0 is free to bend against them.
    int held = 0;
    for (int I = 0; I < n; ++I)
      if (X.x(0, I) < -0.5 * dx) {
        model.prescribed.push_back({I, 0, 0.0});
        model.prescribed.push_back({I, 1, 0.0});
        ++held;
      }
    if (held == 0)
      throw InputError("oscillating-plate: the clamp holds no particle; use clamp >= 1");
    const double c0 = std::sqrt(bulk_modulus() / kDensity);
    def.initial_velocity = Eigen::MatrixXd::Zero(2, n);
    for (int I = 0; I < n; ++I)
      if (X.x(0, I) >= -0.5 * dx) def.initial_velocity(1, I) = vf_ * c0 * mode_shape(X.x(0, I));
    // The tip: the particle nearest (L, 0).
    int tip = 0;
    for (int I = 0; I < n; ++I)
      if (std::hypot(X.x(0, I) - kLength, X.x(1, I)) <
          std::hypot(X.x(0, tip) - kLength, X.x(1, tip)))
        tip = I;
    const double T = 2 * M_PI / thin_plate_omega();
    def.end_time = periods_ * T;
    def.label = fmt::format("oscillating-plate {} n={}", in.method, in.nodes);
    def.notes = fmt::format("V_f = {:g}, clamp {:g} m ({} particles held)", vf_, clamp_, held);
    def.probe_names = {"tip u_y", "tip v_y"};
    def.probes = [tip](const ExplicitDynamics& s) {
      return std::vector<double>{s.particle_displacement()(1, tip), s.particle_velocity()(1, tip)};
    };
    // The tip's displacement after every step, for the period (finish).
    def.trace_names = {"tip u_y"};
    def.trace = [tip](const ExplicitDynamics& s) {
      return std::vector<double>{s.particle_displacement()(1, tip)};
    };
    def.finish = [T, this](const ExplicitDynamics&, const TransientOutcome& out,
                           TransientMeasures& m) {
      // The crossings of the tip displacement through zero, interpolated linearly in time,
      // with hysteresis: a crossing counts when the tip next reaches a quarter of its peak on
      // the other side, so a ripple of higher modes about zero is not read as a half period.
      double t_prev = 0, u_prev = 0, peak = 0, last_zero = 0;
      int side = 0;
      std::vector<double> crossings;
      for (std::size_t k = 0; k < out.trace.size(); ++k) {
        const double u = out.trace[k][0], t = out.trace_time[k];
        if (std::isfinite(u)) {
          peak = std::max(peak, std::abs(u));
          if (u * u_prev < 0) last_zero = t_prev + (t - t_prev) * u_prev / (u_prev - u);
          const int now = u > 0.25 * peak ? 1 : u < -0.25 * peak ? -1 : 0;
          if (now != 0 && now != side) {
            if (side != 0) crossings.push_back(last_zero);
            side = now;
          }
        }
        t_prev = t;
        u_prev = u;
      }
      // A stable run that did not cross zero twice measured no period: a failure with its
      // reason, never a pass with the period left blank.
      if (!out.unstable && crossings.size() < 2)
        throw MeasurementError(fmt::format(
            "oscillating-plate: the tip crossed zero {} time(s) in {:g} thin-plate periods; a "
            "period needs two crossings, so the plate did not oscillate in its first mode within "
            "the run (its period is above {:.3g} of the thin-plate one; raise periods)",
            crossings.size(), out.steps * out.dt / T, out.steps * out.dt / T));
      const double period = out.unstable ? NAN : period_from_crossings(crossings);
      m.headline["period (s)"] = period;
      m.headline["thin-plate period (s)"] = T;
      m.headline[kPeriodRatio] = period / T;
      m.headline["tip amplitude / thin-plate amplitude"] =
          peak / (vf_ * std::sqrt(bulk_modulus() / kDensity) *
                         std::abs(mode_shape(kLength)) / thin_plate_omega());
      m.headline["zero crossings"] = static_cast<double>(crossings.size());
    };
    return def;
  }

  std::vector<std::string> published_notes() const override {
    return {fmt::format(
        "Gray, Monaghan & Swift (2001) §6.1: a plate L = 0.2 m, H = 0.02 m, E = 2 MPa, nu = "
        "0.3975, rho = 1000, clamped at one end, started with the velocity of its first bending "
        "mode (V_f = 0.001 here, small against H/L so the response is linear). The thin-plate "
        "period 2 pi / omega, omega^2 = E H^2 k^4 / (12 rho (1 - nu^2)), kL = 1.875, is {:.5g} s; "
        "ours is read from the tip's zero crossings. Shear and rotary inertia make the plane-"
        "strain plate 1-2 % slower than the thin plate.",
        2 * M_PI / thin_plate_omega())};
  }

 private:
  double vf_;
  double clamp_;
  double periods_;
};

}  // namespace

void register_oscillating_plate(ProblemRegistry& r) {
  ParamSchema s{
      ParamSpec::positive("vf", 0.001,
                          "initial velocity amplitude over c0 = sqrt(K/rho) (GMS eq 37; 0.001 "
                          "gives a tip amplitude of 1 % of L)"),
      capped(ParamSpec::positive("clamp", 0.015,
                                 "length of the clamp at x < 0, m (its particles are held; a "
                                 "whole number of spacings, at least the support)"),
             0.2),
      capped(ParamSpec::positive("periods", 2.25,
                                 "simulated time in thin-plate periods (>= 1.1 for two zero "
                                 "crossings)"),
             100),
  };
  r.add("oscillating-plate",
        "plane-strain cantilever plate 0.2 x 0.02 m set vibrating in its first mode; period "
        "against the thin-plate period (Gray, Monaghan & Swift 2001)",
        s, [](const Params& p) { return std::make_unique<OscillatingPlate>(p); });
}

}  // namespace mfv
