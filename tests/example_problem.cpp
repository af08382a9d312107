/// Worked example of docs/architecture.md: a new transient problem in one file. A 1D bar
/// fixed at both ends, L = 1, E = ρ = 1 (c = 1), set moving in its first mode,
/// v(x, 0) = v0 sin(πx/L); the exact velocity is the standing wave v(x, t) = v0 sin(πx/L)
/// cos(πct/L). The problem only defines: particles, material, masses, supports, the initial
/// velocity, the end time, a checkpoint and what is measured there. The `transient` analysis
/// builds the engine, picks the step, runs the loop and reports it. It also declares the
/// example analysis `volume-check` (tests/example_analysis.cpp). In-tree, the file goes
/// in problems/ and `X(standing_wave)` in MFV_PROBLEMS of problems/register_all.cpp; the
/// tests pass it as an extension.
#include <cmath>
#include <numbers>

#include "problems/transient_problem.hpp"

namespace mfv {
namespace {

/// Small enough that St Venant–Kirchhoff is linear (its relative error ~2.4 v0/c = 2.4e-7),
/// large enough that F = I + ∇u keeps its digits (round-off ~1e-16 c/v0).
constexpr double kV0 = 1e-7;

class StandingWave final : public TransientProblem {
 public:
  explicit StandingWave(const Params& p) : periods_(p.number("periods")) {}

  Domain domain() const override { return Domain::interval(0, 1); }
  std::vector<std::string> analyses() const override { return {"transient", "volume-check"}; }
  std::vector<int> resolutions(Level) const override { return {21, 41}; }

  /// The exact velocity of the first mode at x, t.
  static double exact(double x, double t) {
    const double pi = std::numbers::pi;
    return kV0 * std::sin(pi * x) * std::cos(pi * t);
  }

  TransientDefinition define(const Discretization& d, const TransientInputs& in) const override {
    TransientDefinition def;
    Params material;
    material.set("E", 1.0);
    material.set("nu", 0.0);
    def.model.material = in.materials.create("svk", material);
    def.model.density = 1;
    def.model.mass = lumped_masses(d.particles, 1.0, MassLumping::volume);
    const int n = d.particles.size();
    def.model.prescribed = {{0, 0, 0.0}, {n - 1, 0, 0.0}};  // both ends fixed
    def.initial_velocity.resize(1, n);
    for (int I = 0; I < n; ++I) def.initial_velocity(0, I) = exact(d.particles.x(0, I), 0);
    def.end_time = 2 * periods_;  // the first mode's period is 2L/c = 2
    def.checkpoints = {def.end_time};
    def.label = "standing-wave";
    def.main_error = "relative L2 velocity error at the end time (dimensionless)";
    const ParticleSet X = d.particles;
    def.at_checkpoint = [X](const ExplicitDynamics& s, int, TransientMeasures& m) {
      const Eigen::MatrixXd v = s.particle_velocity();
      double num = 0, den = 0;
      for (int I = 0; I < X.size(); ++I) {
        const double e = exact(X.x(0, I), s.time());
        num += X.volume[I] * (v(0, I) - e) * (v(0, I) - e);
        den += X.volume[I] * e * e;
      }
      m.errors.l2 = std::sqrt(num);
      m.errors.l2_rel = std::sqrt(num / den);
      m.headline["velocity error"] = m.errors.l2_rel;
    };
    return def;
  }

 private:
  double periods_;
};

}  // namespace

void register_standing_wave(ProblemRegistry& r) {
  r.add("standing-wave",
        "1D bar fixed at both ends in its first mode, v = v0 sin(pi x) cos(pi t) (example)",
        {ParamSpec::positive("periods", 1.0, "run time in periods of the first mode")},
        [](const Params& p) { return std::make_unique<StandingWave>(p); });
}

}  // namespace mfv
