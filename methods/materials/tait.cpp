/// `tait`: water as a weakly compressible fluid, the equation of state of 001 eq 77,
///   p = B ((ρ/ρ0)^γ − 1),   ρ = ρ_ref / det F,   σ = −p I,   P = J σ F⁻ᵀ = −p cof F,
/// with no deviatoric stress. The density comes from det F (the continuity equation
/// integrated exactly along the motion), from a per-point reference density ρ_ref that a
/// problem may set (a hydrostatic column is compressed at t = 0: ρ_ref from the equation of
/// state and ρ0 g (H − y)). Viscosity is the engine's (artificial, at the integration points).
/// cof F is written out, never F⁻¹: a fluid's F shears without bound while det F stays near 1.
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "methods/materials/material.hpp"

namespace mfv {

namespace {

class TaitFluid final : public Material {
 public:
  TaitFluid(double rho0, double gamma, double B) : rho0_(rho0), gamma_(gamma), B_(B) {}

  /// Slots: the reference density ρ_ref (ρ0 unless the problem sets it), and the density
  /// ρ_ref / det F of the last committed evaluation (for outputs).
  int state_size(int) const override { return 2; }
  std::vector<std::string> state_names(int) const override {
    return {"reference_density", "density"};
  }
  void initial_state(int, int n, double* state) const override {
    for (int q = 0; q < n; ++q) state[2 * q] = state[2 * q + 1] = rho0_;
  }

  void first_piola(int dim, int n, const double* F, double* P, double* state) const override {
    const int dd = dim * dim;
    for (int q = 0; q < n; ++q) {
      const double* f = F + dd * q;
      double* p = P + dd * q;
      const double J = dim == 1 ? f[0] : f[0] * f[3] - f[1] * f[2];
      // An inverted point has no density: NaN makes the run's failure visible, never a zero.
      const double rho = J > 0 ? state[2 * q] / J : std::numeric_limits<double>::quiet_NaN();
      state[2 * q + 1] = rho;
      const double pressure = B_ * (std::pow(rho / rho0_, gamma_) - 1);
      if (dim == 1) {
        p[0] = -pressure;
        continue;
      }
      // cof F (column-major f[0]=F11 f[1]=F21 f[2]=F12 f[3]=F22): [[F22, −F21], [−F12, F11]].
      p[0] = -pressure * f[3];
      p[1] = pressure * f[2];
      p[2] = pressure * f[1];
      p[3] = -pressure * f[0];
    }
  }

  /// c = √(dp/dρ) at ρ0 = √(γ B / ρ0) (57.4 m/s for 001's water); the engine's density is
  /// not used: the equation of state carries its own ρ0.
  double wave_speed(int, double) const override { return std::sqrt(gamma_ * B_ / rho0_); }

  std::string description(int) const override {
    return fmt::format("Tait fluid rho0={:g} gamma={:g} B={:g} (c0={:.4g})", rho0_, gamma_, B_,
                       wave_speed(2, rho0_));
  }

 private:
  double rho0_, gamma_, B_;
};

}  // namespace

void register_tait(MaterialRegistry& r) {
  r.add("tait",
        "Tait fluid (001 eq 77): p = B((rho/rho0)^gamma - 1), rho from det F, no deviatoric stress",
        {ParamSpec::positive("rho0", 1000.0, "reference density (kg/m^3; 001: 0.001 g/mm^3)"),
         ParamSpec::positive("gamma", 7.0, "exponent (001: 7)"),
         ParamSpec::positive("B", 4.704e5, "pressure constant (Pa; 001: 0.4704 MPa)")},
        [](const Params& p) -> std::unique_ptr<Material> {
          const double gamma = p.number("gamma");
          if (gamma < 1 || gamma > 20)
            throw InputError(fmt::format("material 'tait': gamma = {} is outside [1, 20]; water "
                                         "is 7",
                                         gamma));
          return std::make_unique<TaitFluid>(p.number("rho0"), gamma, p.number("B"));
        });
}

}  // namespace mfv
