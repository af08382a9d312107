/// `plastic-1d`: uniaxial elastic–plastic bar with linear isotropic hardening (004 III §6:
/// σ_y = 30,000 psi, E_p = E/4), small strain ε = F − 1, return mapping per step. E_p is the
/// tangent modulus of the plastic branch, so the plastic modulus is H = E E_p/(E − E_p).
#include <cmath>

#include <fmt/format.h>

#include "methods/materials/material.hpp"

namespace mfv {

namespace {

class Plastic1D final : public Material {
 public:
  Plastic1D(double E, double sigma_y, double Et) : E_(E), sy_(sigma_y), Et_(Et) {
    H_ = E * Et / (E - Et);
  }
  int state_size(int) const override { return 2; }  // plastic strain, accumulated |ε_p|

  void first_piola(int dim, int n, const double* F, double* P, double* state) const override {
    if (dim != 1)
      throw InputError("material 'plastic-1d' is uniaxial: use it on 1D problems only");
    for (int q = 0; q < n; ++q) {
      double& ep = state[2 * q];
      double& alpha = state[2 * q + 1];
      const double trial = E_ * (F[q] - 1 - ep);
      const double f = std::abs(trial) - (sy_ + H_ * alpha);
      if (f > 0) {
        const double dg = f / (E_ + H_);
        const double s = trial > 0 ? 1.0 : -1.0;
        ep += dg * s;
        alpha += dg;
        P[q] = trial - E_ * dg * s;
      } else {
        P[q] = trial;
      }
    }
  }

  double wave_speed(int, double density) const override { return std::sqrt(E_ / density); }

  std::string description(int) const override {
    return fmt::format("elastic-plastic E={:g} sigma_y={:g} E_p={:g} (H={:g}), small strain", E_,
                       sy_, Et_, H_);
  }

 private:
  double E_, sy_, Et_, H_;
};

}  // namespace

void register_plastic_1d(MaterialRegistry& r) {
  r.add("plastic-1d",
        "uniaxial elastic-plastic, linear isotropic hardening, small strain (004 III §6)",
        {ParamSpec::positive("E", 1.0, "Young's modulus"),
         ParamSpec::positive("sigma_y", 1.0, "initial yield stress"),
         ParamSpec::positive("Ep", 0.25, "tangent modulus of the plastic branch (< E)")},
        [](const Params& p) -> std::unique_ptr<Material> {
          if (p.number("Ep") >= p.number("E"))
            throw InputError(fmt::format("material 'plastic-1d': Ep = {} must be below E = {}",
                                         p.number("Ep"), p.number("E")));
          return std::make_unique<Plastic1D>(p.number("E"), p.number("sigma_y"), p.number("Ep"));
        });
}

}  // namespace mfv
